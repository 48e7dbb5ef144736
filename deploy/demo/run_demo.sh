#!/usr/bin/env bash
# The main job on the embedded default: builds fleetloc, composes the default real floor from
# different photographs side by side, imports it as a tiled mosaic, simulates a fast vehicle run
# over it (non-overlapping frames, drifting odometry, dust, lighting change) and tracks it,
# printing the accuracy and speed summary. Outputs go to out/demo/.
set -euo pipefail
cd "$(dirname "$0")/../.."
tools/scripts/setup.sh

FLEETCTL=build/bin/fleetctl
OUT=out/demo
FRAMES="${FLEETLOC_DEMO_FRAMES:-1000}"
mkdir -p "$OUT"
F=deploy/demo/floors
"$FLEETCTL" compose-floor "$F/rock_dirt_2048.png" "$F/stone_slab_floor_2048.png" \
  "$F/moss_2560x1600.jpg" --out "$OUT/floor.png"
rm -f "$OUT/mosaic.db"
"$FLEETCTL" mosaic import "$OUT/floor.png" --resolution 0.0005 --out "$OUT/mosaic.db"
"$FLEETCTL" mosaic info "$OUT/mosaic.db"
rm -rf "$OUT/run"
"$FLEETCTL" sim --mosaic "$OUT/mosaic.db" --out "$OUT/run" --frames "$FRAMES" --seed 1
"$FLEETCTL" track --mosaic "$OUT/mosaic.db" --run "$OUT/run" --out "$OUT/poses.csv"
echo "poses written to $OUT/poses.csv" >&2
