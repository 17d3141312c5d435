#pragma once
// Bag-of-words vocabulary for 256-bit binary (ORB) descriptors, after DBoW2 (Galvez-Lopez and
// Tardos, "Bags of Binary Words for Fast Place Recognition in Image Sequences", T-RO 2012):
// a tree built by hierarchical k-medians on the Hamming distance (k children per node, at most
// L levels below the root; centres are per-bit majorities, seeded by k-means++), leaves are the
// words, each with an IDF weight log(N / n_i) (N training images, n_i of them containing the
// word). Images become L1-normalised TF-IDF vectors compared with the L1 score.
//
// Node ids: 0 is the root (depth 0); children of a node have consecutive ids. Word ids are the
// leaves in increasing node id order (0 .. num_words - 1).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "place/binary_descriptor.h"
#include "place/bow_vector.h"

namespace esdslam {

struct VocabularyOptions {
  // Branching factor and depth. DBoW2/ORB-SLAM2 use k = 10, L = 6 (10^6 words) trained on
  // millions of descriptors; our redistributable training set holds ~4 x 10^5 descriptors, so
  // L = 6 would leave most words with a single descriptor. L = 5 (~9 x 10^4 words, ~4 training
  // descriptors each) separated neighbouring from unrelated frames about twice as well as L = 4
  // on held-out frames (see models/vocabulary/README.md), at a 4.9 MB file.
  int branching = 10;
  int levels = 5;
  int max_iterations = 15;  // k-medians iterations per node (stops earlier when stable)
  std::uint32_t seed = 1;   // k-means++ seeding

  void Check() const;
};

// Progress of training: phase name and fraction in [0, 1].
using TrainProgress = std::function<void(const char* phase, double fraction)>;

class Vocabulary {
 public:
  Vocabulary() = default;

  // descriptors_per_image: one N_i x 32 CV_8U matrix per training image (empty ones are skipped
  // for clustering but still count as documents). Deterministic for a given seed.
  static Vocabulary Train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyOptions& options,
                          const TrainProgress& progress = {});

  // Binary file format: see vocabulary_io.cpp. Load throws InputError on a missing, truncated
  // or corrupt file; Save throws Error when the file cannot be written.
  void Save(const std::string& path) const;
  static Vocabulary Load(const std::string& path);

  // descriptors: N x 32 CV_8U. direct_index (may be null) receives, for each node at depth
  // `direct_index_level` (1 .. levels; a shallower leaf stands for itself), the indices of the
  // descriptors that pass through it.
  BowVector Transform(const cv::Mat& descriptors, FeatureVector* direct_index = nullptr,
                      int direct_index_level = 0) const;
  // Leaf word of one descriptor (and the node at `level` on its path, when node_at_level != null).
  WordId Quantize(const Descriptor256& descriptor, int level = 0, NodeId* node_at_level = nullptr) const;

  double Score(const BowVector& a, const BowVector& b) const { return L1Score(a, b); }

  bool empty() const { return nodes_.empty(); }
  int num_words() const { return static_cast<int>(word_nodes_.size()); }
  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  int branching() const { return branching_; }
  int levels() const { return levels_; }
  double word_weight(WordId word) const { return word_weights_[word]; }
  // Depth of a node below the root (root = 0).
  int node_depth(NodeId node) const { return nodes_[node].depth; }

 private:
  struct Node {
    Descriptor256 descriptor{};
    int first_child = 0;  // valid when num_children > 0
    int num_children = 0;
    int depth = 0;
    WordId word = -1;     // leaves only
  };
  friend class VocabularyBuilder;
  friend class VocabularyFile;

  // Assigns word ids to the leaves and depths to all nodes from the child links.
  void IndexNodes();

  int branching_ = 0;
  int levels_ = 0;
  std::vector<Node> nodes_;
  std::vector<NodeId> word_nodes_;     // word id -> node id
  std::vector<double> word_weights_;   // word id -> IDF weight (>= 0)
};

}  // namespace esdslam
