// The Python module `esdslam` (pybind11) over the public C++ API (include/esdslam/esdslam.h):
//   slam = esdslam.System("settings.yaml", single_thread=True)
//   pose = slam.track(image, depth, t, mask=None)   # 4x4 world_from_cam (numpy) or None
//   t, poses = slam.trajectory()                     # (N,), (N, 4, 4)
// Images are numpy arrays: image HxWx3 uint8 (BGR as cv2.imread gives it; rgb=True for RGB) or
// HxW uint8 grey; depth HxW float32 metres or uint16 in the settings' DepthMapFactor units; mask
// and labels HxW uint8. The GIL is released while a frame is tracked.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <opencv2/imgproc.hpp>

#include "esdslam/esdslam.h"

namespace py = pybind11;

namespace {

// A cv::Mat header over a C-contiguous numpy array (no copy; the array outlives the call).
cv::Mat MatOf(const py::array& array, const char* name) {
  if (array.ndim() != 2 && array.ndim() != 3) throw py::value_error(std::string(name) + " must be HxW or HxWxC");
  if (!(array.flags() & py::array::c_style)) throw py::value_error(std::string(name) + " must be C-contiguous");
  const int channels = array.ndim() == 3 ? static_cast<int>(array.shape(2)) : 1;
  int depth = -1;
  if (array.dtype().is(py::dtype::of<std::uint8_t>())) depth = CV_8U;
  else if (array.dtype().is(py::dtype::of<std::uint16_t>())) depth = CV_16U;
  else if (array.dtype().is(py::dtype::of<float>())) depth = CV_32F;
  if (depth < 0) throw py::value_error(std::string(name) + " must be uint8, uint16 or float32");
  return cv::Mat(static_cast<int>(array.shape(0)), static_cast<int>(array.shape(1)), CV_MAKETYPE(depth, channels),
                 const_cast<void*>(array.data()));
}

py::array_t<double> PoseArray(const esdslam::Matrix4& m) {
  py::array_t<double> out({4, 4});
  std::copy(m.begin(), m.end(), out.mutable_data());
  return out;
}

// (timestamps (N,), poses (N, 4, 4)) of stamped poses.
template <typename T>
py::tuple PosesOf(const std::vector<T>& poses) {
  py::array_t<double> stamps(static_cast<py::ssize_t>(poses.size()));
  py::array_t<double> matrices({static_cast<py::ssize_t>(poses.size()), py::ssize_t{4}, py::ssize_t{4}});
  for (std::size_t i = 0; i < poses.size(); ++i) {
    stamps.mutable_data()[i] = poses[i].timestamp;
    std::copy(poses[i].world_from_cam.begin(), poses[i].world_from_cam.end(), matrices.mutable_data() + 16 * i);
  }
  return py::make_tuple(stamps, matrices);
}

py::dict StatsOf(const esdslam::TrackResult& r) {
  py::dict d;
  d["status"] = esdslam::StatusName(r.status);
  d["new_keyframe"] = r.new_keyframe;
  d["index"] = r.stats.index;
  d["keypoints"] = r.stats.keypoints;
  d["dynamic_keypoints"] = r.stats.dynamic_keypoints;
  d["inliers"] = r.stats.inliers;
  d["mask_ms"] = r.stats.mask_ms;
  d["extract_ms"] = r.stats.extract_ms;
  d["track_ms"] = r.stats.track_ms;
  d["label_age"] = r.stats.label_age;
  return d;
}

class PySystem {
 public:
  explicit PySystem(const esdslam::SystemConfig& config) : slam_(config) {}

  py::object Track(const py::array& image, const py::array& depth, double timestamp, const py::object& mask,
                   const py::object& labels, bool rgb) {
    cv::Mat bgr = MatOf(image, "image");
    if (rgb && bgr.channels() == 3) {
      cv::Mat converted;
      cv::cvtColor(bgr, converted, cv::COLOR_RGB2BGR);
      bgr = converted;
    }
    const cv::Mat depth_mat = MatOf(depth, "depth");
    const cv::Mat mask_mat = mask.is_none() ? cv::Mat() : MatOf(mask.cast<py::array>(), "mask");
    const cv::Mat labels_mat = labels.is_none() ? cv::Mat() : MatOf(labels.cast<py::array>(), "labels");
    {
      py::gil_scoped_release release;
      last_ = slam_.Track(bgr, depth_mat, timestamp, mask_mat, labels_mat);
    }
    if (!last_.has_pose) return py::none();
    return PoseArray(last_.world_from_cam);
  }

  void Shutdown() {
    py::gil_scoped_release release;
    slam_.Shutdown();
  }

