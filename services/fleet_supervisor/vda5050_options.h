// The fleet supervisor's VDA 5050 output over MQTT: the "vda5050" object of its configuration
// (unknown keys rejected, every field checked with a message naming it). Off by default.
#pragma once

#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "base/status.h"
#include "fleet_supervisor/vda5050_messages.h"
#include "io/json_fields.h"

namespace fleetloc::fleet_supervisor {

struct Vda5050Options {
  bool enabled = false;
  std::string host = "127.0.0.1";  // the MQTT broker
  int port = 1883;
  std::string client_id;  // empty: "fleetloc-<supervisor_id>"
  std::string username;   // empty: anonymous
  std::string password;   // or password_file (first line); never logged
  std::string password_file;
  bool tls = false;                          // TLS to the broker (then ca_file is required)
  std::string ca_file, cert_file, key_file;  // client certificate: both or neither
  bool tls_insecure = false;                 // skip the broker host name check (tests only)
  int keepalive_s = 10;
  double reconnect_max_s = 30;  // reconnect backoff 1 s doubling up to this
  Vda5050Header header;         // interface_name, manufacturer (topic fields)
  double rate_hz = 1.0;         // visualization messages per vehicle per second
  double max_pose_age_s = 2.0;  // a vehicle whose newest pose is older is not published
  std::map<std::string, std::string>
      serial_numbers;             // vehicle id -> serialNumber (default: the id)
  std::string connection_serial;  // serialNumber of the supervisor's connection topic
                                  // (empty: the supervisor_id)
};

Status Validate(const Vda5050Options& options);

// Reads the object member "vda5050" of `fields` (whose JSON is `parent`) over `*options`.
Status ReadVda5050Options(const io::JsonFields& fields, const nlohmann::json& parent,
                          Vda5050Options* options);

// The password in force: `password`, else the first line of `password_file` (NotFound naming the
// file), else empty.
Result<std::string> ResolveVda5050Password(const Vda5050Options& options);

}  // namespace fleetloc::fleet_supervisor
