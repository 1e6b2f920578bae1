// Wind-tunnel rows to the drag table (identification/drag_identification.h), on tables we make from a known drag law.
#include "uascma/identification/drag_identification.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/models/drag.h"

namespace uascma::identification {
namespace {

constexpr double kAirDensity = 1.225;  // kg/m³, as docs/defaults.md#drag
constexpr double kExactN = 1e-12;      // N: the v² carry and the median are a few roundings

// docs/defaults.md#drag's tractor law, D = ½ ρ (0.05 |cos θ| + 0.10 |sin θ|) v², our stand-in for a measured airframe.
double Law(double speed, double pitch_deg) {
  const double theta = pitch_deg * M_PI / 180.0;
  return 0.5 * kAirDensity * (0.05 * std::abs(std::cos(theta)) + 0.10 * std::abs(std::sin(theta))) * speed * speed;
}

// Table 2.3's matrix (2.2, 4.5, 6.7, 8.9 m/s; −30° to 30°), each cell three times at the nominal speed ± 0.2 m/s as a
// tunnel that cannot set its speed exactly, plus powered rows (1500 µs, more drag) that must be left out.
std::string Tunnel(double outlier_factor = 1.0) {
  std::string text = "airspeed_mps,pitch_deg,lift_n,drag_n,throttle_us\n";
  for (double speed : {2.2, 4.5, 6.7, 8.9}) {
    for (int pitch = -30; pitch <= 30; pitch += 10) {
      for (double jitter : {-0.2, 0.0, 0.2}) {
        const double v = speed + jitter;
        const double factor = (jitter == 0.2 && pitch == 10) ? outlier_factor : 1.0;
        text += fmt::format("{},{},{},{},0\n", v, pitch, 0.01 * pitch, factor * Law(v, pitch));
      }
      text += fmt::format("{},{},{},{},1500\n", speed, pitch, 1.0, 3.0 * Law(speed, pitch));
    }
  }
  return text;
}

TEST(DragIdentificationTest, ATunnelTableOfAKnownLawGivesTheLawAtEachSpeedAndPitch) {
  const DragIdentification table = IdentifyDrag(ParseWindTunnelRecord(Tunnel(), "tunnel.csv"));
  EXPECT_EQ(table.bare_rows, 4 * 7 * 3);
  EXPECT_EQ(table.powered_rows, 4 * 7);
  EXPECT_TRUE(table.zero_speed_added);
  ASSERT_EQ(table.airspeeds_mps.size(), 5u);
  ASSERT_EQ(table.pitches_deg.size(), 7u);
  EXPECT_EQ(table.largest_repeat_count, 3);
  for (std::size_t i = 0; i < table.airspeeds_mps.size(); ++i) {
    for (std::size_t j = 0; j < table.pitches_deg.size(); ++j) {
      EXPECT_NEAR(table.drag_n[i * 7 + j], Law(table.airspeeds_mps[i], table.pitches_deg[j]), kExactN)
          << table.airspeeds_mps[i] << " m/s, " << table.pitches_deg[j] << " deg";
    }
  }
  // The CSV is the simulator's: DragTable::FromCsv reads it back, and between the grid's speeds it interpolates.
  const auto path = std::filesystem::temp_directory_path() / ("uascma_drag_" + std::to_string(::getpid()) + ".csv");
  std::ofstream(path) << table.DragCsv();
  const models::DragTable read = models::DragTable::FromCsv(path);
  std::filesystem::remove(path);
  EXPECT_NEAR(read.Drag(4.5, 10.0 * M_PI / 180.0), Law(4.5, 10.0), 1e-9);
  EXPECT_EQ(read.Drag(0.0, 0.0), 0.0);
}

// The repeats of one cell reduce to their median: a repeat ten times too large (a gust, a loose stand) moves nothing.
TEST(DragIdentificationTest, ARepeatFarOffDoesNotMoveTheCell) {
  const DragIdentification table = IdentifyDrag(ParseWindTunnelRecord(Tunnel(10.0), "tunnel.csv"));
  const std::size_t pitch_10 = 4;  // −30, −20, −10, 0, 10
  for (std::size_t i = 1; i < table.airspeeds_mps.size(); ++i) {
    EXPECT_NEAR(table.drag_n[i * 7 + pitch_10], Law(table.airspeeds_mps[i], 10.0), kExactN);
  }
  EXPECT_GT(table.largest_repeat_spread_n, 5.0 * Law(8.9, 10.0));
}

TEST(DragIdentificationTest, BadTunnelDataNamesTheFileTheLineAndTheColumn) {
  const auto refused = [](const std::string& text, const std::string& where) {
    try {
      (void)IdentifyDrag(ParseWindTunnelRecord(text, "tunnel.csv"));
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    }
  };
  const std::string header = "airspeed_mps,pitch_deg,lift_n,drag_n,throttle_us\n";
  refused("airspeed_mps,pitch_deg,lift_n,drag_n\n2,0,0,1\n", "throttle_us");
  refused(header + "2,0,0,1,0\n2,10,0,-1,0\n", "tunnel.csv:3");
  refused(header + "2,0,0,1,0\n2,10,0,x,0\n", "drag_n");
  refused(header + "2,0,0,1,1500\n", "bare airframe");
  // 5 m/s has no row at 10 deg.
  refused(header + "2,0,0,1,0\n2,10,0,1,0\n5,0,0,6,0\n", "10 deg has no bare-airframe row at 5 m/s");
}

}  // namespace
}  // namespace uascma::identification
