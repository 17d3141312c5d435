#include "viewer/live_viewer.h"

#include <string>

#include <gtest/gtest.h>
#include <httplib.h>

#include "viewer/viewer_test_frames.h"

namespace esdslam {
namespace {

ViewerOptions FastOptions() {
  ViewerOptions options;
  options.port = 0;  // any free port
  options.frame_interval_ms = 0;
  return options;
}

TEST(LiveViewer, OfferNeverWaitsAndEveryFrameIsEncodedSkippedOrDropped) {
  LiveViewer viewer(FastOptions(), nullptr, nullptr, /*serve=*/false);
  constexpr int kFrames = 200;
  for (int i = 0; i < kFrames; ++i) viewer.Offer(testing::MakeViewerFrame(i));
  viewer.Finish();
  const ViewerStats stats = viewer.stats();
  EXPECT_EQ(stats.offered, kFrames);
  // The viewer thread encodes a 320x240 JPEG per frame, far slower than Offer hands them over:
  // the full queue drops (newest wins) instead of holding the caller.
  EXPECT_GT(stats.dropped, 0);
  EXPECT_EQ(stats.offered, stats.skipped + stats.dropped + stats.encoded - 1);  // + the final frame
  std::uint64_t seen = 0;
  const std::vector<HubEvent> events = viewer.hub().WaitNewer(&seen, std::chrono::milliseconds(0));
  ASSERT_EQ(events.size(), 3u);  // the newest frame, map and status
  EXPECT_EQ(events.back().name, "status");
  bool last_frame = false;
  for (const HubEvent& e : events) last_frame |= e.name == "frame" && e.data.find("\"frames\":200,") != std::string::npos;
  EXPECT_TRUE(last_frame) << "Finish publishes the last frame offered";
}

TEST(LiveViewer, FrameIntervalSkipsFramesOnTheTrackingThread) {
  ViewerOptions options = FastOptions();
  options.frame_interval_ms = 10000;
  LiveViewer viewer(options, nullptr, nullptr, false);
  for (int i = 0; i < 20; ++i) viewer.Offer(testing::MakeViewerFrame(i));
  viewer.Finish();
  const ViewerStats stats = viewer.stats();
  EXPECT_EQ(stats.skipped, 19);  // only the first passes within 10 s
  EXPECT_EQ(stats.encoded, 2);   // it and the final frame
}

TEST(LiveViewer, ServesThePageTheSnapshotAndServerSentEvents) {
  LiveViewer viewer(FastOptions(), nullptr, nullptr, true);
  viewer.Offer(testing::MakeViewerFrame(0));
  viewer.Finish();
  const std::string url = viewer.url();
  ASSERT_EQ(url.rfind("http://127.0.0.1:", 0), 0u) << url;
  const int port = std::stoi(url.substr(17));
  httplib::Client client("127.0.0.1", port);
  const httplib::Result page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("viewer.js"), std::string::npos);
  const httplib::Result snapshot = client.Get("/snapshot");
  ASSERT_TRUE(snapshot);
  EXPECT_EQ(snapshot->body.rfind("{\"frame\":{", 0), 0u) << snapshot->body.substr(0, 80);
  std::string stream;
  const httplib::Result events = client.Get("/events", [&](const char* data, std::size_t size) {
    stream.append(data, size);
    return stream.find("event: status") == std::string::npos;  // stop reading once all three came
  });
  EXPECT_NE(stream.find("event: frame\ndata: {"), std::string::npos);
  EXPECT_NE(stream.find("event: map\ndata: {"), std::string::npos);
  viewer.Close();
}

TEST(LiveViewer, MapPointsCulledAsMovedReachTheMapEvenFromSkippedFrames) {
  ViewerOptions options = FastOptions();
  options.frame_interval_ms = 10000;  // every frame after the first is skipped
  LiveViewer viewer(options, nullptr, nullptr, false);
  for (int i = 0; i < 3; ++i) {
    FrameReport report = testing::MakeViewerFrame(i);
    report.track.geometry.culled_positions.push_back(Vec3(1.5 + i, -0.25, 2.0));
    viewer.Offer(report);
  }
  viewer.Finish();
  std::string map;
  for (const HubEvent& e : viewer.hub().Latest())
    if (e.name == "map") map = e.data;
  EXPECT_NE(map.find("\"culled_points\":[1.500,-0.250,2.000,2.500,-0.250,2.000,3.500,-0.250,2.000]"), std::string::npos)
      << map.substr(0, 300);
}

TEST(ViewerServer, StopsRightAfterItStartedAndRefusesATakenPort) {
  ViewerOptions options = FastOptions();
  for (int i = 0; i < 5; ++i) {  // a stop right after the start is not lost (no hang)
    EventHub hub;
    ViewerServer server(options, &hub);
    EXPECT_GT(server.port(), 0);
    server.Stop();
    EXPECT_TRUE(hub.closed());
  }
  EventHub hub, other_hub;
  ViewerServer server(options, &hub);
  options.port = server.port();
  EXPECT_THROW(ViewerServer(options, &other_hub), Error);
}

TEST(ViewerOptions, CheckBoundsEveryValue) {
  ViewerOptions options;
  EXPECT_NO_THROW(options.Check());
  options.port = 70000;
  EXPECT_THROW(options.Check(), Error);
  options = ViewerOptions();
  options.image_scale = 0;
  EXPECT_THROW(options.Check(), Error);
  options = ViewerOptions();
  options.queue_capacity = 0;
  EXPECT_THROW(options.Check(), Error);
  options = ViewerOptions();
  options.jpeg_quality = 101;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace esdslam
