#include "dense/cloud_io.h"

#include <cstring>
#include <fstream>
#include <sstream>

#include "common/error.h"

namespace esdslam {

namespace {

std::ofstream OpenForWriting(const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path, 0, "cannot open for writing");
  return out;
}

template <typename T>
void WriteRaw(std::ofstream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

}  // namespace

void WritePly(const std::string& path, const PointCloud& cloud) {
  std::ofstream out = OpenForWriting(path);
  out << "ply\nformat binary_little_endian 1.0\ncomment ESD-SLAM static dense map\n"
      << "element vertex " << cloud.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (int a = 0; a < 3; ++a) WriteRaw(out, cloud.points[i][a]);
    WriteRaw(out, cloud.colors[i].r);
    WriteRaw(out, cloud.colors[i].g);
    WriteRaw(out, cloud.colors[i].b);
  }
  if (!out) throw InputError(path, 0, "write failed");
}

PointCloud ReadPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open");
  std::string line;
  std::size_t count = 0;
  int line_number = 0;
  bool binary = false;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.rfind("format binary_little_endian", 0) == 0) binary = true;
    if (line.rfind("element vertex", 0) == 0) {
      std::istringstream fields(line.substr(14));
      if (!(fields >> count)) throw InputError(path, line_number, "expected a vertex count");
    }
    if (line == "end_header") break;
  }
  if (!binary) throw InputError(path, 0, "expected a binary_little_endian PLY as written by ESD-SLAM");
  PointCloud cloud;
  cloud.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    Eigen::Vector3f p;
    Rgb8 c;
    in.read(reinterpret_cast<char*>(p.data()), 3 * sizeof(float));
    in.read(reinterpret_cast<char*>(&c.r), 1);
    in.read(reinterpret_cast<char*>(&c.g), 1);
    in.read(reinterpret_cast<char*>(&c.b), 1);
    if (!in) throw InputError(path, 0, "file ends before its " + std::to_string(count) + " vertices");
    cloud.push_back(p, c);
  }
  return cloud;
}

void WritePcd(const std::string& path, const PointCloud& cloud) {
  std::ofstream out = OpenForWriting(path);
  out << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\n"
      << "TYPE F F F U\nCOUNT 1 1 1 1\nWIDTH " << cloud.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
      << "POINTS " << cloud.size() << "\nDATA binary\n";
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (int a = 0; a < 3; ++a) WriteRaw(out, cloud.points[i][a]);
    const Rgb8& c = cloud.colors[i];
    const std::uint32_t rgb = (static_cast<std::uint32_t>(c.r) << 16) | (static_cast<std::uint32_t>(c.g) << 8) | c.b;
    WriteRaw(out, rgb);
  }
  if (!out) throw InputError(path, 0, "write failed");
}

}  // namespace esdslam
