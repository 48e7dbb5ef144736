#!/usr/bin/env bash
# Builds the libFuzzer targets (tools/fuzz/) with clang, AddressSanitizer and UBSan into
# build-fuzz/, then runs each for FLEETLOC_FUZZ_SECONDS (default 20) starting from its seed corpus
# (tools/fuzz/corpus/<target>/, copied: the committed seeds are not changed). Any crash, leak,
# sanitizer report or time-out fails the run; the reproducer is left in build-fuzz/findings/.
# Usage: tools/scripts/run_fuzz.sh [TARGET...]   (default: every target)
set -euo pipefail
cd "$(dirname "$0")/../.."
SECONDS_EACH="${FLEETLOC_FUZZ_SECONDS:-20}"
cmake --preset fuzz >/dev/null  # clang, FLEETLOC_FUZZ=ON, no tests or benchmarks (CMakePresets.json)
cmake --build --preset fuzz -j "$(nproc)"
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_run_files fuzz_camera_json fuzz_tile_png fuzz_place_index fuzz_wire_samples
                                 fuzz_http_api)
mkdir -p build-fuzz/findings
failed=0
for t in "${targets[@]}"; do
  corpus="build-fuzz/corpus/$t"
  mkdir -p "$corpus"
  cp -n tools/fuzz/corpus/"$t"/* "$corpus"/ 2>/dev/null || true
  echo "fuzz: $t for ${SECONDS_EACH} s" >&2
  if ! build-fuzz/bin/"$t" "$corpus" -max_total_time="$SECONDS_EACH" -timeout=10 -rss_limit_mb=2048 \
       -max_len=65536 -artifact_prefix="build-fuzz/findings/$t-" -print_final_stats=1 \
       > "build-fuzz/findings/$t.log" 2>&1; then
    echo "fuzz: $t FAILED (log: build-fuzz/findings/$t.log)" >&2
    tail -40 "build-fuzz/findings/$t.log" >&2
    failed=1
  else
    grep -E "stat::number_of_executed_runs|cov:" "build-fuzz/findings/$t.log" | tail -2 >&2
  fi
done
exit $failed
