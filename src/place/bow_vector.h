#pragma once
// Bag-of-words vectors and the direct index (DBoW2 terms).
//
// BowVector: sparse word histogram, entries sorted by increasing word id, ids unique, weights
// > 0 and summing to 1 (L1-normalised TF-IDF). FeatureVector ("direct index"): for one image,
// vocabulary node id -> indices of the image's descriptors that descend through that node at
// the chosen level; used to match two images by comparing only descriptors under the same node.

#include <map>
#include <utility>
#include <vector>

namespace esdslam {

using WordId = int;
using NodeId = int;

struct BowEntry {
  WordId word;
  double weight;
};
using BowVector = std::vector<BowEntry>;

using FeatureVector = std::map<NodeId, std::vector<int>>;

// L1 similarity of two L1-normalised BoW vectors: s = 1 - 0.5 * |v1 - v2|_1, in [0, 1]
// (1 = identical histograms, 0 = no word in common).
double L1Score(const BowVector& a, const BowVector& b);

}  // namespace esdslam
