// EventStream: newest snapshot with a sequence number.
#include "fleet_supervisor/event_stream.h"

namespace fleetloc::fleet_supervisor {

void EventStream::Publish(std::string data) {
  std::function<void()> listener;
  {
    std::lock_guard lock(mutex_);
    data_ = std::make_shared<const std::string>(std::move(data));
    ++seq_;
    listener = listener_;
  }
  changed_.notify_all();
  if (listener) listener();
}

std::pair<uint64_t, std::shared_ptr<const std::string>> EventStream::Latest() const {
  std::lock_guard lock(mutex_);
  return {seq_, data_};
}

void EventStream::SetListener(std::function<void()> listener) {
  std::lock_guard lock(mutex_);
  listener_ = std::move(listener);
}

bool EventStream::WaitNewer(uint64_t* seq, std::shared_ptr<const std::string>* data,
                            std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  if (!changed_.wait_for(lock, timeout, [&] { return closed_ || seq_ > *seq; }) || closed_)
    return false;
  *seq = seq_;
  *data = data_;
  return true;
}

void EventStream::Close() {
  std::function<void()> listener;
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
    listener = listener_;
  }
  changed_.notify_all();
  if (listener) listener();
}

bool EventStream::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

}  // namespace fleetloc::fleet_supervisor