  void SetCallbacks(py::object keyframe_added, py::object loop_closed, py::object relocalized) {
    esdslam::Callbacks callbacks;  // called inside Track, where the GIL was released
    if (!keyframe_added.is_none())
      callbacks.keyframe_added = [keyframe_added](const esdslam::KeyFrameInfo& k) {
        py::gil_scoped_acquire gil;
        keyframe_added(k.id, k.timestamp, PoseArray(k.world_from_cam));
      };
    if (!loop_closed.is_none())
      callbacks.loop_closed = [loop_closed](int loops) {
        py::gil_scoped_acquire gil;
        loop_closed(loops);
      };
    if (!relocalized.is_none())
      callbacks.relocalized = [relocalized](const esdslam::TimedPose& p) {
        py::gil_scoped_acquire gil;
        relocalized(p.timestamp, PoseArray(p.world_from_cam));
      };
    slam_.SetCallbacks(std::move(callbacks));
  }

  py::tuple KeyFrames() const {
    const std::vector<esdslam::KeyFrameInfo> keyframes = slam_.KeyFrames();
    py::array_t<long> ids(static_cast<py::ssize_t>(keyframes.size()));
    for (std::size_t i = 0; i < keyframes.size(); ++i) ids.mutable_data()[i] = keyframes[i].id;
    py::tuple poses = PosesOf(keyframes);
    return py::make_tuple(ids, poses[0], poses[1]);
  }

  py::array_t<double> MapPoints() const {
    const std::vector<esdslam::MapPointInfo> points = slam_.MapPoints();
    py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
    for (std::size_t i = 0; i < points.size(); ++i)
      std::copy(points[i].position_world.begin(), points[i].position_world.end(), out.mutable_data() + 3 * i);
    return out;
  }

  esdslam::System& slam() { return slam_; }
  const esdslam::TrackResult& last() const { return last_; }

 private:
  esdslam::System slam_;
  esdslam::TrackResult last_;
};

}  // namespace

PYBIND11_MODULE(esdslam, m) {
  m.doc() = "ESD-SLAM: RGB-D SLAM that keeps moving people out of the pose and the map";
  m.attr("__version__") = esdslam::Version();
  m.def("data_directory", &esdslam::DataDirectory, "Where the installed models and settings are");
  py::class_<PySystem>(m, "System")
      .def(py::init([](const std::string& settings, const std::string& settings_text, const std::string& mode,
                       int segment_every, bool label_input, std::vector<std::string> label_classes, bool single_thread,
                       bool relocalization, bool loop_closing, std::uint32_t seed, bool dense,
                       const std::string& load_map, bool localization, const std::string& out_dir,
                       int viewer_port) {
             esdslam::SystemConfig c;
             c.settings_file = settings, c.settings_text = settings_text, c.mode = mode;
             c.segment_every = segment_every, c.label_input = label_input, c.label_classes = std::move(label_classes);
             c.single_thread = single_thread, c.relocalization = relocalization, c.loop_closing = loop_closing;
             c.seed = seed, c.dense = dense, c.load_map = load_map, c.localization = localization, c.out_dir = out_dir;
             c.viewer_port = viewer_port;
             return std::make_unique<PySystem>(c);
           }),
           py::arg("settings") = "", py::kw_only(), py::arg("settings_text") = "", py::arg("mode") = "full",
           py::arg("segment_every") = 0, py::arg("label_input") = false,
           py::arg("label_classes") = std::vector<std::string>{}, py::arg("single_thread") = false,
           py::arg("relocalization") = true, py::arg("loop_closing") = true, py::arg("seed") = 1,
           py::arg("dense") = false, py::arg("load_map") = "", py::arg("localization") = false,
           py::arg("out_dir") = "", py::arg("viewer_port") = -1,
           "Builds the system from a settings file (or settings_text); options as esdslam::SystemConfig")
      .def("track", &PySystem::Track, py::arg("image"), py::arg("depth"), py::arg("timestamp"),
           py::arg("mask") = py::none(), py::arg("labels") = py::none(), py::arg("rgb") = false,
           "Tracks one frame; returns the 4x4 world_from_cam pose, or None when the frame got no pose")
      .def("shutdown", &PySystem::Shutdown, "Finishes every thread and writes the outputs (out_dir)")
      .def("set_callbacks", &PySystem::SetCallbacks, py::arg("keyframe_added") = py::none(),
           py::arg("loop_closed") = py::none(), py::arg("relocalized") = py::none())
      .def("trajectory", [](const PySystem& s) { return PosesOf(const_cast<PySystem&>(s).slam().Trajectory()); },
           "(timestamps (N,), world_from_cam (N, 4, 4)) of every frame with a pose")
      .def("keyframes", &PySystem::KeyFrames, "(ids (N,), timestamps (N,), world_from_cam (N, 4, 4))")
      .def("map_points", &PySystem::MapPoints, "positions of the live map points, (N, 3) metres")
      .def("save_map", [](PySystem& s, const std::string& path) { s.slam().SaveMap(path); })
      .def_property_readonly("viewer_url", [](PySystem& s) { return s.slam().ViewerUrl(); })
      .def_property_readonly("status", [](PySystem& s) { return esdslam::StatusName(s.slam().status()); })
      .def_property_readonly("last_stats", [](const PySystem& s) { return StatsOf(s.last()); })
      .def("effective_settings", [](PySystem& s) { return s.slam().EffectiveSettings(); });
}
