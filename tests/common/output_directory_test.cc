// OutputDirectory (common/files.h): an --out folder holds exactly one run's files, a folder
// uascma did not make is refused untouched, and errors name the user's path, never the staging folder.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma {
namespace {

namespace fs = std::filesystem;

class OutputDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("uascma_outdir_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  // The names in `folder`, hidden ones included.
  static std::set<std::string> Names(const fs::path& folder) {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder)) names.insert(entry.path().filename().string());
    return names;
  }
  static void Run(const fs::path& out, const std::set<std::string>& files) {
    OutputDirectory folder("--out", out);
    for (const auto& name : files) WriteFileAtomically(folder.staging() / name, name);
    folder.Commit();
  }

  fs::path root_;
};

TEST_F(OutputDirectoryTest, ASecondRunLeavesOnlyItsOwnFiles) {
  const fs::path out = root_ / "flight";
  Run(out, {"telemetry.csv", "map.json"});
  EXPECT_EQ(Names(out), (std::set<std::string>{kOutputMarker, "telemetry.csv", "map.json"}));
  Run(out, {"telemetry.csv"});  // no map this time: the old map.json must not survive
  EXPECT_EQ(Names(out), (std::set<std::string>{kOutputMarker, "telemetry.csv"}));
  // No staging or old folder is left beside it.
  EXPECT_EQ(Names(root_), (std::set<std::string>{"flight"}));
}

TEST_F(OutputDirectoryTest, NewNestedAndEmptyFoldersAreAccepted) {
  Run(root_ / "a" / "b" / "c", {"x"});
  EXPECT_TRUE(fs::is_regular_file(root_ / "a" / "b" / "c" / "x"));
  fs::create_directories(root_ / "empty");
  Run(root_ / "empty/", {"y"});  // a trailing slash names the same folder
  EXPECT_EQ(Names(root_ / "empty"), (std::set<std::string>{kOutputMarker, "y"}));
}

TEST_F(OutputDirectoryTest, AFolderUascmaDidNotMakeIsRefusedAndLeftAlone) {
  const fs::path mine = root_ / "documents";
  fs::create_directories(mine);
  std::ofstream(mine / "thesis.tex") << "keep me";
  try {
    OutputDirectory folder("--out", mine);
    FAIL() << "accepted a foreign folder";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("--out"), std::string::npos) << message;
    EXPECT_NE(message.find(mine.string()), std::string::npos) << message;
    EXPECT_EQ(message.find(".tmp."), std::string::npos) << message;
  }
  EXPECT_EQ(Names(mine), (std::set<std::string>{"thesis.tex"}));
  EXPECT_EQ(Names(root_), (std::set<std::string>{"documents"}));
  std::ofstream(root_ / "file") << "a file";
  EXPECT_THROW(OutputDirectory("--out", root_ / "file"), InputError);
}

TEST_F(OutputDirectoryTest, WithoutCommitNothingChanges) {
  const fs::path out = root_ / "flight";
  Run(out, {"old.csv"});
  {
    OutputDirectory folder("--out", out);
    WriteFileAtomically(folder.staging() / "new.csv", "half a run");
  }  // an exception would leave the scope like this
  EXPECT_EQ(Names(out), (std::set<std::string>{kOutputMarker, "old.csv"}));
  EXPECT_EQ(Names(root_), (std::set<std::string>{"flight"}));
}

// A parent that cannot be a folder (here a file stands where it would be; the same path as a read-only
// folder, but it fails for root as well).
TEST_F(OutputDirectoryTest, AnUncreatableFolderIsReportedUnderTheUsersPath) {
  std::ofstream(root_ / "file") << "a file";
  const fs::path out = root_ / "file" / "flight";
  try {
    OutputDirectory folder("--out", out);
    ADD_FAILURE() << "made a folder under a file";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(out.string()), std::string::npos) << message;
    EXPECT_EQ(message.find(".tmp."), std::string::npos) << message;
  }
  EXPECT_EQ(Names(root_), (std::set<std::string>{"file"}));
}

}  // namespace
}  // namespace uascma
