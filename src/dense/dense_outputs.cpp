#include "dense/dense_outputs.h"

#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "common/timer.h"
#include "dense/cloud_io.h"
#include "dense/map_render.h"
#include "dense/octomap_writer.h"

namespace esdslam {

namespace {

void WritePicture(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image, {cv::IMWRITE_PNG_COMPRESSION, 9})) throw Error("cannot write " + path);
}

}  // namespace

DenseOutputSummary WriteDenseOutputs(const DenseMap& map, const KeyframePoses& poses, const std::string& dir,
                                     const DenseOutputFiles& files) {
  const Stopwatch total;
  std::filesystem::create_directories(dir);
  DenseOutputSummary summary;
  const KeyframePoses resolved = map.Resolve(poses);
  summary.keyframes = resolved.size();
  Stopwatch watch;
  const PointCloud cloud = map.BuildGlobalCloud(resolved);
  summary.cloud_ms = watch.ElapsedMs();
  summary.points = cloud.size();
  if (files.ply) WritePly(dir + "/dense.ply", cloud);
  if (files.pcd || map.options().write_pcd) WritePcd(dir + "/dense.pcd", cloud);
  if (files.octomap) {
    watch.Restart();
    const OctomapStats stats = WriteOctomap(dir + "/octomap.bt", map, resolved, &cloud);
    summary.octomap_ms = watch.ElapsedMs();
    summary.occupied_leaves = stats.occupied_leaves;
    summary.free_leaves = stats.free_leaves;
  }
  if (files.pictures) {
    std::vector<Rigid3> cams;
    for (const auto& entry : resolved) cams.push_back(entry.second);
    MapRenderOptions render;
    render.point_spacing = map.options().voxel_size;
    WritePicture(dir + "/dense_top.png", RenderTopView(cloud, cams, render));
    WritePicture(dir + "/dense_view.png", RenderPerspectiveView(cloud, cams, render));
  }
  summary.build_ms = total.ElapsedMs();
  return summary;
}

}  // namespace esdslam
