#pragma once
// Shared by the campaign tests: a campaign of short flights (~25 s of simulated time, ~10 ms each), so
// tests that fly dozens of them stay fast.
#include <unistd.h>

#include <filesystem>
#include <string>

#include "uascma/campaign/config.h"

namespace uascma::campaign::testing_support {

// Missions of 20–40 m at 4–9 m/s, 5 m up, 2 s drop hover. Ambient temperature always warm: a cold pack
// with one power-faded cell can make the pack EOD search take seconds per flight (reported to the
// simulator's owner; see the campaign report), which would only slow these tests down.
inline CampaignConfig ShortConfig() {
  CampaignConfig config;
  config.name = "short";
  config.seed = 11;
  config.runs = 12;
  config.mission.distance_m = {20.0, 40.0};
  config.mission.cruise_speed_mps = {4.0, 9.0};
  config.mission.cruise_altitude_m = 5.0;
  config.mission.drop_hover_s = 2.0;
  config.battery.cold_probability = 0.0;
  return config;
}

// The same as a campaign file.
inline std::string ShortConfigYaml() {
  return "name: short\n"
         "seed: 11\n"
         "runs: 12\n"
         "mission:\n"
         "  distance_m: [20, 40]\n"
         "  cruise_speed_mps: [4, 9]\n"
         "  cruise_altitude_m: 5\n"
         "  drop_hover_s: 2\n"
         "battery:\n"
         "  cold_probability: 0\n";
}

// A fresh folder under the system temp folder, removed at the end of the test.
struct TempDir {
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("uascma_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::filesystem::path path;
};

}  // namespace uascma::campaign::testing_support
