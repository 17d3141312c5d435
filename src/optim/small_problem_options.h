#pragma once
// Ceres settings for the small, dense problems solved inline on a caller's thread (a single
// pose, a relative pose): dense QR, one thread, no logging, at most `iterations` iterations.
#include <ceres/ceres.h>

namespace esdslam {

inline ceres::Solver::Options SmallProblemOptions(int iterations) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  return options;
}

}  // namespace esdslam
