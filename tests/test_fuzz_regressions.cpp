// Replays every input kept in tests/fuzz_regressions/<format>/ (crashes the fuzzers of
// scripts/fuzz.sh found, and fixed) through the same loader call the fuzzer used: each
// must now either load into a valid scene or be rejected with masq::Error.
#include "fuzz/fuzz_load.h"
#include "scenes/loaders/loader.h"
#include <gtest/gtest.h>
#include <filesystem>

namespace fs = std::filesystem;

TEST(FuzzRegressions, EveryKeptInputLoadsOrFailsCleanly) {
  const fs::path root = fs::path(MASQ_SOURCE_DIR) / "tests" / "fuzz_regressions";
  ASSERT_TRUE(fs::is_directory(root)) << root;
  int replayed = 0;
  for (const auto& dir : fs::directory_iterator(root)) {
    if (!dir.is_directory()) continue;
    const std::string format = dir.path().filename().string();
    for (const auto& file : fs::directory_iterator(dir.path())) {
      SCOPED_TRACE(file.path().string());
      std::vector<std::byte> bytes = masq::read_file_bytes(file.path().string());
      try {
        masq::Scene s = masq::fuzz::load(format, bytes);
        masq::validate_scene(s);
      } catch (const masq::Error& e) {
        EXPECT_NE(std::string(e.what()), "");
      }
      ++replayed;
    }
  }
  EXPECT_GT(replayed, 0) << "no regression inputs under " << root;
}
