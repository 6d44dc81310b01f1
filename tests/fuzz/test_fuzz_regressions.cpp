// Replays every fuzz input kept in the repository (the seed corpora in fuzz/corpus and the
// inputs that once crashed, hung or exhausted memory, in tests/fuzz_regressions) through the
// fuzz targets' bodies: each must end in a result or an InputError. Any other exception fails
// the test; a crash or a sanitizer report (the sanitize preset) fails the process.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "fuzz_targets.hpp"

namespace {
namespace fs = std::filesystem;

std::size_t replay(const std::string& target, void (*body)(std::string_view)) {
  std::size_t replayed = 0;
  for (const fs::path& dir : {fs::path(AGGPACK_SOURCE_DIR) / "fuzz/corpus" / target,
                             fs::path(AGGPACK_SOURCE_DIR) / "tests/fuzz_regressions" / target}) {
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (!entry.is_regular_file()) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      std::stringstream bytes;
      bytes << in.rdbuf();
      SCOPED_TRACE(entry.path().string());
      EXPECT_NO_THROW(body(bytes.str())) << entry.path();
      ++replayed;
    }
  }
  return replayed;
}
}  // namespace

TEST(FuzzRegressions, ScenarioReader) { EXPECT_GE(replay("scenario", aggpack::fuzz::scenario_reader), 10u); }
TEST(FuzzRegressions, GradingReader) { EXPECT_GE(replay("grading", aggpack::fuzz::grading_reader), 5u); }
TEST(FuzzRegressions, ParticleFileReader) {
  EXPECT_GE(replay("particles", aggpack::fuzz::particle_file_reader), 5u);
}
TEST(FuzzRegressions, CalibrationReader) {
  EXPECT_GE(replay("calibration", aggpack::fuzz::calibration_reader), 4u);
}
TEST(FuzzRegressions, CheckpointReader) { EXPECT_GE(replay("checkpoint", aggpack::fuzz::checkpoint_reader), 4u); }
TEST(FuzzRegressions, MaterialReader) { EXPECT_GE(replay("materials", aggpack::fuzz::material_reader), 4u); }
TEST(FuzzRegressions, MaterialFileReader) {
  EXPECT_GE(replay("material_file", aggpack::fuzz::material_file_reader), 4u);
}
TEST(FuzzRegressions, ShapeReader) { EXPECT_GE(replay("shape", aggpack::fuzz::shape_reader), 5u); }
