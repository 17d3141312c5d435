#include "place/bow_matcher.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "common/error.h"
#include "place/binary_descriptor.h"

namespace esdslam {

void BowMatchOptions::Check() const {
  if (max_distance < 0 || max_distance > 256) throw Error("BowMatchOptions: max_distance must be in 0..256");
  if (!(ratio > 0 && ratio <= 1)) throw Error("BowMatchOptions: ratio must be in (0, 1]");
}

std::vector<int> OrientationOutliers(const std::vector<std::pair<float, int>>& rotation_and_id) {
  constexpr int kBins = 12;
  std::array<std::vector<int>, kBins> histogram;
  for (const auto& [rotation_deg, id] : rotation_and_id) {
    float rotation = std::fmod(rotation_deg, 360.f);
    if (rotation < 0) rotation += 360.f;
    const int bin = static_cast<int>(std::round(rotation / 30.f)) % kBins;
    histogram[bin].push_back(id);
  }
  std::array<int, kBins> order;
  for (int b = 0; b < kBins; ++b) order[b] = b;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return histogram[a].size() > histogram[b].size(); });
  std::array<bool, kBins> keep{};
  keep[order[0]] = true;
  for (int k = 1; k < 3; ++k) keep[order[k]] = histogram[order[k]].size() >= 0.1 * histogram[order[0]].size();
  std::vector<int> outliers;
  for (int b = 0; b < kBins; ++b)
    if (!keep[b]) outliers.insert(outliers.end(), histogram[b].begin(), histogram[b].end());
  std::sort(outliers.begin(), outliers.end());
  return outliers;
}

std::vector<int> MatchByDirectIndex(const FeatureSet& train, const FeatureVector& train_index,
                                    const std::vector<bool>& train_usable, const FeatureSet& query,
                                    const FeatureVector& query_index, const std::vector<bool>& query_usable,
                                    const BowMatchOptions& options) {
  std::vector<int> query_to_train(query.size(), -1);
  std::vector<std::pair<float, int>> rotations;  // (rotation, query index)
  auto train_it = train_index.begin();
  auto query_it = query_index.begin();
  while (train_it != train_index.end() && query_it != query_index.end()) {
    if (train_it->first < query_it->first) { ++train_it; continue; }
    if (query_it->first < train_it->first) { ++query_it; continue; }
    for (int t : train_it->second) {
      if (!train_usable.empty() && !train_usable[t]) continue;
      const Descriptor256 train_descriptor = DescriptorFromBytes(train.descriptor(t));
      int best = -1, best_distance = 257, second_distance = 257;
      for (int q : query_it->second) {
        if ((!query_usable.empty() && !query_usable[q]) || query_to_train[q] >= 0) continue;
        const int distance = HammingDistance(train_descriptor, DescriptorFromBytes(query.descriptor(q)));
        if (distance < best_distance) {
          second_distance = best_distance, best_distance = distance, best = q;
        } else if (distance < second_distance) {
          second_distance = distance;
        }
      }
      if (best < 0 || best_distance > options.max_distance) continue;
      if (static_cast<double>(best_distance) >= options.ratio * second_distance) continue;
      query_to_train[best] = t;
      rotations.emplace_back(train.keypoints[t].angle - query.keypoints[best].angle, best);
    }
    ++train_it, ++query_it;
  }
  if (options.check_orientation)
    for (int q : OrientationOutliers(rotations)) query_to_train[q] = -1;
  return query_to_train;
}

}  // namespace esdslam
