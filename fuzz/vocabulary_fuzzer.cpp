// Fuzz target: the vocabulary file (Loop.vocabulary).
#include <cstdlib>

#include "common/error.h"
#include "fuzz/fuzz_input.h"
#include "fuzz/seeds.h"
#include "place/vocabulary.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* seed = std::getenv("ESDSLAM_FUZZ_WRITE_SEED")) {
    esdslam::fuzz::WriteVocabularySeed(seed);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = esdslam::fuzz::WriteScratch("vocabulary.bin", data, size);
  try {
    esdslam::Vocabulary::Load(path);
  } catch (const esdslam::Error&) {
  }
  return 0;
}
