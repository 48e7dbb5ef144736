#!/usr/bin/env bash
# clang-tidy (the repository's .clang-tidy) over the C++ sources changed since a base revision;
# any finding fails. Usage: tools/scripts/check_tidy.sh [BASE]
# The build's compiler flags are GCC's: -Werror (FLEETLOC_WERROR) and GCC-only warning options are
# neutralized for clang-tidy's clang front end, so only the checks' findings count.
#   BASE: a git revision; default $FLEETLOC_TIDY_BASE, else the merge base with origin/main, else
#   HEAD~1 (a clean clone's last commit). Changed headers are checked through the sources that
#   include them. Needs build/compile_commands.json (cmake --preset release writes it). At most
#   $FLEETLOC_TIDY_MAX_FILES sources (default 40) are checked, and the count is printed.
set -euo pipefail
cd "$(dirname "$0")/../.."
base="${1:-${FLEETLOC_TIDY_BASE:-}}"
if [[ -z "$base" ]]; then
  base="$(git merge-base HEAD origin/main 2>/dev/null || true)"
  [[ -n "$base" && "$base" != "$(git rev-parse HEAD)" ]] || base="HEAD~1"
fi
if ! git rev-parse --verify --quiet "$base^{commit}" >/dev/null; then
  echo "check_tidy: no base revision $base; nothing to compare" >&2
  exit 0
fi
[[ -f build/compile_commands.json ]] || { echo "check_tidy: build/compile_commands.json missing" >&2; exit 1; }
mapfile -t changed < <(git diff --name-only --diff-filter=AMR "$base" HEAD -- \
                         'common/*.cpp' 'services/*.cpp' 'tools/*.cpp' 'tests/*.cpp' |
                       while read -r f; do grep -q "\"file\": \".*/$f\"" build/compile_commands.json && echo "$f"; done)
max="${FLEETLOC_TIDY_MAX_FILES:-40}"
echo "check_tidy: ${#changed[@]} changed sources since $(git rev-parse --short "$base"), checking $(( ${#changed[@]} < max ? ${#changed[@]} : max ))"
[[ ${#changed[@]} -gt 0 ]] || exit 0
# Findings in headers count only for the headers the change touched (a header's old findings are
# not the change's); a regex of their absolute paths, or one that matches nothing.
root="$(pwd | sed 's/[][\.*^$+?(){}|]/\\&/g')"
mapfile -t headers < <(git diff --name-only --diff-filter=AMR "$base" HEAD -- '*.h' | sed 's/[][\.*^$+?(){}|]/\\&/g')
header_filter='^$'
[[ ${#headers[@]} -eq 0 ]] || header_filter="^$root/($(IFS='|'; echo "${headers[*]}"))\$"
report="$(mktemp)"
trap 'rm -f "$report"' EXIT
printf '%s\n' "${changed[@]:0:$max}" |
  xargs -P "$(nproc)" -n 1 clang-tidy -p build --quiet --header-filter="$header_filter" \
    --extra-arg=-Wno-error --extra-arg=-Wno-unknown-warning-option \
    2>/dev/null | tee "$report" || true
if grep -qE "(warning|error):" "$report"; then
  echo "check_tidy: findings above" >&2
  exit 1
fi
echo "check_tidy: clean"
