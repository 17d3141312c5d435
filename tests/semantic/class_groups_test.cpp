#include "semantic/class_groups.h"

#include <gtest/gtest.h>

#include "common/error.h"
#include "semantic/segmenter.h"

namespace esdslam {
namespace {

TEST(ClassGroups, DefaultsPersonDynamicChairPotentiallyDynamicSofaStatic) {
  const ClassGroups groups;
  EXPECT_EQ(groups.GroupOf(15), ClassGroup::kDynamic);             // person
  EXPECT_EQ(groups.GroupOf(9), ClassGroup::kPotentiallyDynamic);   // chair
  EXPECT_EQ(groups.GroupOf(5), ClassGroup::kPotentiallyDynamic);   // bottle
  EXPECT_EQ(groups.GroupOf(18), ClassGroup::kStatic);              // sofa
  EXPECT_EQ(groups.GroupOf(0), ClassGroup::kStatic);               // background
  EXPECT_EQ(groups.GroupOf(200), ClassGroup::kStatic);             // unnamed id
  int dynamic = 0;
  for (int id = 0; id < 256; ++id) dynamic += groups.IsDynamic(id);
  EXPECT_EQ(dynamic, 1);
}

TEST(ClassGroups, ConfiguredListsReplaceDefaults) {
  ClassGroupOptions options;
  options.dynamic_classes = {"person", "dog"};
  options.potentially_dynamic_classes = {"tvmonitor"};
  const ClassGroups groups(options);
  EXPECT_TRUE(groups.IsDynamic(12));               // dog
  EXPECT_TRUE(groups.IsPotentiallyDynamic(20));    // tvmonitor
  EXPECT_EQ(groups.GroupOf(9), ClassGroup::kStatic);  // chair no longer listed
}

TEST(ClassGroups, UnknownOrDuplicatedNamesAreErrors) {
  ClassGroupOptions unknown;
  unknown.dynamic_classes = {"pedestrian"};
  EXPECT_THROW(ClassGroups{unknown}, Error);
  ClassGroupOptions both;
  both.potentially_dynamic_classes = {"person"};
  EXPECT_THROW(ClassGroups{both}, Error);
}

TEST(ClassGroups, MasksMarkExactlyTheGroupPixels) {
  cv::Mat labels(2, 3, CV_8UC1);
  labels.at<uchar>(0, 0) = 15;  // person
  labels.at<uchar>(0, 1) = 9;   // chair
  labels.at<uchar>(0, 2) = 0;
  labels.at<uchar>(1, 0) = 18;  // sofa
  labels.at<uchar>(1, 1) = 15;
  labels.at<uchar>(1, 2) = 5;   // bottle
  const SemanticMasks masks = ClassGroups().Masks(labels);
  ASSERT_EQ(masks.dynamic.type(), CV_8UC1);
  const uchar expected_dynamic[] = {255, 0, 0, 0, 255, 0};
  const uchar expected_potential[] = {0, 255, 0, 0, 0, 255};
  const uchar expected_static_objects[] = {0, 0, 0, 255, 0, 0};  // sofa; background is unlabelled
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(masks.dynamic.at<uchar>(i / 3, i % 3), expected_dynamic[i]) << i;
    EXPECT_EQ(masks.potentially_dynamic.at<uchar>(i / 3, i % 3), expected_potential[i]) << i;
    EXPECT_EQ(masks.static_objects.at<uchar>(i / 3, i % 3), expected_static_objects[i]) << i;
  }
  EXPECT_THROW(ClassGroups().Masks(cv::Mat(2, 2, CV_32F)), Error);
}

TEST(ClassGroups, VocNamesHavePersonAt15) {
  ASSERT_EQ(VocClassNames().size(), 21u);
  EXPECT_EQ(VocClassNames()[kVocPersonClass], "person");
  EXPECT_EQ(VocClassNames()[9], "chair");
}

}  // namespace
}  // namespace esdslam
