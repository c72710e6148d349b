// The bad-input corpus (tests/bad-inputs/, issue 25): every case, run through the command line
// as a user would meet it, exits 2 with its exact message (tests/bad-inputs/cases.txt).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace lap::test {
namespace {

struct Case {
  std::string file;      // below tests/bad-inputs/
  std::string expected;  // the first line on standard error
  int line = 0;          // in cases.txt
};

std::filesystem::path corpus() { return source_dir() / "tests/bad-inputs"; }

std::vector<Case> read_cases() {
  std::ifstream in(corpus() / "cases.txt");
  std::vector<Case> cases;
  int n = 0;
  for (std::string text; std::getline(in, text);) {
    ++n;
    if (text.empty() || text[0] == '#') continue;
    const size_t arrow = text.find(" -> ");
    if (arrow == std::string::npos) {
      ADD_FAILURE() << "cases.txt:" << n << ": expected 'FILE -> MESSAGE'";
      continue;
    }
    Case c{text.substr(0, arrow), text.substr(arrow + 4), n};
    for (size_t at = 0; (at = c.expected.find("$DIR", at)) != std::string::npos;) {
      c.expected.replace(at, 4, corpus().string());
      at += corpus().string().size();
    }
    cases.push_back(std::move(c));
  }
  return cases;
}

// The command that reads the case's file, by its extension: a mesh through mesh-info, a scenario
// through validate, a keyframe script as the left tool's scripted device, a device recording as
// its replay device; a folder is a recorded session, through report.
std::string command_for(const std::filesystem::path& file) {
  const std::string cli = "'" + (bin_dir() / "laptrainer-cli").string() + "'";
  const std::string ext = file.extension().string();
  const std::string quoted = "'" + file.string() + "'";
  if (std::filesystem::is_directory(file)) return cli + " report --session " + quoted;
  if (ext == ".yaml") return cli + " validate --scenario " + quoted;
  if (ext == ".csv" || ext == ".lapdev") {
    return cli + " run --scenario '" + (source_dir() / "scenarios/introductory.yaml").string() +
           "' --left " + (ext == ".csv" ? "scripted:" : "replay:") + quoted +
           " --right simulated --fast --duration 0.01";
  }
  return cli + " mesh-info --mesh " + quoted;
}

TEST(BadInputs, EveryCaseExitsTwoWithItsExactMessage) {
  const std::vector<Case> cases = read_cases();
  EXPECT_GE(cases.size(), 170U);  // none lost by accident
  for (const Case& c : cases) {
    SCOPED_TRACE("cases.txt:" + std::to_string(c.line) + ": " + c.file);
    const std::filesystem::path file = corpus() / c.file;
    ASSERT_TRUE(std::filesystem::exists(file));
    const CommandResult r = run_command(command_for(file));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.substr(0, r.err.find('\n')), c.expected);
  }
}

}  // namespace
}  // namespace lap::test
