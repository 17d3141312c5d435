#include "semantic/class_groups.h"

#include <algorithm>
#include <set>

#include <opencv2/core.hpp>

#include "common/error.h"
#include "semantic/segmenter.h"

namespace esdslam {
namespace {

int ClassId(const std::vector<std::string>& class_names, const std::string& name) {
  const auto it = std::find(class_names.begin(), class_names.end(), name);
  if (it == class_names.end()) {
    std::string known;
    for (const auto& n : class_names) known += (known.empty() ? "" : ", ") + n;
    throw Error(fmt::format("unknown class name '{}' (known: {})", name, known));
  }
  return static_cast<int>(it - class_names.begin());
}

cv::Mat MaskFromLut(const cv::Mat& labels, const std::array<ClassGroup, 256>& groups, ClassGroup wanted) {
  cv::Mat lut(1, 256, CV_8UC1);
  for (int i = 0; i < 256; ++i) lut.at<std::uint8_t>(i) = groups[static_cast<std::size_t>(i)] == wanted ? 255 : 0;
  cv::Mat mask;
  cv::LUT(labels, lut, mask);
  return mask;
}

}  // namespace

const std::vector<std::string>& VocClassNames() {
  static const std::vector<std::string> names{
      "background", "aeroplane", "bicycle", "bird",  "boat",        "bottle", "bus",
      "car",        "cat",       "chair",   "cow",   "diningtable", "dog",    "horse",
      "motorbike",  "person",    "pottedplant", "sheep", "sofa",    "train",  "tvmonitor"};
  return names;
}

void ClassGroupOptions::Check(const std::vector<std::string>& class_names) const {
  std::set<int> dynamic_ids;
  for (const auto& name : dynamic_classes) dynamic_ids.insert(ClassId(class_names, name));
  for (const auto& name : potentially_dynamic_classes) {
    if (dynamic_ids.count(ClassId(class_names, name)))
      throw Error(fmt::format("class '{}' is listed as both dynamic and potentially dynamic", name));
  }
}

ClassGroups::ClassGroups(const ClassGroupOptions& options, const std::vector<std::string>& class_names) {
  const auto& names = class_names.empty() ? VocClassNames() : class_names;
  if (names.size() > 256) throw Error("at most 256 classes are supported (labels are 8-bit)");
  options.Check(names);
  group_of_id_.fill(ClassGroup::kStatic);
  for (const auto& name : options.potentially_dynamic_classes)
    group_of_id_[static_cast<std::size_t>(ClassId(names, name))] = ClassGroup::kPotentiallyDynamic;
  for (const auto& name : options.dynamic_classes)
    group_of_id_[static_cast<std::size_t>(ClassId(names, name))] = ClassGroup::kDynamic;
}

SemanticMasks ClassGroups::Masks(const cv::Mat& labels) const {
  if (labels.empty() || labels.type() != CV_8UC1) throw Error("ClassGroups::Masks: labels must be a non-empty CV_8UC1 image");
  SemanticMasks masks{MaskFromLut(labels, group_of_id_, ClassGroup::kDynamic),
                      MaskFromLut(labels, group_of_id_, ClassGroup::kPotentiallyDynamic),
                      MaskFromLut(labels, group_of_id_, ClassGroup::kStatic)};
  masks.static_objects.setTo(0, labels == 0);
  return masks;
}

}  // namespace esdslam
