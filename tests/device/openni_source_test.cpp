// The OpenNI2 source without hardware (none is attached here or in CI): opening the first device
// fails with an error that says no device is attached and what to do, a URI naming no device
// fails naming it, a missing recording names the file, and a build without OpenNI2 says so.
#include <string>

#include <gtest/gtest.h>

#include "common/error.h"
#include "device/openni_source.h"

namespace esdslam {
namespace {

std::string OpenError(const OpenNiOptions& options) {
  try {
    OpenOpenNiSource(options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(OpenNiSourceTest, NoDeviceAttachedIsAClearError) {
  const std::string message = OpenError({});
  if (HaveOpenNi()) {
    EXPECT_TRUE(Contains(message, "no OpenNI2 device attached")) << message;
    EXPECT_TRUE(Contains(message, "--camera FILE.oni")) << message;
  } else {
    EXPECT_TRUE(Contains(message, "built without OpenNI2")) << message;
    EXPECT_TRUE(Contains(message, "libopenni2-dev")) << message;
  }
}

TEST(OpenNiSourceTest, AUriNamingNoDeviceIsNamedInTheError) {
  OpenNiOptions options;
  options.uri = "2bc5/0401@9/9";
  const std::string message = OpenError(options);
  EXPECT_TRUE(Contains(message, HaveOpenNi() ? "cannot open OpenNI2 device '2bc5/0401@9/9'" : "built without OpenNI2"))
      << message;
}

TEST(OpenNiSourceTest, AMissingRecordingNamesTheFile) {
  OpenNiOptions options;
  options.uri = "/nonexistent/walk.ONI";
  try {
    OpenOpenNiSource(options);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), options.uri);
  }
}

TEST(OpenNiSourceTest, OptionsAreChecked) {
  OpenNiOptions options;
  EXPECT_NO_THROW(options.Check());
  options.fps = 0;
  EXPECT_THROW(options.Check(), Error);
  options = {};
  options.width = -640;
  EXPECT_THROW(OpenOpenNiSource(options), Error);
  EXPECT_EQ(ParseDepthRegistration("off"), DepthRegistration::kOff);
  EXPECT_THROW(ParseDepthRegistration("hardware"), Error);
}

}  // namespace
}  // namespace esdslam
