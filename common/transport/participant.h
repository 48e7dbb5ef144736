// A DDS domain participant on a domain configured from Cyclone XML: the compiled-in loopback
// default (deploy/cyclonedds/loopback.xml), a file, or CYCLONEDDS_URI. Several participants of one
// process may share a domain; the domain is deleted with the last of them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "base/status.h"
#include "transport/dds_entity.h"
#include "transport/qos.h"

namespace fleetloc::transport {

// Where the Cyclone configuration comes from, in this order: `xml` if non-empty; the file `path`
// if non-empty; the CYCLONEDDS_URI environment variable if set; the compiled-in loopback default.
struct DdsConfig {
  std::string xml;
  std::string path;
};

// The compiled-in copy of deploy/cyclonedds/loopback.xml.
const std::string& DefaultLoopbackXml();

// Reads the configuration text chosen by `config` (empty when CYCLONEDDS_URI is to be used).
// NotFound / Internal naming the file when `path` cannot be read.
Result<std::string> ResolveConfigXml(const DdsConfig& config);

class Participant {
 public:
  // Creates (or joins, if this process already created it) `domain_id` with the configuration and
  // a participant on it. Internal naming the domain if Cyclone rejects the configuration or the
  // participant cannot be created (e.g. no free participant index).
  static Result<Participant> Create(uint32_t domain_id, const DdsConfig& config = {});

  dds_entity_t get() const { return participant_.get(); }
  uint32_t domain_id() const { return domain_id_; }

  // A publisher / subscriber of this participant in the given partitions (none: the default one).
  Result<Entity> CreatePublisher(const std::vector<std::string>& partitions = {}) const;
  Result<Entity> CreateSubscriber(const std::vector<std::string>& partitions = {}) const;

 private:
  Participant(uint32_t domain_id, std::shared_ptr<Entity> domain, Entity participant)
      : domain_id_(domain_id), domain_(std::move(domain)), participant_(std::move(participant)) {}
  uint32_t domain_id_;
  std::shared_ptr<Entity> domain_;  // shared by this process's participants of the domain
  Entity participant_;              // declared after domain_: deleted first
};

}  // namespace fleetloc::transport
