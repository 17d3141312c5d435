#pragma once
// Point cloud files: binary little-endian PLY (x y z float, red green blue uchar), as read by
// MeshLab, CloudCompare, Open3D and PCL; and PCL's PCD (binary, fields x y z rgb).

#include <string>

#include "dense/point_cloud.h"

namespace esdslam {

void WritePly(const std::string& path, const PointCloud& cloud);
PointCloud ReadPly(const std::string& path);  // reads what WritePly writes
void WritePcd(const std::string& path, const PointCloud& cloud);

}  // namespace esdslam
