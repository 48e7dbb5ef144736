#!/usr/bin/env bash
# The Debian packages (deploy/debian/packaging.cmake): cpack makes them from BUILD_DIR, then each is
# checked as dpkg sees it — its files (binaries in /usr/bin, units in /lib/systemd/system that point
# at them and pass systemd-analyze verify), its conffiles, its maintainer scripts and its declared
# dependencies (shared libraries found by dpkg-shlibdeps, fleetloc-common, the dashboard's
# libjs-*).
# With "install" (in the default test run: it downloads Debian 12 from the mirror, about 2 minutes
# the first time, then the root is cached in BUILD_DIR; FLEETLOC_DEB_ROOT_TEST=0 skips it on a
# machine without the mirror) the
# packages are also installed with apt into a fresh Debian 12 root made by debootstrap, and the
# services are started there as the fleetloc user with their shipped configurations: the map
# server, the supervisor and an agent must come up (mosaic announced, /readyz 200, the vehicle
# tracking).
# Usage: deb_packages_test.sh SOURCE_DIR BUILD_DIR [install]
set -euo pipefail
src="$1"; build="$2"; mode="${3:-}"
fail() { echo "FAIL: $*" >&2; exit 1; }
if [ "$mode" = install ] && [ "${FLEETLOC_DEB_ROOT_TEST:-1}" = 0 ]; then
  echo "skipped: FLEETLOC_DEB_ROOT_TEST=0"; exit 77
fi

