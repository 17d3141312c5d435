// The one source of the esdslam_pch target (CMakeLists.txt), which exists to build the
// precompiled headers every other target reuses. A static library needs a source file.
namespace esdslam {
int PchAnchor() { return 0; }
}  // namespace esdslam
