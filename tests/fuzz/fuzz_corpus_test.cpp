// The fuzz targets' seed corpora and regressions, replayed in the ordinary test build (and so
// under the ASan + UBSan stage): every seed a fuzzer starts from is an input its reader accepts
// (else the fuzzer would start from noise), every `bad-` seed is refused with a message, and
// every input a fuzzer once crashed on (regressions/<target>/) runs through cleanly.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_targets.h"

namespace lap::fuzz {
namespace {

const std::filesystem::path kFuzzDir = std::filesystem::path(LAP_SOURCE_DIR) / "tests" / "fuzz";

std::vector<std::filesystem::path> files_in(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  if (!std::filesystem::is_directory(dir)) return files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().filename() != "README.md") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<uint8_t> bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class FuzzCorpus : public testing::TestWithParam<std::string> {};

TEST_P(FuzzCorpus, SeedsAreAcceptedBadSeedsRefusedRegressionsRunCleanly) {
  const FuzzTarget* target = find_fuzz_target(GetParam());
  ASSERT_NE(target, nullptr);
  const std::vector<std::filesystem::path> seeds = files_in(kFuzzDir / "corpus" / GetParam());
  ASSERT_FALSE(seeds.empty()) << "no seed corpus for " << GetParam();
  int accepted = 0;
  for (const auto& file : seeds) {
    const bool bad = file.filename().string().rfind("bad-", 0) == 0;
    const std::vector<uint8_t> data = bytes_of(file);
    EXPECT_EQ(target->run(data), !bad) << file;
    accepted += bad ? 0 : 1;
  }
  EXPECT_GT(accepted, 0) << "every seed of " << GetParam() << " is a bad one";
  for (const auto& file : files_in(kFuzzDir / "regressions" / GetParam())) {
    SCOPED_TRACE(file.string());
    (void)target->run(bytes_of(file));  // a crash or a sanitizer report fails the test
  }
}

std::vector<std::string> target_names() {
  std::vector<std::string> names;
  for (const FuzzTarget& t : fuzz_targets()) names.emplace_back(t.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(EachTarget, FuzzCorpus, testing::ValuesIn(target_names()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

}  // namespace
}  // namespace lap::fuzz
