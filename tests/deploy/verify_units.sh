#!/usr/bin/env bash
# Checks the shipped systemd units (deploy/systemd/) with systemd-analyze verify: syntax, known
# directives, and that each ExecStart binary exists (pointed at this build's bin directory); and
# that each is Type=notify with a watchdog (the daemons send READY=1 and feed it, issue 22).
# Usage: verify_units.sh SOURCE_DIR BIN_DIR
set -euo pipefail
src="$1"; bin="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
for unit in "$src"/deploy/systemd/*.service; do
  for directive in Type=notify WatchdogSec=; do
    grep -q "^$directive" "$unit" || { echo "$unit: no $directive"; exit 1; }
  done
  name="$(basename "$unit")"
  name="${name/@.service/@agv-1.service}"  # a template is verified as an instance
  sed "s#/usr/local/bin/#$bin/#g" "$unit" > "$work/$name"
done
cd "$work"
out="$(systemd-analyze verify --man=no ./*.service 2>&1 || true)"
if [ -n "$out" ]; then echo "$out"; exit 1; fi
echo "$(ls | wc -l) units verified"
