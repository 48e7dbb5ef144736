// A vehicle's own streams (VehiclePose, VehicleHealth, PatchObservation, TileRequest) travel in
// the vehicle's partition `fleetloc.vehicle.<id>`; receivers subscribe to every vehicle's
// partition (`fleetloc.vehicle.*`). DDS Security grants a vehicle its own partition only
// (docs/security.md), and permissions cannot look into a sample, so every receiver also checks
// that a sample's vehicle_id names the partition its writer writes in: a vehicle cannot speak
// for another one by writing a forged vehicle_id in its own partition. The check holds with or
// without security; a mismatch is rejected and counted, never delivered.
#pragma once

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "transport/matched_writers.h"
#include "transport/typed_io.h"

namespace fleetloc::transport {

// OK when `writer_partitions` is exactly the partition of `vehicle_id`; InvalidInput naming the
// vehicle id and the writer's partitions otherwise.
Status CheckVehiclePartition(const std::string& vehicle_id,
                             const std::vector<std::string>& writer_partitions);

// A publisher in the partition of `vehicle_id` (a valid entity id), for that vehicle's streams.
Result<Entity> CreateVehiclePublisher(const Participant& participant,
                                      const std::string& vehicle_id);
// A subscriber in every vehicle's partition, for the receivers of the vehicles' streams.
Result<Entity> CreateAnyVehicleSubscriber(const Participant& participant);

// Checks the samples of one reader against the partitions of their writers (MatchedWriters).
class VehicleSourceCheck {
 public:
  explicit VehicleSourceCheck(dds_entity_t reader) : writers_(reader) {}
  // Looks up the writers matched since the last call. Call before each take.
  void LearnNewWriters() { writers_.LearnNew(); }
  // OK when the sample's writer (info.publication_handle) writes in exactly the partition of
  // `vehicle_id`; InvalidInput otherwise, or when the writer is unknown (matched and gone again
  // between two takes).
  Status Check(const std::string& vehicle_id, const dds_sample_info_t& info);

 private:
  MatchedWriters writers_;
};

// A writer of one vehicle's stream of type T, through its own publisher in the vehicle's
// partition (the only partition DDS Security lets the vehicle write in).
template <typename T>
class VehicleStreamWriter {
 public:
  static Result<VehicleStreamWriter> Create(const Participant& participant,
                                            const std::string& vehicle_id, const Topic<T>& topic,
                                            const Qos& qos) {
    Result<Entity> publisher = CreateVehiclePublisher(participant, vehicle_id);
    if (!publisher.ok()) return publisher.status();
    Result<Writer<T>> writer = Writer<T>::Create(publisher->get(), topic, qos);
    if (!writer.ok()) return writer.status();
    return VehicleStreamWriter(std::move(publisher).value(), std::move(writer).value());
  }
  Status Write(const T& sample) const { return writer_.Write(sample); }
  int MatchedReaders() const { return writer_.MatchedReaders(); }
  dds_entity_t get() const { return writer_.get(); }

 private:
  VehicleStreamWriter(Entity publisher, Writer<T> writer)
      : publisher_(std::move(publisher)), writer_(std::move(writer)) {}
  Entity publisher_;  // declared first: deleted after the writer
  Writer<T> writer_;
};

// A reader of a vehicle stream of type T (a type with a `vehicle_id`) in every vehicle's
// partition, which delivers only the samples that pass VehicleSourceCheck.
template <typename T>
class VehicleStreamReader {
 public:
  static Result<VehicleStreamReader> Create(const Participant& participant, const Topic<T>& topic,
                                            const Qos& qos) {
    Result<Entity> subscriber = CreateAnyVehicleSubscriber(participant);
    if (!subscriber.ok()) return subscriber.status();
    Result<Reader<T>> reader = Reader<T>::Create(subscriber->get(), topic, qos);
    if (!reader.ok()) return reader.status();
    return VehicleStreamReader(std::move(subscriber).value(), std::move(reader).value());
  }

  // Like Reader::TakeAll: fn(const T&, const dds_sample_info_t&) for each checked sample;
  // rejected(const std::string& message) for each one that fails the check (also counted).
  template <typename Fn, typename Rejected>
  Result<int> TakeAll(Fn&& fn, Rejected&& rejected) {
    check_->LearnNewWriters();
    return reader_.TakeAll([&](const T& sample, const dds_sample_info_t& info) {
      const std::string id(sample.vehicle_id, strnlen(sample.vehicle_id, sizeof sample.vehicle_id));
      if (Status ok = check_->Check(id, info); !ok.ok()) {
        ++rejected_;
        return rejected(ok.message());
      }
      fn(sample, info);
    });
  }
  template <typename Fn>
  Result<int> TakeAll(Fn&& fn) {
    return TakeAll(std::forward<Fn>(fn), [](const std::string&) {});
  }

  uint64_t rejected() const { return rejected_; }
  int MatchedWriters() const { return reader_.MatchedWriters(); }
  dds_entity_t get() const { return reader_.get(); }

 private:
  VehicleStreamReader(Entity subscriber, Reader<T> reader)
      : subscriber_(std::move(subscriber)),
        reader_(std::move(reader)),
        check_(std::make_unique<VehicleSourceCheck>(reader_.get())) {}
  Entity subscriber_;  // declared first: deleted after the reader
  Reader<T> reader_;
  std::unique_ptr<VehicleSourceCheck> check_;
  uint64_t rejected_ = 0;
};

}  // namespace fleetloc::transport
