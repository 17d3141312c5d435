#pragma once
// Top view (X-Y plane, metres) of a ground-truth and an (aligned) estimated trajectory, with
// axes, a legend and a metre scale bar. The format follows the extension: .svg (text written
// directly) or .png (OpenCV drawing).

#include <string>
#include <vector>

#include "common/geometry.h"

namespace esdslam {

// Throws Error for an unknown extension, no points, or an unwritable file.
void PlotTrajectoriesXY(const std::vector<Vec3>& groundtruth, const std::vector<Vec3>& estimate,
                        const std::string& path);

// The same top view as one standalone <svg> element (what a .svg plot file holds), for
// embedding in a page. Throws Error when both point lists are empty.
std::string TrajectoriesXYSvg(const std::vector<Vec3>& groundtruth, const std::vector<Vec3>& estimate);

}  // namespace esdslam
