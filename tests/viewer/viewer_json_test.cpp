#include "viewer/viewer_json.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace esdslam {
namespace {

std::vector<std::uint8_t> Bytes(const std::string& text) { return {text.begin(), text.end()}; }

TEST(ViewerJson, Base64MatchesTheRfc4648Examples) {
  EXPECT_EQ(Base64(Bytes("")), "");
  EXPECT_EQ(Base64(Bytes("f")), "Zg==");
  EXPECT_EQ(Base64(Bytes("fo")), "Zm8=");
  EXPECT_EQ(Base64(Bytes("foo")), "Zm9v");
  EXPECT_EQ(Base64(Bytes("foob")), "Zm9vYg==");
  EXPECT_EQ(Base64(Bytes("fooba")), "Zm9vYmE=");
  EXPECT_EQ(Base64(Bytes("foobar")), "Zm9vYmFy");
  EXPECT_EQ(Base64({0xff, 0xfe, 0x00}), "//4A");
}

TEST(ViewerJson, EvenSampleKeepsEverythingUnderTheLimit) {
  const std::vector<std::size_t> all = EvenSample(5, 10);
  EXPECT_EQ(all, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  EXPECT_TRUE(EvenSample(0, 10).empty());
  EXPECT_TRUE(EvenSample(10, 0).empty());
}

TEST(ViewerJson, EvenSampleThinsEvenlyOverTheWholeRange) {
  const std::vector<std::size_t> picked = EvenSample(1000, 10);
  ASSERT_EQ(picked.size(), 10u);
  EXPECT_EQ(picked.front(), 0u);
  for (std::size_t k = 0; k < picked.size(); ++k) EXPECT_EQ(picked[k], k * 100);
  const std::vector<std::size_t> odd = EvenSample(7, 3);
  ASSERT_EQ(odd.size(), 3u);
  EXPECT_LT(odd[0], odd[1]);
  EXPECT_LT(odd[1], odd[2]);
  EXPECT_LT(odd[2], 7u);
}

TEST(ViewerJson, WritesNestedObjectsArraysAndEscapedStrings) {
  JsonText json;
  json.BeginObject().Integer("a", 3).Number("b", 1.23456, 2).Bool("c", true).String("d", "x\"y\\z\n");
  json.BeginArray("e").Element(1, 0).Element(2.5, 1).EndArray();
  json.Key("f").BeginObject().Number("g", std::numeric_limits<double>::quiet_NaN()).EndObject();
  json.BeginArray("h").BeginObject().Integer("i", 1).EndObject().BeginObject().EndObject().EndArray();
  json.Raw("j", "[1]").EndObject();
  EXPECT_EQ(json.str(),
            "{\"a\":3,\"b\":1.23,\"c\":true,\"d\":\"x\\\"y\\\\z\\u000a\",\"e\":[1,2.5],\"f\":{\"g\":null},"
            "\"h\":[{\"i\":1},{}],\"j\":[1]}");
}

}  // namespace
}  // namespace esdslam
