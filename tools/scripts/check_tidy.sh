#!/usr/bin/env bash
# clang-tidy (the repository's .clang-tidy) over the C++ sources changed since a base revision;
# any finding fails. Usage: tools/scripts/check_tidy.sh [BASE]
# The build's compiler flags are GCC's: -Werror (FLEETLOC_WERROR) and GCC-only warning options are
# neutralized for clang-tidy's clang front end, so only the checks' findings count.
#   BASE: a git revision; default $FLEETLOC_TIDY_BASE, else the recorded base in .ci/tidy_base
#   (the last commit whose sources were all tidy-checked, advanced after each landing whose CI
#   passed: docs/architecture.md, "Structure checks") when it is an ancestor of HEAD, else the
#   merge base with origin/main, else HEAD~1 (a clean clone's last commit). So CI checks every
#   commit of a landing, not only its last. Changed headers are checked through the sources that
#   include them. Needs build/compile_commands.json (cmake --preset release writes it).
#   $FLEETLOC_TIDY_MAX_FILES (default 150; 0 = no cap): more changed sources than that fails.
set -euo pipefail
cd "$(dirname "$0")/../.."
base="${1:-${FLEETLOC_TIDY_BASE:-}}"
if [[ -n "$base" ]]; then
  # A base asked for by name that does not exist is a mistake, not "nothing to check".
  if ! git rev-parse --verify --quiet "$base^{commit}" >/dev/null; then
    echo "check_tidy: no base revision $base" >&2
    exit 2
  fi
  why="given"
else
  recorded="$(tr -d '[:space:]' 2>/dev/null < .ci/tidy_base || true)"
  if [[ -n "$recorded" ]] && git rev-parse --verify --quiet "$recorded^{commit}" >/dev/null &&
     git merge-base --is-ancestor "$recorded" HEAD; then
    base="$recorded"
    why="recorded in .ci/tidy_base"
  else
    echo "check_tidy: the recorded base '${recorded:-<none>}' (.ci/tidy_base) is not a commit" \
         "this clone has as an ancestor of HEAD; falling back" >&2
    base="$(git merge-base HEAD origin/main 2>/dev/null || true)"
    why="merge base with origin/main"
    if [[ -z "$base" || "$base" == "$(git rev-parse HEAD)" ]]; then
      base="HEAD~1"
      why="HEAD~1, the last commit only"
    fi
    if ! git rev-parse --verify --quiet "$base^{commit}" >/dev/null; then
      echo "check_tidy: no base revision $base (a one-commit clone?); nothing to compare" >&2
      exit 0
    fi
  fi
fi
[[ -f build/compile_commands.json ]] || { echo "check_tidy: build/compile_commands.json missing" >&2; exit 1; }
mapfile -t changed < <(git diff --name-only --diff-filter=AMR "$base" HEAD -- \
                         'common/*.cpp' 'services/*.cpp' 'tools/*.cpp' 'tests/*.cpp' |
                       while read -r f; do grep -q "\"file\": \".*/$f\"" build/compile_commands.json && echo "$f"; done)
echo "check_tidy: ${#changed[@]} changed sources since $(git rev-parse --short "$base") ($why)"
[[ ${#changed[@]} -gt 0 ]] || exit 0
# The cap. clang-tidy takes about 13 s per source per core here (the Eigen and OpenCV headers), so
# CI's 2 cores check about 9 sources a minute: 150 sources are ~17 min, what CI's 60-min total can
# spare beside the build, the tests and the fuzzing. A larger range fails with its count rather
# than being checked in part: a truncated check would pass sources nobody checked. Such a landing
# is checked by hand (FLEETLOC_TIDY_MAX_FILES=0 tools/scripts/check_tidy.sh) and its last commit
# records the checked commit in .ci/tidy_base.
max="${FLEETLOC_TIDY_MAX_FILES:-150}"
if [[ "$max" -gt 0 && ${#changed[@]} -gt "$max" ]]; then
  echo "check_tidy: ${#changed[@]} changed sources is more than the cap of $max" \
       "(FLEETLOC_TIDY_MAX_FILES); none checked. Check them by hand with FLEETLOC_TIDY_MAX_FILES=0" \
       "and advance .ci/tidy_base (docs/architecture.md, \"Structure checks\")" >&2
  exit 1
fi
# Findings in headers count only for the headers the change touched (a header's old findings are
# not the change's); a regex of their absolute paths, or one that matches nothing.
root="$(pwd | sed 's/[][\.*^$+?(){}|]/\\&/g')"
mapfile -t headers < <(git diff --name-only --diff-filter=AMR "$base" HEAD -- '*.h' | sed 's/[][\.*^$+?(){}|]/\\&/g')
header_filter='^$'
[[ ${#headers[@]} -eq 0 ]] || header_filter="^$root/($(IFS='|'; echo "${headers[*]}"))\$"
report="$(mktemp)"
trap 'rm -f "$report"' EXIT
printf '%s\n' "${changed[@]}" |
  xargs -P "$(nproc)" -n 1 clang-tidy -p build --quiet --header-filter="$header_filter" \
    --extra-arg=-Wno-error --extra-arg=-Wno-unknown-warning-option \
    2>/dev/null | tee "$report" || true
if grep -qE "(warning|error):" "$report"; then
  echo "check_tidy: findings above" >&2
  exit 1
fi
echo "check_tidy: clean"
