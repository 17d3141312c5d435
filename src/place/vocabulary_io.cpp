// Vocabulary file format (binary, little-endian), version 1:
//   offset 0   char[8]  magic "ESDVOCB\0"
//          8   uint32   version (1)
//         12   uint32   branching factor k
//         16   uint32   depth L
//         20   uint32   num_nodes
//         24   uint32   num_words
//         28   uint32   reserved (0)
//         32   num_nodes x { uint8[32] descriptor, uint32 first_child, uint32 num_children }
//              (node 0 = root; a node's children are consecutive and have larger ids)
//              num_words x float64 IDF weight (word id = rank of the leaf in node id order)
//   last 8     uint64   FNV-1a hash of every preceding byte
// The whole file is read in one go and validated (size, hash, tree structure) before use.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "common/error.h"
#include "place/vocabulary.h"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "vocabulary_io.cpp assumes a little-endian host"
#endif

namespace esdslam {
namespace {

constexpr char kMagic[8] = {'E', 'S', 'D', 'V', 'O', 'C', 'B', '\0'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 32;
constexpr std::size_t kNodeBytes = 40;

std::uint64_t Fnv1a(const char* data, std::size_t size) {
  std::uint64_t hash = 14695981039346656037ull;
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= static_cast<unsigned char>(data[i]);
    hash *= 1099511628211ull;
  }
  return hash;
}

template <typename T>
void Put(std::vector<char>* out, const T& value) {
  const char* bytes = reinterpret_cast<const char*>(&value);
  out->insert(out->end(), bytes, bytes + sizeof(T));
}

template <typename T>
T Get(const std::vector<char>& in, std::size_t offset) {
  T value;
  std::memcpy(&value, in.data() + offset, sizeof(T));
  return value;
}

}  // namespace

class VocabularyFile {
 public:
  static std::vector<char> Serialize(const Vocabulary& vocabulary);
  static Vocabulary Parse(const std::vector<char>& bytes, const std::string& path);

