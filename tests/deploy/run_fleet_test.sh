#!/usr/bin/env bash
# The README's main command end to end: deploy/demo/run_fleet.sh (on the existing build) brings up
# the map server, the supervisor and three simulated vehicles; within a minute the supervisor's
# API shows all three tracking, the dashboard page is served, and SIGTERM (what Ctrl-C's process
# group signal amounts to) stops every process with exit status 0.
# Usage: run_fleet_test.sh SOURCE_DIR
set -euo pipefail
src="$1"
dir="$(mktemp -d)"
port=$((20000 + RANDOM % 20000))
cleanup() { [ -n "${pid:-}" ] && kill -TERM "$pid" 2>/dev/null; rm -rf "$dir"; }
trap cleanup EXIT
FLEETLOC_SKIP_SETUP=1 FLEETLOC_FLEET_DIR="$dir" FLEETLOC_DOMAIN=96 FLEETLOC_HTTP_PORT="$port" \
  setsid "$src/deploy/demo/run_fleet.sh" > "$dir/run_fleet.out" 2>&1 &
pid=$!
tracking=0
for _ in $(seq 1 120); do
  sleep 1
  kill -0 "$pid" 2>/dev/null || { echo "run_fleet.sh exited early:"; cat "$dir/run_fleet.out"; exit 1; }
  fleet="$(curl -sf "http://127.0.0.1:$port/api/fleet" || true)"
  tracking="$(printf '%s' "$fleet" | python3 -c 'import json,sys
try: print(json.load(sys.stdin)["summary"]["tracking"])
except Exception: print(0)')"
  [ "$tracking" -ge 3 ] && break
done
[ "$tracking" -ge 3 ] || { echo "only $tracking vehicles tracking"; tail -20 "$dir/logs/"*.log; exit 1; }
grep -q "http://127.0.0.1:$port/" "$dir/run_fleet.out" || { echo "no dashboard URL printed"; exit 1; }
curl -sf "http://127.0.0.1:$port/" | grep -qi "<html" || { echo "no dashboard page"; exit 1; }
children="$(pgrep -P "$pid" -f "build/bin/" | tr '\n' ' ')"
[ "$(echo $children | wc -w)" -eq 5 ] || { echo "expected 5 fleet processes, found: $children"; exit 1; }
kill -TERM "$pid"
status=0
wait "$pid" || status=$?
pid=""
[ "$status" -eq 0 ] || { echo "run_fleet.sh exited $status"; exit 1; }
for c in $children; do
  if kill -0 "$c" 2>/dev/null; then echo "process $c still running after the stop"; exit 1; fi
done
for log in "$dir"/logs/*.log; do
  grep -q "stopping" "$log" || { echo "$(basename "$log") did not stop cleanly"; tail -5 "$log"; exit 1; }
done
echo "3 vehicles tracking on port $port; stopped cleanly"
