#pragma once
// The viewer's HTTP server (Debian's cpp-httplib): the page and its scripts from
// ViewerOptions::web_dir (index.html, viewer.js, node_modules/three installed by `npm ci` in
// tools/web: nothing is fetched from the internet), the hub's events as server-sent events on
// /events, and the newest event of each name as one JSON object on /snapshot.
//
// Threads: the listening thread (started by the constructor, joined by Stop) and cpp-httplib's
// pool, one pool thread per open request. An /events request waits on the hub's condition
// variable (EventHub::WaitNewer, woken by a new event or by Close); it writes to its socket with
// no lock held. Stop() closes the hub first, so every waiting stream ends, then the server.

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "viewer/event_hub.h"
#include "viewer/viewer_options.h"

namespace httplib {
class Server;
}

namespace esdslam {

class ViewerServer {
 public:
  // Binds options.address:options.port (port 0: any free port) and starts listening. Throws
  // Error when the address cannot be bound or web_dir has no index.html; warns when three.js is
  // missing (npm ci in tools/web).
  ViewerServer(const ViewerOptions& options, EventHub* hub);
  ~ViewerServer();
  ViewerServer(const ViewerServer&) = delete;
  ViewerServer& operator=(const ViewerServer&) = delete;

  int port() const { return port_; }
  std::string url() const;  // http://ADDRESS:PORT/
  // Idempotent.
  void Stop();

 private:
  void AddRoutes();
  void MarkStarted();

  const ViewerOptions options_;
  EventHub* hub_;
  std::unique_ptr<httplib::Server> server_;
  int port_ = 0;
  // Set by the listening thread once it serves (or gave up): Stop() before that would be lost
  // (cpp-httplib ignores a stop before its accept loop runs), so the constructor waits for it.
  std::mutex started_mutex_;
  std::condition_variable started_cv_;
  bool started_ = false;
  std::thread listener_;
};

}  // namespace esdslam
