// SPDX-License-Identifier: MIT
// A command's output folder lands whole or not at all, replaces only folders softbench made,
// and clears what killed runs left.
#include "harness/report/staged_folder.h"

#include "geometry/input_error.h"
#include "tests/test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace softbench::harness {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

void write(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
}

std::string read(const fs::path& file) {
  std::ostringstream text;
  text << std::ifstream(file).rdbuf();
  return text.str();
}

/// Every entry of `folder` whose name starts with `prefix`.
int count_prefixed(const fs::path& folder, const std::string& prefix) {
  int count = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    count += entry.path().filename().string().rfind(prefix, 0) == 0 ? 1 : 0;
  }
  return count;
}

TEST(StagedFolder, NothingIsAtTheTargetUntilTheCommitThenEverything) {
  test::TempDir dir;
  const fs::path target = dir.path() / "out" / "run";
  StagedFolder out(target, "--out");
  write(out.path() / "metrics.json", "{}");
  write(out.path() / "summary.md", "# run");
  EXPECT_FALSE(fs::exists(target));
  out.commit();
  EXPECT_EQ(out.path(), target);
  EXPECT_EQ(read(target / "metrics.json"), "{}");
  EXPECT_EQ(read(target / "summary.md"), "# run");
  EXPECT_TRUE(fs::exists(target / StagedFolder::kMarkerFile));
  EXPECT_EQ(count_prefixed(dir.path() / "out", ".run"), 0);  // no staging left
}

TEST(StagedFolder, ACommitReplacesTheLastRunsFolderWhole) {
  test::TempDir dir;
  const fs::path target = dir.path() / "run";
  {
    StagedFolder first(target, "--out");
    write(first.path() / "metrics.json", "first");
    write(first.path() / "frame_00001.vtu", "first");
    first.commit();
  }
  StagedFolder second(target, "--out");
  write(second.path() / "metrics.json", "second");
  EXPECT_EQ(read(target / "metrics.json"), "first");  // untouched until the commit
  second.commit();
  EXPECT_EQ(read(target / "metrics.json"), "second");
  EXPECT_FALSE(fs::exists(target / "frame_00001.vtu"));  // nothing of the old run stays
  EXPECT_EQ(count_prefixed(dir.path(), ".run"), 0);
}

TEST(StagedFolder, AFailedOrInterruptedCommandLeavesTheOldFolderAsItWas) {
  test::TempDir dir;
  const fs::path target = dir.path() / "run";
  {
    StagedFolder first(target, "--out");
    write(first.path() / "metrics.json", "first");
    first.commit();
  }
  {
    StagedFolder second(target, "--out");
    write(second.path() / "metrics.json", "half");
    // An exception (a blow-up, Ctrl-C) unwinds before the commit.
  }
  EXPECT_EQ(read(target / "metrics.json"), "first");
  EXPECT_EQ(count_prefixed(dir.path(), ".run"), 0);
}

TEST(StagedFolder, RefusesAFolderSoftbenchDidNotMakeButTakesAnEmptyOne) {
  test::TempDir dir;
  fs::create_directories(dir.path() / "notes");
  write(dir.path() / "notes" / "thesis.md", "mine");
  try {
    StagedFolder out(dir.path() / "notes", "--out");
    FAIL() << "replaced a user's folder";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("--out "));
    EXPECT_THAT(error.what(), HasSubstr("notes: cannot write (a folder softbench did not make"));
  }
  EXPECT_EQ(read(dir.path() / "notes" / "thesis.md"), "mine");
  EXPECT_EQ(count_prefixed(dir.path(), ".notes"), 0);

  fs::create_directories(dir.path() / "empty");
  StagedFolder out(dir.path() / "empty", "--out");
  write(out.path() / "compare.json", "{}");
  out.commit();
  EXPECT_EQ(read(dir.path() / "empty" / "compare.json"), "{}");
}

TEST(StagedFolder, RefusesAFileAndANameThatIsNoFolder) {
  test::TempDir dir;
  write(dir.path() / "metrics.json", "{}");
  EXPECT_THROW(StagedFolder(dir.path() / "metrics.json", "--out"), InputError);
  EXPECT_THROW(StagedFolder(".", "--out"), InputError);
  EXPECT_THROW(StagedFolder("..", "--out"), InputError);
  EXPECT_THROW(StagedFolder(dir.path() / "metrics.json" / "run", "--out"), InputError);
}

TEST(StagedFolder, ClearsWhatKilledRunsLeftAndNothingOfARunningOne) {
  test::TempDir dir;
  // A pid above Linux's largest (2^22) never runs; pid 1 always does.
  const fs::path dead = dir.path() / ".run.staging-99999999-0";
  const fs::path alive = dir.path() / ".run.staging-1-0";
  fs::create_directories(dead);
  write(dead / "metrics.json", "killed");
  fs::create_directories(alive);
  const fs::path other = dir.path() / ".runner.staging-99999999-0";  // another folder's
  fs::create_directories(other);
  StagedFolder out(dir.path() / "run", "--out");
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(alive));
  EXPECT_TRUE(fs::exists(other));
}

}  // namespace
}  // namespace softbench::harness
