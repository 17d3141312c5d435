#pragma once
// Groups of class ids by how they may move:
//   dynamic              - moves on its own, never used for tracking or mapping (default: person)
//   potentially dynamic  - usually still but often moved by people; the geometry check decides
//   static               - everything else (background, furniture, screens, ...)
// Default potentially dynamic classes: animals that move on their own but are not the paper's
// primary concern (bird, cat, cow, dog, horse, sheep), objects people routinely pick up or push
// (bottle, chair), and vehicles people ride (bicycle, motorbike, car). Large vehicles that are
// rare indoors (aeroplane, boat, bus, train) and heavy furniture stay static.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

enum class ClassGroup : std::uint8_t { kStatic = 0, kPotentiallyDynamic = 1, kDynamic = 2 };

struct ClassGroupOptions {
  std::vector<std::string> dynamic_classes{"person"};  // Semantic.dynamicClasses
  std::vector<std::string> potentially_dynamic_classes{  // Semantic.potentiallyDynamicClasses
      "bicycle", "bird", "bottle", "car", "cat", "chair", "cow", "dog", "horse", "motorbike", "sheep"};

  // Throws Error if a name is not one of `class_names` or appears in both lists.
  void Check(const std::vector<std::string>& class_names) const;
};

// Masks are CV_8UC1, 255 where the label belongs to the group, 0 elsewhere.
struct SemanticMasks {
  cv::Mat dynamic;
  cv::Mat potentially_dynamic;
  cv::Mat static_objects;  // static group except class id 0 (background: "unlabelled")
};

class ClassGroups {
 public:
  // `class_names[i]` names class id i (at most 256 classes).
  explicit ClassGroups(const ClassGroupOptions& options = {},
                       const std::vector<std::string>& class_names = {});

  ClassGroup GroupOf(int class_id) const { return group_of_id_.at(static_cast<std::size_t>(class_id)); }
  bool IsDynamic(int class_id) const { return GroupOf(class_id) == ClassGroup::kDynamic; }
  bool IsPotentiallyDynamic(int class_id) const { return GroupOf(class_id) == ClassGroup::kPotentiallyDynamic; }

  // labels: CV_8UC1 class ids. Ids without a name are static.
  SemanticMasks Masks(const cv::Mat& labels) const;

 private:
  std::array<ClassGroup, 256> group_of_id_{};
};

}  // namespace esdslam
