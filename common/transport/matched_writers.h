// What a reader knows of the writers it is matched with: their partitions and user data, looked up
// once per writer (dds_get_matched_publication_data) and remembered, so a sample can be traced to
// its writer by the publication handle in its sample info. The vehicle-stream check (which
// partition a vehicle wrote in) and the patch client (which map server acknowledged) use it.
#pragma once

#include <dds/dds.h>

#include <string>
#include <unordered_map>
#include <vector>

namespace fleetloc::transport {

struct WriterFacts {
  std::vector<std::string> partitions;  // of the writer's publisher
  std::string user_data;                // the writer's USER_DATA QoS, as bytes
};

class MatchedWriters {
 public:
  explicit MatchedWriters(dds_entity_t reader) : reader_(reader) {}
  // Looks up the writers matched since the last call, so that the samples of a writer that goes
  // away before they are taken can still be traced. Call before each take.
  void LearnNew();
  // The facts of `writer`, or nullptr when it is not known (matched and gone again between two
  // LearnNew calls). The pointer is valid until the next call.
  const WriterFacts* Find(dds_instance_handle_t writer);

 private:
  static constexpr size_t kMaxWriters = 4096;  // forgets every writer past this many
  dds_entity_t reader_;
  uint32_t matched_total_ = 0;  // writers ever matched, when last learned
  std::unordered_map<dds_instance_handle_t, WriterFacts> writers_;
};

}  // namespace fleetloc::transport
