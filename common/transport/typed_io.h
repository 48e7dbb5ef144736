// Typed topics, writers and readers over the Cyclone C API: the only place that casts between
// void* samples and the generated wire types. No business logic.
#pragma once

#include <array>
#include <string>

#include "transport/dds_entity.h"
#include "transport/fleetloc_types.h"
#include "transport/participant.h"
#include "transport/qos.h"

namespace fleetloc::transport {

template <typename T>
class Topic {
 public:
  // Creates (or finds, if this participant has it) the topic `name` of wire type T.
  static Result<Topic> Create(const Participant& participant, const std::string& name) {
    Result<Entity> topic = Adopt(dds_create_topic(participant.get(), DdsType<T>::descriptor(),
                                                  name.c_str(), nullptr, nullptr),
                                 "DDS topic " + name);
    if (!topic.ok()) return topic.status();
    return Topic(std::move(topic).value(), name);
  }
  dds_entity_t get() const { return topic_.get(); }
  const std::string& name() const { return name_; }

 private:
  Topic(Entity topic, std::string name) : topic_(std::move(topic)), name_(std::move(name)) {}
  Entity topic_;
  std::string name_;
};

template <typename T>
class Writer {
 public:
  // `parent`: a participant or a publisher (whose partitions the writer then uses).
  static Result<Writer> Create(dds_entity_t parent, const Topic<T>& topic, const Qos& qos) {
    Result<Entity> writer = Adopt(dds_create_writer(parent, topic.get(), qos.get(), nullptr),
                                  "DDS writer of " + topic.name());
    if (!writer.ok()) return writer.status();
    return Writer(std::move(writer).value(), topic.name());
  }
  Status Write(const T& sample) const {
    return DdsStatus(dds_write(writer_.get(), &sample), "write to " + topic_name_);
  }
  // Ends this writer's interest in the sample's instance (frees its history for that key).
  Status Unregister(const T& key_sample) const {
    return DdsStatus(dds_unregister_instance(writer_.get(), &key_sample),
                     "unregister on " + topic_name_);
  }
  // Number of readers currently matched (0 when nobody listens).
  int MatchedReaders() const {
    dds_publication_matched_status_t status{};
    if (dds_get_publication_matched_status(writer_.get(), &status) < 0) return 0;
    return static_cast<int>(status.current_count);
  }
  dds_entity_t get() const { return writer_.get(); }

 private:
  Writer(Entity writer, std::string topic_name)
      : writer_(std::move(writer)), topic_name_(std::move(topic_name)) {}
  Entity writer_;
  std::string topic_name_;
};

template <typename T>
class Reader {
 public:
  // `parent`: a participant or a subscriber (whose partitions the reader then uses).
  static Result<Reader> Create(dds_entity_t parent, const Topic<T>& topic, const Qos& qos) {
    Result<Entity> reader = Adopt(dds_create_reader(parent, topic.get(), qos.get(), nullptr),
                                  "DDS reader of " + topic.name());
    if (!reader.ok()) return reader.status();
    return Reader(std::move(reader).value(), topic.name());
  }

  // Takes up to kBatch samples and calls fn(const T&, const dds_sample_info_t&) for each one that
  // carries data (disposals and unregistrations are skipped). Returns the number of samples taken
  // (with or without data); Internal if the take fails. fn must not throw.
  template <typename Fn>
  Result<int> Take(Fn&& fn) const {
    static constexpr int kBatch = 32;
    std::array<void*, kBatch> samples{};
    std::array<dds_sample_info_t, kBatch> infos{};
    const dds_return_t n = dds_take(reader_.get(), samples.data(), infos.data(), kBatch, kBatch);
    if (n < 0) return DdsStatus(n, "take from " + topic_name_);
    for (int i = 0; i < n; ++i) {
      if (infos[i].valid_data) fn(*static_cast<const T*>(samples[i]), infos[i]);
    }
    dds_return_loan(reader_.get(), samples.data(), n);
    return static_cast<int>(n);
  }
  // Takes every available sample (repeated Take until none is left); returns how many.
  template <typename Fn>
  Result<int> TakeAll(Fn&& fn) const {
    int total = 0;
    for (;;) {
      Result<int> n = Take(fn);
      if (!n.ok()) return n.status();
      total += *n;
      if (*n == 0) return total;
    }
  }
  int MatchedWriters() const {
    dds_subscription_matched_status_t status{};
    if (dds_get_subscription_matched_status(reader_.get(), &status) < 0) return 0;
    return static_cast<int>(status.current_count);
  }
  dds_entity_t get() const { return reader_.get(); }
  const std::string& topic_name() const { return topic_name_; }

 private:
  Reader(Entity reader, std::string topic_name)
      : reader_(std::move(reader)), topic_name_(std::move(topic_name)) {}
  Entity reader_;
  std::string topic_name_;
};

}  // namespace fleetloc::transport
