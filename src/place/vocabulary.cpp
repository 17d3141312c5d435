#include "place/vocabulary.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace esdslam {

void VocabularyOptions::Check() const {
  if (branching < 2 || branching > 255) throw Error("vocabulary branching factor k must be in 2..255");
  if (levels < 1 || levels > 10) throw Error("vocabulary depth L must be in 1..10");
  if (max_iterations < 1) throw Error("vocabulary k-medians iterations must be positive");
}

double L1Score(const BowVector& a, const BowVector& b) {
  // With both vectors L1-normalised and non-negative, 1 - 0.5 |a - b|_1 reduces to a sum over
  // the common words of (|a_i| + |b_i| - |a_i - b_i|) / 2; words present in only one vector
  // contribute nothing.
  double score = 0.0;
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->word < ib->word) {
      ++ia;
    } else if (ib->word < ia->word) {
      ++ib;
    } else {
      score += std::abs(ia->weight) + std::abs(ib->weight) - std::abs(ia->weight - ib->weight);
      ++ia;
      ++ib;
    }
  }
  return 0.5 * score;
}

void Vocabulary::IndexNodes() {
  word_nodes_.clear();
  if (nodes_.empty()) return;
  nodes_[0].depth = 0;
  for (NodeId id = 0; id < num_nodes(); ++id) {
    Node& node = nodes_[id];
    if (node.num_children == 0) {
      node.word = static_cast<WordId>(word_nodes_.size());
      word_nodes_.push_back(id);
      continue;
    }
    node.word = -1;
    for (int c = 0; c < node.num_children; ++c) nodes_[node.first_child + c].depth = node.depth + 1;
  }
}

WordId Vocabulary::Quantize(const Descriptor256& descriptor, int level, NodeId* node_at_level) const {
  NodeId current = 0;
  while (nodes_[current].num_children > 0) {
    if (node_at_level != nullptr && nodes_[current].depth == level) *node_at_level = current;
    const Node& node = nodes_[current];
    NodeId best = node.first_child;
    int best_distance = HammingDistance(descriptor, nodes_[best].descriptor);
    for (int c = 1; c < node.num_children; ++c) {
      const int distance = HammingDistance(descriptor, nodes_[node.first_child + c].descriptor);
      if (distance < best_distance) {
        best_distance = distance;
        best = node.first_child + c;
      }
    }
    current = best;
  }
  // A leaf shallower than (or at) the requested level stands for itself.
  if (node_at_level != nullptr && nodes_[current].depth <= level) *node_at_level = current;
  return nodes_[current].word;
}

BowVector Vocabulary::Transform(const cv::Mat& descriptors, FeatureVector* direct_index,
                                int direct_index_level) const {
  if (empty()) throw Error("Vocabulary::Transform on an empty vocabulary");
  if (direct_index != nullptr) {
    direct_index->clear();
    if (direct_index_level < 0 || direct_index_level > levels_)
      throw Error(fmt::format("direct index level {} outside 0..{}", direct_index_level, levels_));
  }
  const std::vector<Descriptor256> rows = DescriptorsFromMat(descriptors);
  std::vector<BowEntry> raw;
  raw.reserve(rows.size());
  for (int i = 0; i < static_cast<int>(rows.size()); ++i) {
    NodeId node = 0;
    const WordId word = Quantize(rows[i], direct_index_level, direct_index != nullptr ? &node : nullptr);
    if (direct_index != nullptr) (*direct_index)[node].push_back(i);
    const double weight = word_weights_[word];
    if (weight > 0.0) raw.push_back({word, weight});
  }
  std::sort(raw.begin(), raw.end(), [](const BowEntry& a, const BowEntry& b) { return a.word < b.word; });
  // Term frequency x IDF: repeated words accumulate their weight; then L1 normalisation.
  BowVector bow;
  double total = 0.0;
  for (const BowEntry& entry : raw) {
    if (!bow.empty() && bow.back().word == entry.word) {
      bow.back().weight += entry.weight;
    } else {
      bow.push_back(entry);
    }
    total += entry.weight;
  }
  if (total > 0.0) {
    for (BowEntry& entry : bow) entry.weight /= total;
  }
  return bow;
}

}  // namespace esdslam
