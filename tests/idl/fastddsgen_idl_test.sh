#!/usr/bin/env bash
# Checks that idl/fleetloc.idl is valid OMG IDL for a second vendor's generator: eProsima's
# fastddsgen, run without its case-sensitivity flag (-cs), must generate the types without an
# error. (IDL identifiers that differ only in case collide; Cyclone's idlc lets that pass.)
# Usage: fastddsgen_idl_test.sh FASTDDSGEN IDL_FILE
set -euo pipefail
fastddsgen="$1"
idl="$2"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

status=0
log="$("$fastddsgen" -replace -d "$out" "$idl" 2>&1)" || status=$?
echo "$log"
# fastddsgen has exited 0 after printing errors in some versions: look at its output too.
if [ "$status" -ne 0 ] || grep -q "error:" <<<"$log"; then
  echo "FAIL: fastddsgen rejects $idl (exit status $status)" >&2
  exit 1
fi
name="$(basename "$idl" .idl)"
for f in "$name.h" "$name.cxx" "${name}PubSubTypes.h" "${name}PubSubTypes.cxx"; do
  [ -s "$out/$f" ] || { echo "FAIL: fastddsgen wrote no $f" >&2; exit 1; }
done
echo "OK: fastddsgen generates $idl without -cs"
