// Start-up of the command-line tool: `uascma` loads neither MPI nor PROJ unless a command
// needs them. The dynamic loader reports every library it maps (LD_DEBUG=libs), so these checks fail as soon
// as libmpi or libproj is linked into `uascma` again, and the controls show that the same check sees them
// when they are loaded: PROJ by the map import that projects, MPI by uascma-mpi, the tool mpirun runs.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "cli_runner.h"

namespace uascma {
namespace {

using testing_support::ScratchDir;
using testing_support::Slurp;

// The loader's report (stderr) of `environment uascma arguments`, run by the shell; stdout is discarded.
std::string LoaderReport(const std::string& environment, const std::string& program, const std::string& arguments,
                         const std::filesystem::path& scratch) {
  const auto report = scratch / "loader.txt";
  const std::string command =
      "env " + environment + " LD_DEBUG=libs " + program + " " + arguments + " >/dev/null 2>" + report.string();
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return Slurp(report);
}

// True when the loader initialised a library whose file name starts with `library`, from a report line such as
// "  4242:	calling init: /lib/x86_64-linux-gnu/libmpi.so.40".
bool Loads(const std::string& report, const std::string& library) {
  std::istringstream lines(report);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("calling init: ") == std::string::npos) continue;
    if (line.compare(line.rfind('/') + 1, library.size(), library) == 0) return true;
  }
  return false;
}

TEST(StartupCliTest, VersionLoadsNeitherMpiNorProj) {
  ScratchDir scratch("startup_version");
  const std::string report = LoaderReport("", UASCMA_CLI_PATH, "--version", scratch.path);
  // The report is there (the C library is always initialised), so an absent library is really absent.
  ASSERT_TRUE(Loads(report, "libc.so")) << report;
  EXPECT_FALSE(Loads(report, "libmpi")) << report;
  EXPECT_FALSE(Loads(report, "libproj")) << report;
}

TEST(StartupCliTest, MapImportLoadsProjWhenItProjects) {
  ScratchDir scratch("startup_map");
  // One 20 m building near the Manhattan origin of the shipped examples: the importer projects it with PROJ.
  const auto city = scratch.path / "one.geojson";
  std::ofstream(city) << R"({"type":"FeatureCollection","features":[{"type":"Feature",
    "properties":{"building":"yes","height":"20"},"geometry":{"type":"Polygon","coordinates":[[[-73.9700,40.7610],
    [-73.9695,40.7610],[-73.9695,40.7614],[-73.9700,40.7614],[-73.9700,40.7610]]]}}]})";
  const std::string report = LoaderReport("", UASCMA_CLI_PATH, "map info --json " + city.string(), scratch.path);
  EXPECT_TRUE(Loads(report, "libproj")) << report;
  EXPECT_FALSE(Loads(report, "libmpi")) << report;
}

TEST(StartupCliTest, UnderAnMpiLauncherTheToolContinuesWithMpi) {
  const auto launcher = std::filesystem::path(UASCMA_CLI_PATH).parent_path() / "uascma-mpi";
  if (!std::filesystem::exists(launcher)) GTEST_SKIP() << "built without MPI (UASCMA_WITH_MPI=OFF)";
  ScratchDir scratch("startup_mpi");
  EXPECT_TRUE(Loads(LoaderReport("", launcher.string(), "--version", scratch.path), "libmpi"));
  // mpirun's environment (one rank): `uascma` hands over to uascma-mpi, which loads MPI.
  EXPECT_TRUE(Loads(LoaderReport("OMPI_COMM_WORLD_SIZE=1", UASCMA_CLI_PATH, "--version", scratch.path), "libmpi"));
}

}  // namespace
}  // namespace uascma
