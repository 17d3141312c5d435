#include "common/geometry.h"

#include <gtest/gtest.h>

namespace esdslam {
namespace {

TEST(Rigid3, ExpLogRoundTrip) {
  Vec6 twist;
  twist << 0.3, -0.2, 1.5, 0.4, -0.7, 0.2;
  const Rigid3 t = Rigid3::Exp(twist);
  EXPECT_TRUE(t.Log().isApprox(twist, 1e-10));
}

TEST(Rigid3, InverseComposesToIdentity) {
  Vec6 twist;
  twist << 1, 2, 3, 0.1, 0.2, 0.3;
  const Rigid3 t = Rigid3::Exp(twist);
  const Rigid3 id = t * t.inverse();
  EXPECT_LT(id.translation().norm(), 1e-12);
  EXPECT_LT(RotationAngle(id.rotation()), 1e-7);
  const Vec3 p(0.5, -1, 2);
  EXPECT_TRUE((t.inverse() * (t * p)).isApprox(p, 1e-12));
}

TEST(Rigid3, ExpOfPureRotationMatchesAngleAxis) {
  Vec6 twist = Vec6::Zero();
  twist(5) = 0.5;
  const Rigid3 t = Rigid3::Exp(twist);
  EXPECT_NEAR(RotationAngle(t.rotation()), 0.5, 1e-12);
  EXPECT_LT(t.translation().norm(), 1e-15);
}

}  // namespace
}  // namespace esdslam

namespace esdslam {
namespace {
TEST(RotationAngle, PreciseForTinyAngles) {
  const Quat q(Eigen::AngleAxisd(1e-9, Vec3::UnitZ()));
  EXPECT_NEAR(RotationAngle(q), 1e-9, 1e-15);
  EXPECT_NEAR(RotationAngle(Quat(Eigen::AngleAxisd(3.0, Vec3::UnitX()))), 3.0, 1e-12);
}
}  // namespace
}  // namespace esdslam
