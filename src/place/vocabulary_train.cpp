// Vocabulary training: hierarchical k-medians on Hamming distance with k-means++ seeding,
// followed by IDF weighting over the training images.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "place/vocabulary.h"

namespace esdslam {

class VocabularyBuilder {
 public:
  VocabularyBuilder(const VocabularyOptions& options, const std::vector<Descriptor256>& descriptors,
                    const TrainProgress& progress)
      : options_(options), descriptors_(descriptors), progress_(progress), rng_(options.seed) {}

  // Builds the tree (nodes and child links) into `vocabulary`.
  void BuildTree(Vocabulary* vocabulary);

 private:
  using Node = Vocabulary::Node;
  void Split(std::vector<Node>* nodes, NodeId node, int depth, const std::vector<int>& members);
  std::vector<Descriptor256> SeedCentres(const std::vector<int>& members);
  std::vector<std::vector<int>> KMedians(const std::vector<int>& members, std::vector<Descriptor256>* centres);
  void AddChildren(std::vector<Node>* nodes, NodeId parent, const std::vector<Descriptor256>& centres);
  void ReportLeaf(std::size_t count);

  const VocabularyOptions options_;
  const std::vector<Descriptor256>& descriptors_;
  const TrainProgress& progress_;
  std::mt19937 rng_;
  std::size_t done_ = 0;  // descriptors that reached a leaf
  double last_reported_ = -1.0;
};

void VocabularyBuilder::BuildTree(Vocabulary* vocabulary) {
  vocabulary->nodes_.assign(1, Node{});
  std::vector<int> all(descriptors_.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  if (!all.empty()) Split(&vocabulary->nodes_, 0, 0, all);
}

void VocabularyBuilder::ReportLeaf(std::size_t count) {
  done_ += count;
  if (!progress_ || descriptors_.empty()) return;
  const double fraction = static_cast<double>(done_) / static_cast<double>(descriptors_.size());
  if (fraction - last_reported_ >= 0.01 || done_ == descriptors_.size()) {
    last_reported_ = fraction;
    progress_("clustering", fraction);
  }
}

void VocabularyBuilder::AddChildren(std::vector<Node>* nodes, NodeId parent, const std::vector<Descriptor256>& centres) {
  (*nodes)[parent].first_child = static_cast<int>(nodes->size());
  (*nodes)[parent].num_children = static_cast<int>(centres.size());
  for (const Descriptor256& centre : centres) {
    Node child;
    child.descriptor = centre;
    nodes->push_back(child);
  }
}

// Depth-first: a node's children are appended together (consecutive ids), then each is split.
void VocabularyBuilder::Split(std::vector<Node>* nodes, NodeId node, int depth, const std::vector<int>& members) {
  if (depth == options_.levels || members.size() <= 1) {
    ReportLeaf(members.size());
    return;
  }
  if (members.size() <= static_cast<std::size_t>(options_.branching)) {
    // Few descriptors: each distinct one becomes a leaf (as DBoW2 does).
    std::set<Descriptor256> distinct;
    for (const int m : members) distinct.insert(descriptors_[m]);
    if (distinct.size() > 1) AddChildren(nodes, node, std::vector<Descriptor256>(distinct.begin(), distinct.end()));
    ReportLeaf(members.size());
    return;
  }
  std::vector<Descriptor256> centres;
  const std::vector<std::vector<int>> clusters = KMedians(members, &centres);
  if (clusters.size() <= 1) {  // all members identical
    ReportLeaf(members.size());
    return;
  }
  AddChildren(nodes, node, centres);
  const NodeId first_child = (*nodes)[node].first_child;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    Split(nodes, first_child + static_cast<int>(c), depth + 1, clusters[c]);
  }
}

// k-means++: first centre uniform, each next one with probability proportional to the squared
// distance to the nearest centre chosen so far. Stops early when every member is a centre.
std::vector<Descriptor256> VocabularyBuilder::SeedCentres(const std::vector<int>& members) {
  std::vector<Descriptor256> centres;
  centres.push_back(descriptors_[members[rng_() % members.size()]]);
  std::vector<double> nearest2(members.size(), std::numeric_limits<double>::max());
  while (static_cast<int>(centres.size()) < options_.branching) {
    double total = 0.0;
    for (std::size_t i = 0; i < members.size(); ++i) {
      const double d = HammingDistance(descriptors_[members[i]], centres.back());
      nearest2[i] = std::min(nearest2[i], d * d);
      total += nearest2[i];
    }
    if (total <= 0.0) break;
    const double target = (static_cast<double>(rng_()) / 4294967296.0) * total;
    double cumulative = 0.0;
    std::size_t pick = members.size() - 1;
    for (std::size_t i = 0; i < members.size(); ++i) {
      cumulative += nearest2[i];
      if (cumulative > target && nearest2[i] > 0.0) {
        pick = i;
        break;
      }
    }
    centres.push_back(descriptors_[members[pick]]);
  }
  return centres;
}

// Lloyd iterations with the Hamming distance and per-bit majority centres (k-medians).
// Returns the non-empty clusters; *centres is resized to match them.
std::vector<std::vector<int>> VocabularyBuilder::KMedians(const std::vector<int>& members,
                                                          std::vector<Descriptor256>* centres) {
  *centres = SeedCentres(members);
  std::vector<int> assignment(members.size(), -1);
  std::vector<std::vector<int>> clusters;
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    bool changed = false;
    clusters.assign(centres->size(), {});
    for (std::size_t i = 0; i < members.size(); ++i) {
      const Descriptor256& d = descriptors_[members[i]];
      int best = 0;
      int best_distance = HammingDistance(d, (*centres)[0]);
      for (int c = 1; c < static_cast<int>(centres->size()); ++c) {
        const int distance = HammingDistance(d, (*centres)[c]);
        if (distance < best_distance) {
          best_distance = distance;
          best = c;
        }
      }
      changed = changed || assignment[i] != best;
      assignment[i] = best;
      clusters[best].push_back(members[i]);
    }
    if (!changed) break;
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      if (!clusters[c].empty()) (*centres)[c] = MajorityDescriptor(descriptors_, clusters[c]);
    }
  }
  // Drop empty clusters (keeping centre/cluster pairs aligned).
  std::vector<std::vector<int>> kept;
  std::vector<Descriptor256> kept_centres;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (clusters[c].empty()) continue;
    kept.push_back(std::move(clusters[c]));
    kept_centres.push_back((*centres)[c]);
  }
  *centres = std::move(kept_centres);
  return kept;
}