 private:
  static void CheckTree(const Vocabulary& vocabulary, const std::string& path);
};

std::vector<char> VocabularyFile::Serialize(const Vocabulary& vocabulary) {
  std::vector<char> out;
  out.reserve(kHeaderBytes + kNodeBytes * vocabulary.nodes_.size() + 8 * vocabulary.word_weights_.size() + 8);
  out.insert(out.end(), kMagic, kMagic + 8);
  Put<std::uint32_t>(&out, kVersion);
  Put<std::uint32_t>(&out, vocabulary.branching_);
  Put<std::uint32_t>(&out, vocabulary.levels_);
  Put<std::uint32_t>(&out, static_cast<std::uint32_t>(vocabulary.nodes_.size()));
  Put<std::uint32_t>(&out, static_cast<std::uint32_t>(vocabulary.word_weights_.size()));
  Put<std::uint32_t>(&out, 0);
  for (const Vocabulary::Node& node : vocabulary.nodes_) {
    Put(&out, node.descriptor);
    Put<std::uint32_t>(&out, node.num_children > 0 ? node.first_child : 0);
    Put<std::uint32_t>(&out, node.num_children);
  }
  for (const double weight : vocabulary.word_weights_) Put(&out, weight);
  Put<std::uint64_t>(&out, Fnv1a(out.data(), out.size()));
  return out;
}

Vocabulary VocabularyFile::Parse(const std::vector<char>& bytes, const std::string& path) {
  if (bytes.size() < kHeaderBytes + 8 || std::memcmp(bytes.data(), kMagic, 8) != 0)
    throw InputError(path, 0, "not an esdslam vocabulary file (expected magic ESDVOCB)");
  const auto version = Get<std::uint32_t>(bytes, 8);
  if (version != kVersion) throw InputError(path, 0, fmt::format("vocabulary format version {} (expected {})", version, kVersion));
  Vocabulary vocabulary;
  vocabulary.branching_ = static_cast<int>(Get<std::uint32_t>(bytes, 12));
  vocabulary.levels_ = static_cast<int>(Get<std::uint32_t>(bytes, 16));
  const std::size_t num_nodes = Get<std::uint32_t>(bytes, 20);
  const std::size_t num_words = Get<std::uint32_t>(bytes, 24);
  const std::size_t expected = kHeaderBytes + kNodeBytes * num_nodes + 8 * num_words + 8;
  if (bytes.size() != expected)
    throw InputError(path, 0, fmt::format("file has {} bytes, header announces {} (truncated or corrupt)", bytes.size(), expected));
  if (Get<std::uint64_t>(bytes, bytes.size() - 8) != Fnv1a(bytes.data(), bytes.size() - 8))
    throw InputError(path, 0, "checksum mismatch (corrupt file)");
  if (num_nodes == 0) throw InputError(path, 0, "vocabulary without nodes");

  vocabulary.nodes_.resize(num_nodes);
  std::size_t offset = kHeaderBytes;
  for (Vocabulary::Node& node : vocabulary.nodes_) {
    std::memcpy(node.descriptor.data(), bytes.data() + offset, kDescriptorBytes);
    node.first_child = static_cast<int>(Get<std::uint32_t>(bytes, offset + 32));
    node.num_children = static_cast<int>(Get<std::uint32_t>(bytes, offset + 36));
    offset += kNodeBytes;
  }
  vocabulary.word_weights_.resize(num_words);
  for (double& weight : vocabulary.word_weights_) {
    weight = Get<double>(bytes, offset);
    offset += 8;
    if (!std::isfinite(weight) || weight < 0.0) throw InputError(path, 0, "word weight is not a finite value >= 0");
  }
  CheckTree(vocabulary, path);
  vocabulary.IndexNodes();
  return vocabulary;
}

// Every node but the root has exactly one parent with a smaller id, children are in range,
// no node is deeper than L and the number of leaves equals num_words.
void VocabularyFile::CheckTree(const Vocabulary& vocabulary, const std::string& path) {
  const auto& nodes = vocabulary.nodes_;
  const std::size_t n = nodes.size();
  if (vocabulary.branching_ < 2 || vocabulary.levels_ < 1) throw InputError(path, 0, "invalid k or L in header");
  std::vector<int> depth(n, -1);
  depth[0] = 0;
  std::size_t leaves = 0;
  for (std::size_t id = 0; id < n; ++id) {
    const auto& node = nodes[id];
    if (depth[id] < 0) throw InputError(path, 0, fmt::format("node {} has no parent", id));
    if (node.num_children == 0) {
      ++leaves;
      continue;
    }
    const std::size_t first = static_cast<std::size_t>(node.first_child);
    if (node.num_children > vocabulary.branching_ || first <= id || first + node.num_children > n ||
        depth[id] >= vocabulary.levels_)
      throw InputError(path, 0, fmt::format("node {} has invalid children", id));
    for (std::size_t c = first; c < first + node.num_children; ++c) {
      if (depth[c] >= 0) throw InputError(path, 0, fmt::format("node {} has two parents", c));
      depth[c] = depth[id] + 1;
    }
  }
  if (leaves != vocabulary.word_weights_.size())
    throw InputError(path, 0, fmt::format("{} leaves but {} word weights", leaves, vocabulary.word_weights_.size()));
}

void Vocabulary::Save(const std::string& path) const {
  if (empty()) throw Error("cannot save an empty vocabulary");
  const std::vector<char> bytes = VocabularyFile::Serialize(*this);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw Error(fmt::format("cannot open {} for writing", path));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw Error(fmt::format("failed writing {}", path));
}

Vocabulary Vocabulary::Load(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(path, 0, "cannot open vocabulary file");
  const std::streamsize size = in.tellg();
  in.seekg(0);
  std::vector<char> bytes(static_cast<std::size_t>(std::max<std::streamsize>(size, 0)));
  if (!in.read(bytes.data(), size)) throw InputError(path, 0, "cannot read vocabulary file");
  return VocabularyFile::Parse(bytes, path);
}

}  // namespace esdslam
