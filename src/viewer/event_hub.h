#pragma once
// The viewer's latest events, shared between the viewer thread (which publishes them) and the
// HTTP threads (one per browser, which stream them as server-sent events).
//
// Newest wins: the hub keeps only the last event of each name ("frame", "map", "status"). A
// browser that is slow to read gets, when it is ready again, the newest event of each name and
// never the ones in between, so a slow browser never holds memory or the viewer thread back.
// Events are numbered in publication order (seq, from 1); a reader remembers the last number it
// has sent.
//
// Threads: mutex_ is a leaf (held only to copy or replace strings, never while writing to a
// socket). Close() wakes every waiting reader for good.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace esdslam {

struct HubEvent {
  std::string name;  // SSE event name, no newline
  std::string data;  // one line (JSON), no newline
  std::uint64_t seq = 0;
};

class EventHub {
 public:
  // Replaces the previous event named `name`. After Close: ignored.
  void Publish(const std::string& name, std::string data);
  // Waits (condition variable, up to `timeout`) until an event newer than *seen exists or the hub
  // is closed; returns the newer events in seq order and sets *seen to the newest one's seq.
  // Empty: timed out (the caller sends a keep-alive) or closed.
  std::vector<HubEvent> WaitNewer(std::uint64_t* seen, std::chrono::milliseconds timeout);
  // The newest event of every name, in seq order (a snapshot for a plain request).
  std::vector<HubEvent> Latest() const;
  void Close();
  bool closed() const;
  // Events published, and of those replaced before any reader asked for them (dropped).
  std::uint64_t published() const;
  std::uint64_t unread_replaced() const;

 private:
  std::vector<HubEvent> NewerLocked(std::uint64_t seen) const;

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::string, HubEvent> latest_;
  std::uint64_t seq_ = 0;
  std::uint64_t read_seq_ = 0;  // the newest seq any reader has taken
  std::uint64_t unread_replaced_ = 0;
  bool closed_ = false;
};

// One server-sent event: "event: NAME\ndata: DATA\n\n".
std::string FormatServerSentEvent(const HubEvent& event);
// Every event as one JSON object {"NAME": DATA, ...} (DATA is JSON already).
std::string EventsAsJson(const std::vector<HubEvent>& events);

}  // namespace esdslam
