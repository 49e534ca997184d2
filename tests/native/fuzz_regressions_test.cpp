// Replays the fuzz targets' seed corpora and every input a fuzzer ever reported
// (tests/fuzz/corpus/<target>/, tests/fuzz/regressions/<target>/) through the same harness the
// libFuzzer binaries run (tests/fuzz/fuzz_harness.h). This keeps past findings fixed in the
// ordinary native suite, with gcc and under the sanitizers, without clang or libFuzzer. Each finding
// also has a named test in hostile_input_test.cpp that says what went wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../fuzz/fuzz_harness.h"
#include "test_helpers.h"

namespace springbones {
namespace {

namespace fs = std::filesystem;
using Harness = std::string (*)(const std::uint8_t*, std::size_t);

const fs::path kFuzzDir = fs::path(test::fixturesDir()) / ".." / "fuzz";

// Runs every file of corpus/<target> and regressions/<target>; returns how many ran.
std::size_t replay(const std::string& target, Harness harness) {
  std::vector<fs::path> files;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path dir = kFuzzDir / kind / target;
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.is_regular_file()) files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<std::uint8_t> bytes(std::istreambuf_iterator<char>(in), {});
    EXPECT_EQ(harness(bytes.data(), bytes.size()), "") << file;
  }
  return files.size();
}

TEST(FuzzRegressions, GlbAndMetadataInputsKeepEveryInvariant) {
  EXPECT_GT(replay("glb_metadata", fuzz::runGlbAndMetadata), 0u);
}

TEST(FuzzRegressions, EntityInputsKeepEveryInvariant) { EXPECT_GT(replay("entity", fuzz::runEntity), 0u); }

TEST(FuzzRegressions, MetadataInputsKeepEveryInvariant) { EXPECT_GT(replay("metadata", fuzz::runMetadata), 0u); }

TEST(FuzzRegressions, TypedInputsKeepEveryInvariant) { EXPECT_GT(replay("typed", fuzz::runTyped), 0u); }

TEST(FuzzRegressions, SimulationInputsKeepEveryInvariant) { EXPECT_GT(replay("simulation", fuzz::runSimulation), 0u); }

#ifdef SPRINGBONES_FUZZ_HAS_VRM
TEST(FuzzRegressions, VrmInputsKeepEveryInvariant) { EXPECT_GT(replay("vrm", fuzz::runVrm), 0u); }
#endif

}  // namespace
}  // namespace springbones
