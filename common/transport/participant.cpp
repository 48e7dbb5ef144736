// Participants on explicitly configured domains.
#include "transport/participant.h"

#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "transport/loopback_config.h"  // generated: kLoopbackXml

namespace fleetloc::transport {

namespace {

// The domains this process created, so a second participant joins instead of re-creating.
std::mutex domains_mutex;
std::map<uint32_t, std::weak_ptr<Entity>> domains;

Result<std::shared_ptr<Entity>> AcquireDomain(uint32_t domain_id, const std::string& xml) {
  std::lock_guard lock(domains_mutex);
  if (auto existing = domains[domain_id].lock()) return existing;
  const char* config = xml.empty() ? nullptr : xml.c_str();
  Result<Entity> domain =
      Adopt(dds_create_domain(domain_id, config),
            "DDS domain " + std::to_string(domain_id) + " (check the Cyclone configuration)");
  if (!domain.ok()) return domain.status();
  auto shared = std::make_shared<Entity>(std::move(domain).value());
  domains[domain_id] = shared;
  return shared;
}

}  // namespace

const std::string& DefaultLoopbackXml() {
  static const std::string xml(kLoopbackXml);
  return xml;
}

Result<std::string> ResolveConfigXml(const DdsConfig& config) {
  if (!config.xml.empty()) return config.xml;
  if (!config.path.empty()) {
    std::ifstream in(config.path);
    if (!in) return NotFound(config.path + ": cannot read the DDS configuration");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  if (std::getenv("CYCLONEDDS_URI") != nullptr) return std::string();
  return DefaultLoopbackXml();
}

Result<Participant> Participant::Create(uint32_t domain_id, const DdsConfig& config) {
  Result<std::string> xml = ResolveConfigXml(config);
  if (!xml.ok()) return xml.status();
  Result<std::shared_ptr<Entity>> domain = AcquireDomain(domain_id, *xml);
  if (!domain.ok()) return domain.status();
  Result<Entity> participant = Adopt(dds_create_participant(domain_id, nullptr, nullptr),
                                     "DDS participant on domain " + std::to_string(domain_id));
  if (!participant.ok()) return participant.status();
  return Participant(domain_id, std::move(domain).value(), std::move(participant).value());
}

Result<Entity> Participant::CreatePublisher(const std::vector<std::string>& partitions) const {
  Qos qos;
  if (!partitions.empty()) qos.Partitions(partitions);
  return Adopt(dds_create_publisher(get(), qos.get(), nullptr), "DDS publisher");
}

Result<Entity> Participant::CreateSubscriber(const std::vector<std::string>& partitions) const {
  Qos qos;
  if (!partitions.empty()) qos.Partitions(partitions);
  return Adopt(dds_create_subscriber(get(), qos.get(), nullptr), "DDS subscriber");
}

}  // namespace fleetloc::transport
