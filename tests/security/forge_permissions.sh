#!/usr/bin/env bash
# Test helper (tests/security_test.cpp): the configuration of an intruder who holds a site's real
# vehicle identity (certificate and key of PARTICIPANT) but presents a permissions document of its
# own, granting every vehicle's partition, signed by another permissions CA (that of OUTSIDER_SITE,
# which it also names as its permissions CA, with that site's governance). Peers of the real site
# must refuse it: the document is not signed by their permissions CA.
#   forge_permissions.sh SITE_DIR PARTICIPANT OUTSIDER_SITE_DIR OUT_DIR
set -euo pipefail
site="$1" participant="$2" outsider="$3" out="$4"
mkdir -p "$out"
real="$site/participants/$participant"
sed 's/<partition>fleetloc\.vehicle\.[^<]*<\/partition>/<partition>fleetloc.vehicle.*<\/partition>/' \
  "$real/permissions.xml" > "$out/permissions.xml"
openssl smime -sign -in "$out/permissions.xml" -text -out "$out/permissions.p7s" \
  -signer "$outsider/ca/permissions_ca.pem" -inkey "$outsider/ca/permissions_ca.key"
sed -e "s#<PermissionsCA>.*</PermissionsCA>#<PermissionsCA>file:$outsider/ca/permissions_ca.pem</PermissionsCA>#" \
    -e "s#<Governance>.*</Governance>#<Governance>file:$outsider/governance.p7s</Governance>#" \
    -e "s#<Permissions>.*</Permissions>#<Permissions>file:$out/permissions.p7s</Permissions>#" \
  "$real/cyclonedds.xml" > "$out/cyclonedds.xml"
