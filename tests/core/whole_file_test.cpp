// core/whole_file.h: a file written whole or not at all. A full disk is tested where the callers
// meet it (a real ENOSPC: tests/hardware/device_recording_test.cpp, tests/project/cli_test.cpp);
// here the other ways a write fails, each leaving nothing behind, and the file's mode.

#include "core/whole_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace lap {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(WholeFile, ReplacesTheFileForItsOwnerOnlyAndLeavesNothingElse) {
  const test::TempDir dir;
  const fs::path file = dir.path() / "metrics.json";
  ASSERT_TRUE(write_file_whole(file, "first", "the metrics").ok());
  const Status again = write_file_whole(file, std::string(100000, 'x'), "the metrics");
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_EQ(test::read_file(file), std::string(100000, 'x'));
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"metrics.json"});
  ASSERT_TRUE(write_file_whole(file, "", "the metrics").ok());  // empty is a content too
  EXPECT_EQ(fs::file_size(file), 0U);
}

TEST(WholeFile, AFileNamedWithoutAFolderGoesInTheCurrentOne) {
  const test::TempDir dir;
  const fs::path before = fs::current_path();
  fs::current_path(dir.path());
  const Status written = write_file_whole("plain.txt", "text", "the text");
  fs::current_path(before);
  ASSERT_TRUE(written.ok()) << written.message();
  EXPECT_EQ(test::read_file(dir.path() / "plain.txt"), "text");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"plain.txt"});
}

TEST(WholeFile, AWriteThatCannotBeDoneNamesTheFileAndTheReasonAndLeavesNothing) {
  const test::TempDir dir;
  // A folder where the file should be: the temporary file is written, then cannot take its name.
  fs::create_directory(dir.path() / "taken");
  fs::create_directory(dir.path() / "taken" / "inside");  // not empty: rename cannot replace it
  const Status over_folder = write_file_whole(dir.path() / "taken", "text", "the metrics");
  ASSERT_FALSE(over_folder.ok());
  EXPECT_EQ(over_folder.message(), (dir.path() / "taken").string() +
                                       ": cannot write the metrics: " + std::strerror(EISDIR) +
                                       " (nothing of it was written)");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"taken"});  // no temporary file
  // No folder to write in.
  const Status nowhere = write_file_whole(dir.path() / "missing" / "f.lapdev", "x",
                                          "the device "
                                          "recording");
  ASSERT_FALSE(nowhere.ok());
  EXPECT_EQ(nowhere.message(), (dir.path() / "missing" / "f.lapdev").string() +
                                   ": cannot write the device recording: " + std::strerror(ENOENT) +
                                   " (nothing of it was written)");
}

// IfTaken::kRefuse (a session's record is written once): written where the name is free, never
// over a file of that name, nor over a dangling link of it, and nothing left behind.
TEST(WholeFile, ARefusedNameKeepsWhatIsThereAndLeavesNothingElse) {
  const test::TempDir dir;
  const fs::path file = dir.path() / "session.json";
  ASSERT_TRUE(write_file_whole(file, "first", "a session's record", IfTaken::kRefuse).ok());
  const Status again = write_file_whole(file, "second", "a session's record", IfTaken::kRefuse);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.message(),
            file.string() + ": already exists: a session's record is written once");
  EXPECT_EQ(test::read_file(file), "first");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"session.json"});
  // A link whose target does not exist is a name taken too: writing through it could land
  // anywhere.
  const fs::path link = dir.path() / "linked.json";
  fs::create_symlink(dir.path() / "nowhere.json", link);
  const Status over_link = write_file_whole(link, "text", "a session's record", IfTaken::kRefuse);
  ASSERT_FALSE(over_link.ok());
  EXPECT_EQ(over_link.message(),
            link.string() + ": already exists: a session's record is written once");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_FALSE(fs::exists(dir.path() / "nowhere.json"));
  EXPECT_EQ(names_in(dir.path()), (std::vector<std::string>{"linked.json", "session.json"}));
}

}  // namespace
}  // namespace lap
