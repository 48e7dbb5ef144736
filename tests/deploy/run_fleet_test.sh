#!/usr/bin/env bash
# The README's main command end to end: deploy/demo/run_fleet.sh (on the existing build) brings up
# the map server, the supervisor and three simulated vehicles; within a minute the supervisor's
# API shows all three tracking, the dashboard page is served, and SIGTERM (what Ctrl-C's process
# group signal amounts to) stops every process with exit status 0. With `secure`
# (FLEETLOC_SECURE=1), a maintainer's fleetctl sees the three vehicles and an outsider sees none.
# Usage: run_fleet_test.sh SOURCE_DIR BINARY_DIR DOMAIN [secure]
set -euo pipefail
src="$1" bin="$2" domain="$3" secure="${4:-}"
dir="$(mktemp -d)"
port=$((20000 + RANDOM % 20000))
cleanup() { [ -n "${pid:-}" ] && kill -TERM "$pid" 2>/dev/null; rm -rf "$dir"; }
trap cleanup EXIT
FLEETLOC_SECURE="$([ "$secure" = secure ] && echo 1 || echo 0)" \
FLEETLOC_SKIP_SETUP=1 FLEETLOC_FLEET_DIR="$dir" FLEETLOC_DOMAIN="$domain" FLEETLOC_HTTP_PORT="$port" \
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
vehicles_seen() {  # by fleetctl status with the given extra arguments
  "$bin/fleetctl" status --json --wait 3 --domain "$domain" "$@" |
    python3 -c 'import json,sys; print(len(json.load(sys.stdin)["vehicles"]))'
}
if [ "$secure" = secure ]; then
  maintainer="$dir/security/participants/maintainer-ops-1/cyclonedds.xml"
  grep -q "fleetctl status --domain $domain --dds-config $maintainer" "$dir/run_fleet.out" ||
    { echo "no maintainer command printed"; cat "$dir/run_fleet.out"; exit 1; }
  seen="$(vehicles_seen --dds-config "$maintainer")"
  [ "$seen" -eq 3 ] || { echo "the maintainer sees $seen vehicles, not 3"; exit 1; }
  seen="$(vehicles_seen)"
  [ "$seen" -eq 0 ] || { echo "an outsider without credentials sees $seen vehicles"; exit 1; }
fi
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
echo "3 vehicles tracking on port $port${secure:+ (secured)}; stopped cleanly"
