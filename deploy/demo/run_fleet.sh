#!/usr/bin/env bash
# The running fleet on this machine, on the embedded default: installs and builds (setup.sh),
# composes the default real floor from the demo photographs and imports it as the shared mosaic
# (once; kept in out/fleet/), then starts the map server, the fleet supervisor with its dashboard
# and three simulated vehicles driving forever over the floor, each with its own tracker agent.
# Prints the dashboard URL and the maintainer token; Ctrl-C (or SIGTERM) stops everything cleanly.
# Environment: FLEETLOC_DOMAIN (DDS domain, default 0), FLEETLOC_HTTP_PORT (default 8080),
# FLEETLOC_VEHICLES (default 3), FLEETLOC_SECURE=1 (DDS Security, the production setting: the
# credentials are made once in out/fleet/security/ by deploy/security/make_security.sh, each
# process runs as its own participant, and fleetctl needs the maintainer's configuration the
# script prints), FLEETLOC_MQTT=1 (VDA 5050: a local mosquitto broker on FLEETLOC_MQTT_PORT,
# default 1883, and the supervisor publishing every vehicle's visualization to it; the script
# prints the mosquitto_sub command that shows them); for tests: FLEETLOC_FLEET_DIR (default out/fleet) and FLEETLOC_SKIP_SETUP=1
# (use the existing build).
set -euo pipefail
cd "$(dirname "$0")/../.."
[ "${FLEETLOC_SKIP_SETUP:-0}" = 1 ] || tools/scripts/setup.sh

BIN="$PWD/build/bin"  # absolute, as OUT: the printed commands work from any directory
OUT="$(realpath -m "${FLEETLOC_FLEET_DIR:-out/fleet}")"
DOMAIN="${FLEETLOC_DOMAIN:-0}"
PORT="${FLEETLOC_HTTP_PORT:-8080}"
VEHICLES="${FLEETLOC_VEHICLES:-3}"
SECURE="${FLEETLOC_SECURE:-0}"
MQTT="${FLEETLOC_MQTT:-0}"
MQTT_PORT="${FLEETLOC_MQTT_PORT:-1883}"
F=deploy/demo/floors
mkdir -p "$OUT/logs"

if [ ! -f "$OUT/mosaic.db" ]; then
  "$BIN/fleetctl" compose-floor "$F/rock_dirt_2048.png" "$F/stone_slab_floor_2048.png" \
    "$F/moss_2560x1600.jpg" --out "$OUT/floor.png"
  "$BIN/fleetctl" mosaic import "$OUT/floor.png" --resolution 0.0005 --out "$OUT/mosaic.db.part"
  mv "$OUT/mosaic.db.part" "$OUT/mosaic.db"
fi
[ -f "$OUT/maintainer.token" ] || head -c 18 /dev/urandom | base64 | tr '+/' '-_' > "$OUT/maintainer.token"
chmod 600 "$OUT/maintainer.token"

# The Cyclone configuration of one participant (role, id): the built-in loopback default, or
# with FLEETLOC_SECURE=1 its own secured configuration.
dds_config() {
  if [ "$SECURE" = 1 ]; then
    echo --dds-config "$OUT/security/participants/$1-$2/cyclonedds.xml"
  fi
}
if [ "$SECURE" = 1 ]; then
  vehicle_ids="$(seq -s, -f 'agv-%g' 1 "$VEHICLES")"
  deploy/security/make_security.sh --out "$OUT/security" --domain "$DOMAIN" --servers map-1 \
    --supervisors sup-1 --maintainers ops-1 --vehicles "$vehicle_ids" > "$OUT/make_security.log"
fi

PIDS=()
stop_all() {
  trap - INT TERM
  echo "fleet: stopping ${#PIDS[@]} processes" >&2
  for pid in "${PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
  echo "fleet: stopped" >&2
  exit 0
}
trap stop_all INT TERM

start() {  # name, then the command; output to out/fleet/logs/<name>.log
  local name="$1"; shift
  "$@" > "$OUT/logs/$name.log" 2>&1 &
  PIDS+=("$!")
}

start map_server "$BIN/map_server" --mosaic "$OUT/mosaic.db" --domain "$DOMAIN" --server-id map-1 \
  $(dds_config server map-1)
supervisor_config=()
if [ "$MQTT" = 1 ]; then  # a local broker, and VDA 5050 on in the supervisor's configuration
  printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\n' "$MQTT_PORT" > "$OUT/mosquitto.conf"
  start mosquitto /usr/sbin/mosquitto -c "$OUT/mosquitto.conf"
  printf '{"vda5050": {"enabled": true, "host": "127.0.0.1", "port": %s, "rate_hz": 2}}\n' "$MQTT_PORT" \
    > "$OUT/fleet_supervisor.json"
  supervisor_config=(--config "$OUT/fleet_supervisor.json")
fi
start fleet_supervisor "$BIN/fleet_supervisor" --domain "$DOMAIN" --http-port "$PORT" \
  --history "$OUT/fleet_history.db" --token-file "$OUT/maintainer.token" "${supervisor_config[@]}" \
  $(dds_config supervisor sup-1)
for i in $(seq 1 "$VEHICLES"); do
  id="agv-$i"
  # Spread the vehicles along the route; each starts from its own simulated pose.
  printf '{"vehicle_id": "%s", "source": "sim", "sim_floor": "%s", "sim_start_fraction": %s, "sim_seed": %d}\n' \
    "$id" "$OUT/floor.png" "$(awk -v i="$i" -v n="$VEHICLES" 'BEGIN { printf "%.3f", (i - 1) / n }')" "$i" \
    > "$OUT/$id.json"
  start "$id" "$BIN/tracker_agent" --config "$OUT/$id.json" --domain "$DOMAIN" \
    --outbox "$OUT/outbox-$id.db" $(dds_config vehicle "$id")
done

echo "fleet: map server, supervisor and $VEHICLES vehicles running on DDS domain $DOMAIN" >&2
echo "fleet: dashboard  http://127.0.0.1:$PORT/" >&2
echo "fleet: maintainer token (for re-mapping from the dashboard) in $OUT/maintainer.token" >&2
if [ "$SECURE" = 1 ]; then
  echo "fleet: DDS Security on; as a maintainer: $BIN/fleetctl status --domain $DOMAIN $(dds_config maintainer ops-1)" >&2
fi
if [ "$MQTT" = 1 ]; then
  echo "fleet: VDA 5050 on mqtt://127.0.0.1:$MQTT_PORT; watch: mosquitto_sub -p $MQTT_PORT -t 'uagv/v2/fleetloc/+/visualization' -v" >&2
fi
echo "fleet: logs in $OUT/logs/; Ctrl-C stops everything" >&2
# Any process that exits on its own is reported; the rest keep running until Ctrl-C.
while true; do
  for idx in "${!PIDS[@]}"; do
    if ! kill -0 "${PIDS[$idx]}" 2>/dev/null; then
      wait "${PIDS[$idx]}" 2>/dev/null && rc=0 || rc=$?
      echo "fleet: process ${PIDS[$idx]} exited ($rc); see $OUT/logs/" >&2
      unset "PIDS[$idx]"
    fi
  done
  sleep 1 &
  wait $! || true
done
