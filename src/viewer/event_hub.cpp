#include "viewer/event_hub.h"

#include <algorithm>

namespace esdslam {

void EventHub::Publish(const std::string& name, std::string data) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return;
    HubEvent& slot = latest_[name];
    if (slot.seq > read_seq_) ++unread_replaced_;  // nobody took the one it replaces
    slot.name = name;
    slot.data = std::move(data);
    slot.seq = ++seq_;
  }
  changed_.notify_all();
}

std::vector<HubEvent> EventHub::NewerLocked(std::uint64_t seen) const {
  std::vector<HubEvent> events;
  for (const auto& entry : latest_)
    if (entry.second.seq > seen) events.push_back(entry.second);
  std::sort(events.begin(), events.end(), [](const HubEvent& a, const HubEvent& b) { return a.seq < b.seq; });
  return events;
}

std::vector<HubEvent> EventHub::WaitNewer(std::uint64_t* seen, std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return closed_ || seq_ > *seen; });
  if (closed_) return {};
  std::vector<HubEvent> events = NewerLocked(*seen);
  if (!events.empty()) {
    *seen = events.back().seq;
    read_seq_ = std::max(read_seq_, *seen);
  }
  return events;
}

std::vector<HubEvent> EventHub::Latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return NewerLocked(0);
}

void EventHub::Close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

bool EventHub::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

std::uint64_t EventHub::published() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return seq_;
}

std::uint64_t EventHub::unread_replaced() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return unread_replaced_;
}

std::string FormatServerSentEvent(const HubEvent& event) {
  std::string text;
  text.reserve(event.name.size() + event.data.size() + 16);
  text += "event: ";
  text += event.name;
  text += "\ndata: ";
  text += event.data;
  text += "\n\n";
  return text;
}

std::string EventsAsJson(const std::vector<HubEvent>& events) {
  std::string json = "{";
  for (const HubEvent& event : events) {
    if (json.size() > 1) json += ',';
    json += '"';
    json += event.name;
    json += "\":";
    json += event.data;
  }
  json += '}';
  return json;
}

}  // namespace esdslam
