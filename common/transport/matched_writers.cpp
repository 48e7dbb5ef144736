// Matched writers' partitions and user data, looked up once per writer.
#include "transport/matched_writers.h"

#include <algorithm>

namespace fleetloc::transport {
namespace {

WriterFacts FactsOf(const dds_qos_t* qos) {
  WriterFacts facts;
  if (qos == nullptr) return facts;
  uint32_t n = 0;
  char** names = nullptr;
  if (dds_qget_partition(qos, &n, &names)) {
    for (uint32_t i = 0; i < n; ++i) {
      facts.partitions.emplace_back(names[i]);
      dds_free(names[i]);
    }
    dds_free(names);
  }
  void* data = nullptr;
  size_t size = 0;
  if (dds_qget_userdata(qos, &data, &size) && data != nullptr) {
    facts.user_data.assign(static_cast<const char*>(data), size);
    dds_free(data);
  }
  return facts;
}

}  // namespace

void MatchedWriters::LearnNew() {
  dds_subscription_matched_status_t status{};
  if (dds_get_subscription_matched_status(reader_, &status) < 0) return;
  if (status.total_count == matched_total_) return;
  matched_total_ = status.total_count;
  std::vector<dds_instance_handle_t> writers(status.current_count + 16);
  const dds_return_t n = dds_get_matched_publications(reader_, writers.data(), writers.size());
  for (dds_return_t i = 0; i < std::min<dds_return_t>(n, static_cast<dds_return_t>(writers.size()));
       ++i) {
    (void)Find(writers[i]);
  }
}

const WriterFacts* MatchedWriters::Find(dds_instance_handle_t writer) {
  if (auto it = writers_.find(writer); it != writers_.end()) return &it->second;
  dds_builtintopic_endpoint_t* endpoint = dds_get_matched_publication_data(reader_, writer);
  if (endpoint == nullptr) return nullptr;
  WriterFacts facts = FactsOf(endpoint->qos);
  dds_builtintopic_free_endpoint(endpoint);
  if (writers_.size() >= kMaxWriters) writers_.clear();
  return &writers_.emplace(writer, std::move(facts)).first->second;
}

}  // namespace fleetloc::transport
