#!/usr/bin/env bash
# Makes the DDS Security credentials of a fleetloc site (docs/security.md): an identity CA and a
# permissions CA, one identity certificate and key per participant, the signed governance, one
# signed permissions document per participant and one Cyclone DDS configuration per participant
# that loads Cyclone's authentication, access-control and crypto plugins. Idempotent: the CAs,
# keys and certificates are made once and kept; the XML documents are rewritten and re-signed only
# when their content changes. Run it again with a longer list to add a participant.
#
#   make_security.sh --out DIR [--domain N|MIN-MAX] [--maintainers a,b] [--vehicles agv-1,agv-2]
#                    [--servers map-1] [--supervisors sup-1]
#                    [--base-config FILE] [--install-dir DIR] [--days N]
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out="" domain="0" maintainers="" vehicles="" servers="" supervisors=""
base_config="$here/../cyclonedds/loopback.xml" install_dir="" days=3650
plugins="${FLEETLOC_DDS_SECURITY_PLUGINS:-/usr/lib/x86_64-linux-gnu/libddsc0debian}"

usage() { sed -n '2,11p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit "${1:-2}"; }
die() { echo "make_security: $*" >&2; exit 1; }
step() { echo "make_security: $*"; }

while [[ $# -gt 0 ]]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --domain) domain="$2"; shift 2 ;;
    --maintainers) maintainers="$2"; shift 2 ;;
    --vehicles) vehicles="$2"; shift 2 ;;
    --servers) servers="$2"; shift 2 ;;
    --supervisors) supervisors="$2"; shift 2 ;;
    --base-config) base_config="$2"; shift 2 ;;
    --install-dir) install_dir="$2"; shift 2 ;;
    --days) days="$2"; shift 2 ;;
    -h|--help) usage 0 ;;
    *) echo "make_security: unknown argument '$1'" >&2; usage ;;
  esac
done

[[ -n "$out" ]] || die "--out DIR is required"
[[ "$domain" =~ ^[0-9]+(-[0-9]+)?$ ]] || die "--domain '$domain' is not N or MIN-MAX"
[[ "$days" =~ ^[0-9]+$ ]] || die "--days '$days' is not a number"
[[ -r "$base_config" ]] || die "cannot read the base configuration $base_config"
grep -q '</Domain>' "$base_config" || die "$base_config has no <Domain> element"
for lib in auth ac crypto; do
  [[ -r "$plugins/libdds_security_$lib.so" ]] ||
    die "$plugins/libdds_security_$lib.so is missing (Debian package libddsc0debian)"
done
command -v openssl > /dev/null || die "openssl is not installed"
split() { tr ',' '\n' <<< "$1" | sed '/^$/d'; }
check_ids() {  # ids are vehicle ids too (partitions): 1-11 of [A-Za-z0-9_-]
  local id
  for id in $(split "$1"); do
    [[ "$id" =~ ^[A-Za-z0-9_-]{1,11}$ ]] || die "id '$id' is not 1-11 of [A-Za-z0-9_-]"
  done
}
for list in "$maintainers" "$vehicles" "$servers" "$supervisors"; do check_ids "$list"; done
mkdir -p "$out/ca"
out="$(cd "$out" && pwd)"
# Where the files will be when the services read them (the XML names them with absolute paths).
install_dir="${install_dir:-$out}"


# Writes $2 to file $1 only when it differs; returns 0 when the file changed.
write_if_changed() {
  if [[ -f "$1" ]] && [[ "$(cat "$1")" == "$2" ]]; then return 1; fi
  printf '%s\n' "$2" > "$1"
}

# --- certificate authorities ------------------------------------------------------------------
make_ca() {  # name, subject
  local key="$out/ca/$1.key" cert="$out/ca/$1.pem"
  [[ -f "$key" && -f "$cert" ]] && return 0
  step "making the $1 ($2)"
  (umask 077; openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out "$key" 2> /dev/null)
  openssl req -x509 -new -key "$key" -sha256 -days "$days" -subj "$2" -out "$cert"
}
make_ca identity_ca "/O=fleetloc/CN=fleetloc identity CA"
make_ca permissions_ca "/O=fleetloc/CN=fleetloc permissions CA"

