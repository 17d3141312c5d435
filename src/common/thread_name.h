#pragma once
// Names the calling thread for the system's tools (top -H, perf, gdb, /proc/PID/task/TID/comm).
// Linux keeps at most 15 characters; longer names are cut. Does nothing where unsupported.

#include <string>

namespace esdslam {

void NameThisThread(const std::string& name);

}  // namespace esdslam
