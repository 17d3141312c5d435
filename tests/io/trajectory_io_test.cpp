#include "io/trajectory_io.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/error.h"
#include "io/test_files.h"

namespace esdslam {
namespace {

using testing::TempDir;

// Expects ReadTumTrajectory to throw InputError for `path` at `line` with `fragment` in it.
void ExpectInputError(const std::string& path, int line, const std::string& fragment) {
  try {
    ReadTumTrajectory(path);
    FAIL() << "no error for " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(TrajectoryIo, ReadsCommentsBlankLinesAndNormalisesQuaternions) {
  TempDir dir;
  const std::string path = dir.Write("t.txt",
                                     "# comment\n"
                                     "\n"
                                     "1.5 1 2 3 0 0 0 2\n"
                                     "  # indented comment\n"
                                     "2.25\t-1,0.5 0 0 0 0.7071068 0.7071068\n");
  const auto poses = ReadTumTrajectory(path);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_DOUBLE_EQ(poses[0].timestamp, 1.5);
  EXPECT_TRUE(poses[0].world_from_cam.translation().isApprox(Vec3(1, 2, 3)));
  EXPECT_NEAR(poses[0].world_from_cam.rotation().w(), 1.0, 1e-12);  // (0,0,0,2) normalised
  EXPECT_DOUBLE_EQ(poses[1].timestamp, 2.25);
  EXPECT_NEAR(poses[1].world_from_cam.rotation().norm(), 1.0, 1e-12);
  // 90 degrees about z: x axis maps to y.
  EXPECT_TRUE((poses[1].world_from_cam.rotation() * Vec3(1, 0, 0)).isApprox(Vec3(0, 1, 0), 1e-6));
}

TEST(TrajectoryIo, WriteThenReadRoundTrips) {
  TempDir dir;
  std::vector<StampedPose> poses;
  for (int i = 0; i < 5; ++i) {
    StampedPose pose;
    pose.timestamp = 1305031229.528748 + 0.033 * i;
    pose.world_from_cam = Rigid3(Quat(Eigen::AngleAxisd(0.3 * i + 0.1, Vec3(1, 2, 3).normalized())),
                                 Vec3(1.23456789 * i, -0.000123456, 3.3));
    poses.push_back(pose);
  }
  const std::string path = dir.Path("sub/est.txt");
  WriteTumTrajectory(path, poses);
  const auto read = ReadTumTrajectory(path);
  ASSERT_EQ(read.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_NEAR(read[i].timestamp, poses[i].timestamp, 1e-6);
    EXPECT_NEAR((read[i].world_from_cam.translation() - poses[i].world_from_cam.translation()).norm(), 0, 1e-8);
    EXPECT_NEAR(read[i].world_from_cam.rotation().angularDistance(poses[i].world_from_cam.rotation()), 0, 1e-8);
  }
}

TEST(TrajectoryIo, EmptyFileGivesNoPoses) {
  TempDir dir;
  EXPECT_TRUE(ReadTumTrajectory(dir.Write("e.txt", "# only a comment\n")).empty());
}

TEST(TrajectoryIo, MissingFileIsAnInputError) {
  TempDir dir;
  ExpectInputError(dir.Path("nope.txt"), 0, "cannot open");
}

TEST(TrajectoryIo, WrongFieldCountNamesLine) {
  TempDir dir;
  ExpectInputError(dir.Write("t.txt", "# c\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n"), 3, "expected 8 fields");
}

TEST(TrajectoryIo, NonNumericFieldNamesLineAndField) {
  TempDir dir;
  ExpectInputError(dir.Write("t.txt", "1 0 0 0 0 0 0 1\n2 0 abc 0 0 0 0 1\n"), 2, "ty");
  ExpectInputError(dir.Write("u.txt", "1 0 0 0 0 0 0 1x\n"), 1, "qw");
}

TEST(TrajectoryIo, NanOrInfIsRejected) {
  TempDir dir;
  ExpectInputError(dir.Write("t.txt", "1 0 0 nan 0 0 0 1\n"), 1, "finite");
  ExpectInputError(dir.Write("u.txt", "1 0 0 0 0 0 inf 1\n"), 1, "finite");
}

TEST(TrajectoryIo, UnsortedAndDuplicateTimestampsAreRejected) {
  TempDir dir;
  ExpectInputError(dir.Write("t.txt", "1 0 0 0 0 0 0 1\n3 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n"), 3, "not sorted");
  ExpectInputError(dir.Write("u.txt", "1 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n"), 2, "duplicate");
}

TEST(TrajectoryIo, ZeroQuaternionIsRejected) {
  TempDir dir;
  ExpectInputError(dir.Write("t.txt", "1 0 0 0 0 0 0 0\n"), 1, "quaternion");
}

}  // namespace
}  // namespace esdslam