sign() {  # xml file -> .p7s signed by the permissions CA (S/MIME, as the DDS Security spec asks)
  openssl smime -sign -in "$1" -text -out "${1%.xml}.p7s" -signer "$out/ca/permissions_ca.pem" \
    -inkey "$out/ca/permissions_ca.key"
}

domains_xml() {
  if [[ "$domain" == *-* ]]; then
    echo "<domains><id_range><min>${domain%-*}</min><max>${domain#*-}</max></id_range></domains>"
  else
    echo "<domains><id>$domain</id></domains>"
  fi
}

# --- governance -------------------------------------------------------------------------------
# Every participant must authenticate (no unauthenticated peers) and be allowed to join; discovery
# and liveliness traffic is encrypted, every RTPS message is signed (no injected or altered
# heartbeats, acknowledgements or data), every topic is access-controlled for both reading and
# writing, and payloads are encrypted (poses, health and floor images are the site's data).
governance_xml() {
  cat << EOF
<?xml version="1.0" encoding="UTF-8"?>
<!-- fleetloc governance (made by deploy/security/make_security.sh; docs/security.md) -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      $(domains_xml)
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>SIGN</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>fleetloc/*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>NONE</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
EOF
}
if write_if_changed "$out/governance.xml" "$(governance_xml)" || [[ ! -f "$out/governance.p7s" ]]; then
  step "signing governance.xml (domain $domain)"
  sign "$out/governance.xml"
fi

# --- permissions ------------------------------------------------------------------------------
any_vehicle="fleetloc.vehicle.*"
# One <publish>/<subscribe> criterion: kind, partition ("" = the default partition), topics...
criterion() {
  local kind="$1" partition="$2" topic
  shift 2
  echo "        <$kind>"
  echo "          <topics>"
  for topic in "$@"; do echo "            <topic>fleetloc/$topic</topic>"; done
  echo "          </topics>"
  if [[ -n "$partition" ]]; then
    echo "          <partitions><partition>$partition</partition></partitions>"
  fi
  echo "        </$kind>"
}

# The grants of each role (docs/security.md has the table and the reasons).
vehicle_rules() {  # a vehicle writes and receives only in its own partition
  local own="fleetloc.vehicle.$1"
  criterion publish "$own" vehicle_pose vehicle_health patch_observation tile_request
  criterion subscribe "$own" tile patch_ack
  criterion subscribe "" mosaic_info tile_update service_health place_index
}
server_rules() {
  criterion publish "" mosaic_info tile_update remap_status service_health place_index
  criterion publish "$any_vehicle" tile patch_ack
  criterion subscribe "$any_vehicle" tile_request patch_observation
  criterion subscribe "" remap_command service_health
}
# A supervisor holds the maintainer's RemapCommand grant: the dashboard's re-map (behind the
# maintainer token) is sent by it. Its overview tiles come in its own partition, like a vehicle's.
supervisor_rules() {
  local own="fleetloc.vehicle.$1"
  criterion publish "" service_health remap_command
  criterion publish "$own" tile_request
  criterion subscribe "$own" tile
  criterion subscribe "$any_vehicle" vehicle_pose vehicle_health
  criterion subscribe "" service_health remap_status mosaic_info tile_update
}
maintainer_rules() {
  criterion publish "" remap_command
  criterion subscribe "$any_vehicle" vehicle_pose vehicle_health
  criterion subscribe "" remap_status mosaic_info service_health tile_update
}

subject_of() { echo "CN=$1 $2,O=fleetloc"; }  # role, id (the certificate's subject)

permissions_xml() {  # role, id, certificate (the grant is valid as long as the certificate)
  local not_before not_after
  cert_date() { date -u -d "$(openssl x509 -in "$2" -noout "-$1" | cut -d= -f2)" +%Y-%m-%dT%H:%M:%S; }
  not_before="$(cert_date startdate "$3")" not_after="$(cert_date enddate "$3")"
  cat << EOF
<?xml version="1.0" encoding="UTF-8"?>
<!-- fleetloc permissions of $1 $2 (made by deploy/security/make_security.sh; docs/security.md) -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="$1_$2">
      <subject_name>$(subject_of "$1" "$2")</subject_name>
      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>
      <allow_rule>
        $(domains_xml)
$("$1_rules" "$2")
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
EOF
}

# The participant's Cyclone configuration: the base configuration plus a <Security> section.
security_xml() {  # participant directory (as installed)
  local ca="$install_dir/ca" me="$1"
  cat << EOF
    <Security>
      <Authentication>
        <Library path="$plugins/libdds_security_auth.so" initFunction="init_authentication" finalizeFunction="finalize_authentication"/>
        <IdentityCA>file:$ca/identity_ca.pem</IdentityCA>
        <IdentityCertificate>file:$me/cert.pem</IdentityCertificate>
        <PrivateKey>file:$me/key.pem</PrivateKey>
      </Authentication>
      <AccessControl>
        <Library path="$plugins/libdds_security_ac.so" initFunction="init_access_control" finalizeFunction="finalize_access_control"/>
        <PermissionsCA>file:$ca/permissions_ca.pem</PermissionsCA>
        <Governance>file:$install_dir/governance.p7s</Governance>
        <Permissions>file:$me/permissions.p7s</Permissions>
      </AccessControl>
      <Cryptographic>
        <Library path="$plugins/libdds_security_crypto.so" initFunction="init_crypto" finalizeFunction="finalize_crypto"/>
      </Cryptographic>
    </Security>
EOF
}

participant() {  # role, id
  local name="$1-$2" dir="$out/participants/$1-$2"
  mkdir -p "$dir"
  if [[ ! -f "$dir/key.pem" || ! -f "$dir/cert.pem" ]] ||
     ! openssl verify -CAfile "$out/ca/identity_ca.pem" "$dir/cert.pem" > /dev/null 2>&1; then
    step "making the identity of $name ($(subject_of "$1" "$2"))"
    (umask 077; openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out "$dir/key.pem" 2> /dev/null)
    openssl req -new -key "$dir/key.pem" -subj "/O=fleetloc/CN=$1 $2" -out "$dir/cert.csr"
    openssl x509 -req -in "$dir/cert.csr" -CA "$out/ca/identity_ca.pem" -CAkey "$out/ca/identity_ca.key" \
      -CAcreateserial -CAserial "$out/ca/identity_ca.srl" -days "$days" -sha256 -out "$dir/cert.pem" 2> /dev/null
    rm -f "$dir/cert.csr"
  fi
  if write_if_changed "$dir/permissions.xml" "$(permissions_xml "$1" "$2" "$dir/cert.pem")" || [[ ! -f "$dir/permissions.p7s" ]]; then
    step "signing the permissions of $name"
    sign "$dir/permissions.xml"
  fi
  local config
  config="$(sed '/<\/Domain>/,$d' "$base_config")
$(security_xml "$install_dir/participants/$name")
$(sed -n '/<\/Domain>/,$p' "$base_config")"
  write_if_changed "$dir/cyclonedds.xml" "$config" && step "wrote $dir/cyclonedds.xml"
  return 0
}

for id in $(split "$servers"); do participant server "$id"; done
for id in $(split "$supervisors"); do participant supervisor "$id"; done
for id in $(split "$maintainers"); do participant maintainer "$id"; done
for id in $(split "$vehicles"); do participant vehicle "$id"; done
step "done: $out (participants: $(ls "$out/participants" 2> /dev/null | tr '\n' ' '))"