Vocabulary Vocabulary::Train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyOptions& options,
                             const TrainProgress& progress) {
  options.Check();
  std::vector<Descriptor256> all;
  std::vector<std::vector<Descriptor256>> per_image;
  per_image.reserve(descriptors_per_image.size());
  for (const cv::Mat& image_descriptors : descriptors_per_image) {
    per_image.push_back(DescriptorsFromMat(image_descriptors));
    all.insert(all.end(), per_image.back().begin(), per_image.back().end());
  }
  if (all.empty()) throw Error("vocabulary training needs at least one descriptor");

  Vocabulary vocabulary;
  vocabulary.branching_ = options.branching;
  vocabulary.levels_ = options.levels;
  VocabularyBuilder(options, all, progress).BuildTree(&vocabulary);
  vocabulary.IndexNodes();

  // IDF: n_i = number of training images in which word i occurs (via the same descent as
  // Transform); unseen words get the largest weight log(N).
  std::vector<int> images_with_word(vocabulary.num_words(), 0);
  std::vector<int> last_image(vocabulary.num_words(), -1);
  for (int image = 0; image < static_cast<int>(per_image.size()); ++image) {
    for (const Descriptor256& d : per_image[image]) {
      const WordId word = vocabulary.Quantize(d);
      if (last_image[word] != image) {
        last_image[word] = image;
        ++images_with_word[word];
      }
    }
    if (progress) progress("weighting", static_cast<double>(image + 1) / per_image.size());
  }
  const double num_images = static_cast<double>(per_image.size());
  vocabulary.word_weights_.resize(vocabulary.num_words());
  for (int w = 0; w < vocabulary.num_words(); ++w) {
    vocabulary.word_weights_[w] = std::log(num_images / std::max(1, images_with_word[w]));
  }
  spdlog::debug("vocabulary: {} descriptors from {} images -> {} nodes, {} words (k={}, L={})", all.size(),
                per_image.size(), vocabulary.num_nodes(), vocabulary.num_words(), options.branching, options.levels);
  return vocabulary;
}

}  // namespace esdslam
