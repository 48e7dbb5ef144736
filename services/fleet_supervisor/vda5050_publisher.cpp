// Vda5050Publisher: libmosquitto client, callbacks on its network thread.
#include "fleet_supervisor/vda5050_publisher.h"

#include <mosquitto.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "io/json_fields.h"

namespace fleetloc::fleet_supervisor {

namespace {

double WallNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// libmosquitto's process-wide set-up, once.
void InitLibrary() {
  static const int once = [] { return mosquitto_lib_init(); }();
  (void)once;
}

}  // namespace

Vda5050Publisher::Vda5050Publisher(const Vda5050Options& options, std::string connection_serial)
    : options_(options), connection_serial_(std::move(connection_serial)) {}

Result<std::unique_ptr<Vda5050Publisher>> Vda5050Publisher::Start(
    const Vda5050Options& o, const std::string& supervisor_id) {
  FLEETLOC_RETURN_IF_ERROR(Validate(o));
  Result<std::string> password = ResolveVda5050Password(o);
  if (!password.ok()) return password.status();
  InitLibrary();
  std::unique_ptr<Vda5050Publisher> p(
      new Vda5050Publisher(o, o.connection_serial.empty() ? supervisor_id : o.connection_serial));
  const std::string client_id = o.client_id.empty() ? "fleetloc-" + supervisor_id : o.client_id;
  p->client_ = mosquitto_new(client_id.c_str(), true, p.get());
  if (!p->client_) return Internal("vda5050: cannot create the MQTT client");
  mosquitto_int_option(p->client_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V311);
  if (!o.username.empty() &&
      mosquitto_username_pw_set(p->client_, o.username.c_str(),
                                password->empty() ? nullptr : password->c_str()) !=
          MOSQ_ERR_SUCCESS) {
    return InvalidInput("vda5050: the MQTT username or password is unusable");
  }
  if (o.tls) {
    const int rc = mosquitto_tls_set(p->client_, o.ca_file.c_str(), nullptr,
                                     o.cert_file.empty() ? nullptr : o.cert_file.c_str(),
                                     o.key_file.empty() ? nullptr : o.key_file.c_str(), nullptr);
    if (rc != MOSQ_ERR_SUCCESS) {
      return InvalidInput("vda5050: TLS files (" + o.ca_file + ", " + o.cert_file + ", " +
                          o.key_file + "): " + mosquitto_strerror(rc));
    }
    mosquitto_tls_insecure_set(p->client_, o.tls_insecure);
  }
  // The last will: the broker tells the fleet manager when the supervisor vanishes.
  const std::string will = io::DumpJson(
      ConnectionMessage(o.header, p->connection_serial_, 0, WallNow(), "CONNECTIONBROKEN"));
  const std::string topic = Vda5050Topic(o.header, p->connection_serial_, "connection");
  if (mosquitto_will_set(p->client_, topic.c_str(), static_cast<int>(will.size()), will.data(), 1,
                         true) != MOSQ_ERR_SUCCESS) {
    return InvalidInput("vda5050: cannot set the last will on " + topic);
  }
  mosquitto_connect_callback_set(p->client_, [](mosquitto*, void* self, int rc) {
    static_cast<Vda5050Publisher*>(self)->OnConnect(rc);
  });
  mosquitto_disconnect_callback_set(p->client_, [](mosquitto*, void* self, int rc) {
    static_cast<Vda5050Publisher*>(self)->OnDisconnect(rc);
  });
  mosquitto_reconnect_delay_set(p->client_, 1, static_cast<unsigned>(o.reconnect_max_s), true);
  const int rc = mosquitto_connect_async(p->client_, o.host.c_str(), o.port, o.keepalive_s);
  if (rc != MOSQ_ERR_SUCCESS) {  // e.g. refused at once: the network thread keeps trying
    ++p->losses_;
    p->SetProblem("cannot connect to the MQTT broker " + o.host + ":" + std::to_string(o.port) +
                  ": " + mosquitto_strerror(rc));
    spdlog::warn("vda5050: {}", p->problem());
  }
  if (mosquitto_loop_start(p->client_) != MOSQ_ERR_SUCCESS)
    return Internal("vda5050: cannot start the MQTT thread");
  spdlog::info("vda5050: publishing to {}:{} as {} ({} Hz per vehicle, topics {})", o.host, o.port,
               client_id, o.rate_hz, Vda5050Topic(o.header, "<serialNumber>", "visualization"));
  return p;
}

Vda5050Publisher::~Vda5050Publisher() {
  if (!client_) return;
  if (connected_) PublishConnection("OFFLINE", 1);
  mosquitto_disconnect(client_);
  mosquitto_loop_stop(client_, false);
  mosquitto_destroy(client_);
}

void Vda5050Publisher::SetProblem(std::string problem) {
  std::lock_guard<std::mutex> lock(mutex_);
  problem_ = std::move(problem);
}

std::string Vda5050Publisher::problem() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return connected_ ? "" : problem_;
}