# Starts the installed map server, supervisor and agent in root $1 as their units would (no systemd
# runs as PID 1 here): the shipped configurations, the fleetloc user, the unit's CYCLONEDDS_URI;
# they must come up (mosaic announced over DDS, /readyz 200, the vehicle tracking in the
# supervisor's API) and stop cleanly on SIGTERM.
start_services() {
  local r="$1" work="$2"
  ip link set lo up
  chroot "$r" sh -c 'head -c 40 /dev/urandom | od -An -tx1 | tr -d " \n" > /etc/fleetloc/maintainer_token; chown fleetloc /etc/fleetloc/maintainer_token; chmod 600 /etc/fleetloc/maintainer_token'
  run_as() { chroot --userspec=fleetloc:fleetloc "$r" env CYCLONEDDS_URI=file:///etc/fleetloc/cyclonedds.xml HOME=/var/lib/fleetloc "$@"; }
  start_as() { exec chroot --userspec=fleetloc:fleetloc "$r" env CYCLONEDDS_URI=file:///etc/fleetloc/cyclonedds.xml HOME=/var/lib/fleetloc "$@"; }
  cp "$src/deploy/demo/floors/gravel_1024.png" "$r/tmp/floor.png"
  run_as fleetctl mosaic import /tmp/floor.png --resolution 0.0005 --out /var/lib/fleetloc/mosaic.db >/dev/null 2>&1
  start_as map_server --config /etc/fleetloc/map_server.json >"$work/map_server.log" 2>&1 & ms=$!
  start_as fleet_supervisor --config /etc/fleetloc/fleet_supervisor.json >"$work/supervisor.log" 2>&1 & sv=$!
  # The agent's shipped configuration replays a recorded run; here it drives a simulated vehicle.
  start_as tracker_agent --config /etc/fleetloc/tracker_agent.json --sim-floor /tmp/floor.png \
    --outbox /var/lib/fleetloc/outbox-agv-1.db >"$work/agent.log" 2>&1 & ag=$!
  trap 'kill $ms $sv $ag 2>/dev/null || true' EXIT
  ok=""
  for _ in $(seq 60); do
    sleep 1
    if run_as fleetctl mosaic info --domain 0 --wait 1 2>/dev/null | grep -q mosaic_id &&
       curl -sf http://127.0.0.1:8080/readyz >/dev/null &&
       curl -sf http://127.0.0.1:8080/api/vehicles/agv-1 | grep -q '"lock": *"tracking"'; then ok=1; break; fi
  done
  [ -n "$ok" ] || { tail -20 "$work/map_server.log" "$work/supervisor.log" "$work/agent.log"; fail "the services did not come up"; }
  echo "map server, supervisor and agent up; agv-1 tracking on the supervisor"
  kill -TERM $ag $ms $sv
  wait $ag || fail "the agent did not stop cleanly: $(tail -3 "$work/agent.log")"
  wait $ms || fail "the map server did not stop cleanly: $(tail -3 "$work/map_server.log")"
  wait $sv || fail "the supervisor did not stop cleanly: $(tail -3 "$work/supervisor.log")"
}
if [ "$mode" = start-services ]; then start_services "$4" "$5"; exit 0; fi
work="$(mktemp -d)"; trap 'rm -rf --one-file-system "$work"' EXIT

(cd "$build" && cpack -G DEB -B "$work/out" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack"; }
field() { dpkg-deb -f "$1" "$2"; }
deb() { ls "$work"/out/fleetloc-"$1"_*.deb 2>/dev/null | head -1; }

for pkg in common map-server supervisor agent tools; do
  [ -n "$(deb "$pkg")" ] || fail "no fleetloc-$pkg package ($(ls "$work/out"))"
done
declare -A binary=([map-server]=map_server [supervisor]=fleet_supervisor [agent]=tracker_agent)
declare -A unit=([map-server]=fleetloc-map-server.service [supervisor]=fleetloc-fleet-supervisor.service
                 [agent]=fleetloc-tracker-agent@.service)
declare -A config=([map-server]=map_server.json [supervisor]=fleet_supervisor.json [agent]=tracker_agent.json)
mkdir -p "$work/units"
for pkg in map-server supervisor agent; do
  d="$(deb "$pkg")"
  files="$(dpkg-deb -c "$d")"
  for f in "./usr/bin/${binary[$pkg]}" "./lib/systemd/system/${unit[$pkg]}" "./etc/fleetloc/${config[$pkg]}"; do
    grep -q " $f\$" <<<"$files" || fail "$pkg: $f missing"
  done
  dpkg-deb --ctrl-tarfile "$d" | tar -x -C "$work" ./conffiles ./postinst
  grep -qx "/etc/fleetloc/${config[$pkg]}" "$work/conffiles" || fail "$pkg: ${config[$pkg]} is not a conffile"
  grep -q "adduser --system" "$work/postinst" || fail "$pkg: postinst does not make the fleetloc user"
  depends="$(field "$d" Depends)"
  for need in fleetloc-common libddsc libsystemd0 libc6; do
    grep -q "$need" <<<"$depends" || fail "$pkg: Depends lacks $need: $depends"
  done
  # The map server and the agent run image code; the supervisor links no OpenCV (its fleet logic
  # shares only the lock-state vocabulary with the tracker), so its package must not pull it in.
  if [ "$pkg" = supervisor ]; then
    ! grep -q libopencv <<<"$depends" || fail "$pkg: depends on OpenCV, which it does not use: $depends"
  else
    grep -q libopencv <<<"$depends" || fail "$pkg: Depends lacks libopencv: $depends"
  fi
  dpkg-deb --fsys-tarfile "$d" | tar -x -O "./lib/systemd/system/${unit[$pkg]}" >"$work/units/${unit[$pkg]/@.service/@agv-1.service}"
  grep -q "^ExecStart=/usr/bin/${binary[$pkg]} " "$work/units/${unit[$pkg]/@.service/@agv-1.service}" ||
    fail "$pkg: the unit does not start /usr/bin/${binary[$pkg]}"
  echo "fleetloc-$pkg: $(field "$d" Version), Depends: $depends"
done
grep -q "libjs-leaflet" <<<"$(field "$(deb supervisor)" Depends)" || fail "supervisor: no libjs-leaflet dependency"
grep -q " ./usr/share/fleetloc/fleet_supervisor/web/map_view.js$" <<<"$(dpkg-deb -c "$(deb supervisor)")" || fail "no dashboard"
grep -q " ./usr/bin/fleetctl$" <<<"$(dpkg-deb -c "$(deb tools)")" || fail "tools: no fleetctl"
grep -q " ./etc/fleetloc/cyclonedds.xml$" <<<"$(dpkg-deb -c "$(deb common)")" || fail "common: no cyclonedds.xml"
# The packaged units verify with their binaries at /usr/bin (pointed at this build's).
for u in "$work"/units/*; do sed -i "s#/usr/bin/#$build/bin/#g" "$u"; done
out="$(cd "$work/units" && systemd-analyze verify --man=no ./*.service 2>&1 || true)"
[ -z "$out" ] || fail "systemd-analyze verify: $out"
echo "5 packages checked"

[ "$mode" = install ] || exit 0
# ---- install into a fresh Debian 12 root and start the services --------------------------------
root="${FLEETLOC_DEB_ROOT_CACHE:-$build/debian12-root.tar}"
if [ ! -f "$root" ]; then
  command -v debootstrap >/dev/null || fail "debootstrap is not installed (tools/scripts/setup.sh)"
  debootstrap --variant=minbase bookworm "$work/root" http://deb.debian.org/debian >"$work/debootstrap.log" 2>&1 ||
    { tail -20 "$work/debootstrap.log"; fail "debootstrap (is the Debian mirror reachable?)"; }
  tar -C "$work/root" -cf "$root" .
else
  mkdir -p "$work/root" && tar -C "$work/root" -xf "$root"
fi
r="$work/root"
cp "$work"/out/*.deb "$r/tmp/"
cp /etc/resolv.conf "$r/etc/resolv.conf"
mount -t proc proc "$r/proc"; mount --bind /dev "$r/dev"
trap 'umount "$r/dev" "$r/proc" 2>/dev/null || true; rm -rf --one-file-system "$work"' EXIT
chroot "$r" sh -c 'apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends /tmp/fleetloc-*.deb' \
  >"$work/apt.log" 2>&1 || { tail -30 "$work/apt.log"; fail "apt-get install of the packages"; }
chroot "$r" getent passwd fleetloc >/dev/null || fail "no fleetloc user after install"
[ "$(chroot "$r" stat -c %U /var/lib/fleetloc)" = fleetloc ] || fail "/var/lib/fleetloc is not the fleetloc user's"
# The services run in a network namespace of their own (their ports are the shipped defaults,
# 8080 and 9471/9472, which something on this host may hold).
unshare -n "$0" "$src" "$build" start-services "$r" "$work"
echo "installed into a fresh Debian 12 root; the three services came up as fleetloc"
