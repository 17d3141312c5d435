#include "viewer/viewer_server.h"

#include <sys/socket.h>

#include <chrono>
#include <filesystem>

#include <httplib.h>
#include <spdlog/spdlog.h>

#include "common/error.h"

namespace esdslam {
namespace {

// A stream with nothing new sends an SSE comment this often (ms), so that the browser and any
// proxy keep the connection, and a closed browser is noticed by the failed write.
constexpr std::chrono::milliseconds kKeepAlive(15000);
// HTTP threads: each open event stream holds one; a page needs one more for its files.
constexpr std::size_t kHttpThreads = 4;

}  // namespace

ViewerServer::ViewerServer(const ViewerOptions& options, EventHub* hub)
    : options_(options), hub_(hub), server_(std::make_unique<httplib::Server>()) {
  options_.Check();
  const std::filesystem::path web(options_.web_dir);
  if (!std::filesystem::exists(web / "index.html"))
    throw Error("viewer: " + (web / "index.html").string() + " is missing (give the tools/web folder)");
  if (!std::filesystem::exists(web / "node_modules/three/build/three.module.js"))
    spdlog::warn("viewer: three.js is not installed in {}: run `npm ci --prefix {}` (tools/install_deps.sh does)",
                 web.string(), web.string());
  AddRoutes();
  // SO_REUSEADDR only: cpp-httplib's default, SO_REUSEPORT, would let a second program bind the
  // same port (and share its connections) instead of failing with "in use".
  server_->set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  if (options_.port == 0) {
    port_ = server_->bind_to_any_port(options_.address);
  } else {
    port_ = server_->bind_to_port(options_.address, options_.port) ? options_.port : -1;
  }
  if (port_ <= 0)
    throw Error("viewer: cannot listen on " + options_.address + ":" + std::to_string(options_.port) +
                " (in use? give another port)");
  // cpp-httplib makes its task queue inside listen_after_bind, after it marked itself running
  // and before its accept loop: from then on stop() takes effect.
  server_->new_task_queue = [this] {
    MarkStarted();
    return new httplib::ThreadPool(kHttpThreads);
  };
  listener_ = std::thread([this] {
    if (!server_->listen_after_bind()) spdlog::error("viewer: the HTTP server stopped with an error");
    MarkStarted();  // in case it failed before making its queue
  });
  std::unique_lock<std::mutex> lock(started_mutex_);
  started_cv_.wait(lock, [this] { return started_; });
}

void ViewerServer::MarkStarted() {
  {
    std::lock_guard<std::mutex> lock(started_mutex_);
    started_ = true;
  }
  started_cv_.notify_all();
}

ViewerServer::~ViewerServer() { Stop(); }

std::string ViewerServer::url() const { return "http://" + options_.address + ":" + std::to_string(port_) + "/"; }

void ViewerServer::Stop() {
  hub_->Close();  // ends every event stream's wait
  if (server_) server_->stop();
  if (listener_.joinable()) listener_.join();
}

void ViewerServer::AddRoutes() {
  server_->set_mount_point("/", options_.web_dir);
  EventHub* hub = hub_;
  server_->Get("/snapshot", [hub](const httplib::Request&, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    res.set_content(EventsAsJson(hub->Latest()), "application/json");
  });
  server_->Get("/events", [hub](const httplib::Request&, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    auto seen = std::make_shared<std::uint64_t>(0);
    res.set_chunked_content_provider("text/event-stream", [hub, seen](std::size_t, httplib::DataSink& sink) {
      const std::vector<HubEvent> events = hub->WaitNewer(seen.get(), kKeepAlive);
      if (hub->closed()) {
        sink.done();
        return false;
      }
      if (events.empty()) return sink.write(": keep-alive\n\n", 14);
      for (const HubEvent& event : events) {
        const std::string text = FormatServerSentEvent(event);
        if (!sink.write(text.data(), text.size())) return false;  // the browser went away
      }
      return true;
    });
  });
}

}  // namespace esdslam