void Vda5050Publisher::OnConnect(int rc) {
  if (rc != 0) {
    ++refused_;
    const std::string why =
        std::string("the MQTT broker refused the connection: ") + mosquitto_connack_string(rc);
    SetProblem(why);
    spdlog::error("vda5050: {}", why);
    return;
  }
  ++connects_;
  connected_ = true;
  spdlog::info("vda5050: connected to {}:{}", options_.host, options_.port);
  PublishConnection("ONLINE", 1);
}

void Vda5050Publisher::OnDisconnect(int rc) {
  const bool was = connected_.exchange(false);
  if (rc == 0) return;  // our own disconnect
  if (was) ++losses_;
  const std::string why = "lost the connection to the MQTT broker " + options_.host + ":" +
                          std::to_string(options_.port) + " (reconnecting)";
  SetProblem(why);
  if (was) spdlog::warn("vda5050: {}", why);
}

void Vda5050Publisher::PublishConnection(const char* state, int qos) {
  const std::string text = io::DumpJson(ConnectionMessage(
      options_.header, connection_serial_, connection_header_id_++, WallNow(), state));
  const std::string topic = Vda5050Topic(options_.header, connection_serial_, "connection");
  if (mosquitto_publish(client_, nullptr, topic.c_str(), static_cast<int>(text.size()), text.data(),
                        qos, true) != MOSQ_ERR_SUCCESS) {
    ++publish_errors_;
  }
}

bool Vda5050Publisher::Due(double now) {
  if (now < next_publish_) return false;
  next_publish_ = std::max(next_publish_ + 1.0 / options_.rate_hz, now);
  return true;
}

std::string Vda5050Publisher::SerialOf(const std::string& vehicle_id) const {
  auto it = options_.serial_numbers.find(vehicle_id);
  return it == options_.serial_numbers.end() ? vehicle_id : it->second;
}

void Vda5050Publisher::Publish(const std::vector<LatestPose>& vehicles,
                               const std::string& mosaic_id, double now) {
  for (const LatestPose& v : vehicles) {
    if (now - v.last_seen > options_.max_pose_age_s) continue;
    if (!connected_) {
      ++dropped_;
      continue;
    }
    auto previous = previous_.find(v.vehicle_id);
    const std::optional<Velocity> velocity =
        previous == previous_.end() ? std::nullopt : VelocityBetween(previous->second, v.pose);
    const std::string serial = SerialOf(v.vehicle_id);
    const std::string text = io::DumpJson(VisualizationMessage(
        options_.header, serial, header_ids_[v.vehicle_id]++, now, v.pose, mosaic_id, velocity));
    const std::string topic = Vda5050Topic(options_.header, serial, "visualization");
    const int rc = mosquitto_publish(client_, nullptr, topic.c_str(), static_cast<int>(text.size()),
                                     text.data(), 0, false);
    if (rc == MOSQ_ERR_SUCCESS) {
      ++published_;
    } else {
      ++(rc == MOSQ_ERR_NO_CONN ? dropped_ : publish_errors_);
    }
    previous_[v.vehicle_id] = v.pose;
  }
}

std::vector<std::pair<std::string, std::uint64_t>> Vda5050Publisher::Counters() const {
  return {{"vda5050_published", published_},           {"vda5050_dropped", dropped_},
          {"vda5050_publish_errors", publish_errors_}, {"vda5050_connects", connects_},
          {"vda5050_connection_losses", losses_},      {"vda5050_refused", refused_}};
}

}  // namespace fleetloc::fleet_supervisor
