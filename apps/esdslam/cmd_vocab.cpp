// esdslam vocab: trains a bag-of-words vocabulary (ORB descriptors) from image folders.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "common/timer.h"
#include "place/vocabulary.h"
#include "place/vocabulary_images.h"

namespace esdslam::cli {
namespace {

struct VocabTrainArgs {
  std::vector<std::string> image_folders;
  std::string out_path;
  VocabularyOptions vocabulary;
  OrbOptions orb;
  int max_images = 0;
};

int RunVocabTrain(const VocabTrainArgs& args) {
  args.vocabulary.Check();
  args.orb.Check();
  const Stopwatch watch;
  const std::vector<std::string> images = ListTrainingImages(args.image_folders, args.max_images);
  if (images.empty()) throw Error("no images found in the given folders");
  spdlog::info("vocab: extracting up to {} ORB features from each of {} images", args.orb.num_features, images.size());
  const std::vector<cv::Mat> descriptors = ExtractTrainingDescriptors(images, args.orb, [&](int done, int total) {
    std::fprintf(stderr, "\rvocab: features %d/%d (%.1f s)", done, total, watch.ElapsedMs() / 1000.0);
    if (done == total) std::fprintf(stderr, "\n");
  });
  std::size_t total_descriptors = 0;
  for (const cv::Mat& d : descriptors) total_descriptors += static_cast<std::size_t>(d.rows);
  spdlog::info("vocab: training k={} L={} seed={} on {} descriptors", args.vocabulary.branching, args.vocabulary.levels,
               args.vocabulary.seed, total_descriptors);
  const Vocabulary vocabulary = Vocabulary::Train(descriptors, args.vocabulary, [&](const char* phase, double fraction) {
    std::fprintf(stderr, "\rvocab: %-10s %5.1f%% (%.1f s)", phase, 100.0 * fraction, watch.ElapsedMs() / 1000.0);
    if (fraction >= 1.0) std::fprintf(stderr, "\n");
  });
  vocabulary.Save(args.out_path);
  spdlog::info("vocab: {} words, {} nodes -> {} ({:.1f} s)", vocabulary.num_words(), vocabulary.num_nodes(),
               args.out_path, watch.ElapsedMs() / 1000.0);
  return 0;
}

RunFn SetupVocab(CLI::App& app) {
  app.require_subcommand(1);
  CLI::App* train = app.add_subcommand("train", "Train a vocabulary from the images in one or more folders");
  auto args = std::make_shared<VocabTrainArgs>();
  train->add_option("--images", args->image_folders, "Image folders (a folder with rgb/ uses rgb/)")
      ->required()
      ->check(CLI::ExistingDirectory);
  train->add_option("--out", args->out_path, "Output vocabulary file")->required();
  train->add_option("--k", args->vocabulary.branching, "Branching factor")->check(CLI::Range(2, 255))->capture_default_str();
  train->add_option("--levels", args->vocabulary.levels, "Depth L of the tree")->check(CLI::Range(1, 10))->capture_default_str();
  train->add_option("--max-images", args->max_images, "Use at most N images, evenly spaced (0 = all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  train->add_option("--seed", args->vocabulary.seed, "Seed of the k-means++ initialisation")->capture_default_str();
  train->add_option("--features", args->orb.num_features, "ORB features per image")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  return [args] { return RunVocabTrain(*args); };
}

const Registrar kRegistrar({"vocab", "Bag-of-words vocabulary tools (train)", SetupVocab, 80});

}  // namespace
}  // namespace esdslam::cli
