// Vda5050Options from JSON.
#include "fleet_supervisor/vda5050_options.h"

#include <nlohmann/json.hpp>

#include "io/file_util.h"

namespace fleetloc::fleet_supervisor {

namespace {

// A topic level must not be empty or contain MQTT's separators and wildcards.
bool IsTopicLevel(const std::string& s) {
  return !s.empty() && s.size() <= 64 && s.find_first_of("/+#") == std::string::npos;
}

}  // namespace

Status Validate(const Vda5050Options& o) {
  auto bad = [](const std::string& field, const std::string& what) {
    return InvalidInput("fleet supervisor config: field 'vda5050." + field + "': " + what);
  };
  if (o.host.empty()) return bad("host", "is empty");
  if (o.port < 1 || o.port > 65535) return bad("port", "must be in [1, 65535]");
  if (o.keepalive_s < 5 || o.keepalive_s > 3600) return bad("keepalive_s", "must be in [5, 3600]");
  if (!(o.reconnect_max_s >= 1 && o.reconnect_max_s <= 3600))
    return bad("reconnect_max_s", "must be in [1, 3600]");
  if (!(o.rate_hz >= 0.1 && o.rate_hz <= 50)) return bad("rate_hz", "must be in [0.1, 50]");
  if (!(o.max_pose_age_s > 0 && o.max_pose_age_s <= 3600))
    return bad("max_pose_age_s", "must be in (0, 3600]");
  if (!IsTopicLevel(o.header.interface_name))
    return bad("interface_name", "must be 1-64 characters without / + #");
  if (!IsTopicLevel(o.header.manufacturer))
    return bad("manufacturer", "must be 1-64 characters without / + #");
  if (!o.connection_serial.empty() && !IsTopicLevel(o.connection_serial)) {
    return bad("connection_serial", "must be 1-64 characters without / + #");
  }
  for (const auto& [vehicle, serial] : o.serial_numbers) {
    if (!IsTopicLevel(serial))
      return bad("serial_numbers." + vehicle, "must be 1-64 characters without / + #");
  }
  if (!o.password.empty() && !o.password_file.empty())
    return bad("password", "give password or password_file, not both");
  if ((!o.password.empty() || !o.password_file.empty()) && o.username.empty())
    return bad("username", "is required with a password");
  if (o.tls && o.ca_file.empty()) return bad("ca_file", "is required with tls");
  if (o.cert_file.empty() != o.key_file.empty())
    return bad("cert_file", "cert_file and key_file go together");
  return Status::Ok();
}

Status ReadVda5050Options(const io::JsonFields& fields, const nlohmann::json& parent,
                          Vda5050Options* o) {
  Result<io::JsonFields> vda = fields.Object("vda5050");
  if (!vda.ok()) return vda.status();
  const nlohmann::json& json = parent.at("vda5050");
  const std::pair<const char*, std::string*> strings[] = {
      {"host", &o->host},
      {"client_id", &o->client_id},
      {"username", &o->username},
      {"password", &o->password},
      {"password_file", &o->password_file},
      {"ca_file", &o->ca_file},
      {"cert_file", &o->cert_file},
      {"key_file", &o->key_file},
      {"interface_name", &o->header.interface_name},
      {"manufacturer", &o->header.manufacturer},
      {"connection_serial", &o->connection_serial}};
  const std::pair<const char*, int*> ints[] = {{"port", &o->port},
                                               {"keepalive_s", &o->keepalive_s}};
  const std::pair<const char*, double*> numbers[] = {{"reconnect_max_s", &o->reconnect_max_s},
                                                     {"rate_hz", &o->rate_hz},
                                                     {"max_pose_age_s", &o->max_pose_age_s}};
  const std::pair<const char*, bool*> bools[] = {
      {"enabled", &o->enabled}, {"tls", &o->tls}, {"tls_insecure", &o->tls_insecure}};
  for (const auto& [key, value] : json.items()) {
    bool known = key == "serial_numbers";
    for (const auto& [name, out] : strings) known |= key == name;
    for (const auto& [name, out] : ints) known |= key == name;
    for (const auto& [name, out] : numbers) known |= key == name;
    for (const auto& [name, out] : bools) known |= key == name;
    if (!known) return vda->Error(key, "unknown option");
  }
  for (const auto& [name, out] : strings) {
    if (vda->Has(name)) FLEETLOC_RETURN_IF_ERROR(vda->NonEmptyString(name, out));
  }
  for (const auto& [name, out] : ints) {
    if (!vda->Has(name)) continue;
    double value = 0;
    FLEETLOC_RETURN_IF_ERROR(vda->NonNegativeNumber(name, &value));
    if (value != static_cast<int>(value)) return vda->Error(name, "must be an integer");
    *out = static_cast<int>(value);
  }
  for (const auto& [name, out] : numbers) {
    if (vda->Has(name)) FLEETLOC_RETURN_IF_ERROR(vda->PositiveNumber(name, out));
  }
  for (const auto& [name, out] : bools) {
    if (vda->Has(name)) FLEETLOC_RETURN_IF_ERROR(vda->Bool(name, out));
  }
  if (vda->Has("serial_numbers")) {
    const nlohmann::json& map = json.at("serial_numbers");
    if (!map.is_object())
      return vda->Error("serial_numbers", "must be an object {\"vehicle id\": \"serial number\"}");
    for (const auto& [vehicle, serial] : map.items()) {
      if (!serial.is_string()) return vda->Error("serial_numbers." + vehicle, "must be a string");
      o->serial_numbers[vehicle] = serial.get<std::string>();
    }
  }
  return Status::Ok();
}

Result<std::string> ResolveVda5050Password(const Vda5050Options& o) {
  if (!o.password.empty() || o.password_file.empty()) return o.password;
  Result<std::string> text = io::ReadFileText(o.password_file);
  if (!text.ok()) return NotFound(o.password_file + ": cannot read the MQTT password file");
  std::string password = text->substr(0, text->find('\n'));
  while (!password.empty() && password.back() == '\r') password.pop_back();
  return password;
}

}  // namespace fleetloc::fleet_supervisor
