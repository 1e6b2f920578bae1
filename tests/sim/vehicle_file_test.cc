// Vehicle files (sim/vehicle_file.h): the cell, the parallel count, the rotor directions and the mass reach the
// models the simulator and the CMA read; a file that leaves everything out flies the dissertation's vehicle bit for
// bit; bad files name the file and the key.
#include "uascma/sim/vehicle_file.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "uascma/common/error.h"
#include "uascma/identification/model_files.h"
#include "uascma/models/ocv_table.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {
namespace {

struct Folder {
  explicit Folder(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("uascma_vehicle_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~Folder() { std::filesystem::remove_all(path); }
  std::filesystem::path Write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return path / name;
  }
  std::filesystem::path path;
};

// A CELL.json (identification/model_files.h) of Table 3.1's cell 1 with capacity `capacity_ah` and the default OCV.
std::string CellJson(double capacity_ah) {
  models::CellParams p = models::Table31Cell(1);
  p.capacity_ah = capacity_ah;
  const models::OcvTable ocv = models::DefaultOcvTable();
  const nlohmann::json json = {{"format", identification::kCellModelFormat},
                               {"parameters", identification::CellParamsJson(p)},
                               {"ocv", {{"soc_fraction", ocv.soc_fraction()}, {"voltage_v", ocv.voltage_v()}}}};
  return json.dump();
}

// The EOD (s) the CMA reads at the first epoch (Observe: the forecast load of the whole plan, the pack at rest).
double FirstEpochEod(const Scenario& scenario) {
  const FlightModel model(scenario);
  FlightState state = MakeInitialState(model, scenario.seed);
  return Observe(model, state, nullptr, false).eod_value().eod_s;
}

Scenario Delivery() {
  Scenario scenario;
  scenario.mission.destination_NE = Eigen::Vector2d(300, 200);
  return scenario;
}

// Eq. 3.1: dz/dt = −η i / Q, so from the same rest voltage at the same load the time to the cut-off scales with Q.
// The file's Q is what the CMA's EOD reads: 20 % less capacity, about 20 % less EOD (the RC pair's slower transient
// is the rest; 2 % tolerance, as the eod command's check of CELL.json).
TEST(VehicleFileTest, TheCellFileCapacityChangesTheEodTheCmaReads) {
  const Folder folder("capacity");
  const models::CellParams table = models::Table31Cell(1);
  folder.Write("full.json", CellJson(table.capacity_ah));
  folder.Write("faded.json", CellJson(0.8 * table.capacity_ah));
  Scenario full = Delivery(), faded = Delivery();
  UseVehicle(full, LoadVehicleFile(folder.Write("full.yaml", "battery: {cell: full.json}\n")));
  UseVehicle(faded, LoadVehicleFile(folder.Write("faded.yaml", "battery: {cell: faded.json}\n")));
  const double full_s = FirstEpochEod(full), faded_s = FirstEpochEod(faded);
  EXPECT_GT(full_s, 300.0);
  EXPECT_NEAR(faded_s / full_s, 0.8, 0.02);
  // And the file's cell is not Table 3.1's three cells: the same Q as cell 1 in all six positions differs from the
  // default pack (cells 1-3 differ in Q and R0), so the EOD differs too.
  EXPECT_NE(full_s, FirstEpochEod(Delivery()));
}

// P identical cells in parallel are one cell of P Q, R0 / P, R1 / P, P C1: the same time constant R1 C1, and at P
// times the current the same SOC rate (eq. 3.1) and the same voltage drops (eq. 3.3).
TEST(VehicleFileTest, ParallelCellsScaleAsOneCell) {
  const models::CellParams cell = models::Table31Cell(2);
  const models::CellParams two = ParallelCell(cell, 2);
  EXPECT_DOUBLE_EQ(two.capacity_ah, 2.0 * cell.capacity_ah);
  EXPECT_DOUBLE_EQ(two.r0_ohm * 2.0, cell.r0_ohm);
  EXPECT_DOUBLE_EQ(two.rc[0].resistance_ohm * two.rc[0].capacitance_f,
                   cell.rc[0].resistance_ohm * cell.rc[0].capacitance_f);
  EXPECT_DOUBLE_EQ(two.hysteresis_m_v, cell.hysteresis_m_v);
  // In a flight: two cells in parallel from the same rest voltage at the same load last about twice as long.
  const Folder folder("parallel");
  Scenario one = Delivery(), parallel = Delivery();
  UseVehicle(parallel, LoadVehicleFile(folder.Write("v.yaml", "battery: {cells_in_parallel: 2}\n")));
  EXPECT_NEAR(FirstEpochEod(parallel) / FirstEpochEod(one), 2.0, 0.1);
}

// A file that sets nothing keeps every model: the flight is the dissertation vehicle's, bit for bit.
TEST(VehicleFileTest, AFileThatSetsNothingFliesTheDissertationVehicle) {
  const Folder folder("empty");
  const auto vehicle = LoadVehicleFile(folder.Write("v.yaml", "name: as-published\n"));
  // mass_kg, inertia_kg_m2, arm_length_m, rotor_directions, battery, propulsion, drag: each listed.
  EXPECT_EQ(vehicle->defaulted.size(), 7u);
  EXPECT_NE(vehicle->DefaultedLine().find("mass_kg"), std::string::npos);
  Scenario plain = Delivery(), filed = Delivery();
  UseVehicle(filed, vehicle);
  NoOpPolicy a, b;
  const SimResult x = Simulator(plain).Run(a), y = Simulator(filed).Run(b);
  EXPECT_EQ(x.outcome, y.outcome);
  EXPECT_EQ(x.sim_time_s, y.sim_time_s);
  EXPECT_EQ(x.min_cell_voltage_v, y.min_cell_voltage_v);
  EXPECT_EQ(x.energy_wh, y.energy_wh);
}

// Mirrored rotor directions change only the yaw row of eq. 4.11's matrix, and change its sign.
TEST(VehicleFileTest, MirroredRotorDirectionsFlipTheYawRow) {
  const Folder folder("mirrored");
  const auto vehicle =
      LoadVehicleFile(folder.Write("v.yaml", "rotor_directions: [ccw, cw, ccw, cw, ccw, cw]\narm_length_m: 0.1\n"));
  EXPECT_FALSE(vehicle->mixer.rotor1_clockwise);
  models::MixerParams published = models::MixerParams::ForPropulsion(vehicle->propulsion);
  published.arm_length = 0.1;
  const models::MixingMatrix m = models::CalcMixingMatrix(vehicle->mixer, 0);
  const models::MixingMatrix n = models::CalcMixingMatrix(published, 0);
  EXPECT_TRUE(m.topRows<3>().isApprox(n.topRows<3>(), 0.0));
  EXPECT_TRUE(m.row(3).isApprox(-n.row(3), 0.0));
  EXPECT_DOUBLE_EQ(m(2, 0), 0.1 * std::cos(models::RotorAzimuth(1)));  // τy = L cos ψ T (models/mixer.h)
}

// The mass is the LQR's and the flyability check's: a vehicle the six rotors cannot hold up is refused, naming it.
TEST(VehicleFileTest, TheMassIsCheckedAgainstTheRotorsThrust) {
  const Folder folder("heavy");
  Scenario scenario = Delivery();
  // Table 2.2: six rotors give 26.85 N, 2.74 kg at most.
  UseVehicle(scenario, LoadVehicleFile(folder.Write("v.yaml", "mass_kg: 2.9\n")));
  std::string error;
  EXPECT_FALSE(scenario.IsValid(&error));
  EXPECT_NE(error.find("mass_kg 2.9"), std::string::npos) << error;
  EXPECT_NE(error.find("v.yaml"), std::string::npos) << error;
}

TEST(VehicleFileTest, BadFilesNameTheFileAndTheKey) {
  const Folder folder("bad");
  const auto refused = [&](const std::string& text, const std::string& key) {
    const std::filesystem::path file = folder.Write("bad.yaml", text);
    try {
      (void)LoadVehicleFile(file);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file.string()), std::string::npos) << what;
      EXPECT_NE(what.find(key), std::string::npos) << what;
    }
  };
  refused("battery: {cells_in_series: 4}\n", "battery.cells_in_series");
  refused("battery: {cells_in_parallel: 0}\n", "battery.cells_in_parallel");
  refused("rotor_directions: [cw, cw, ccw, cw, ccw, cw]\n", "rotor_directions[1]");
  refused("mass_kg: 100\n", "mass_kg");
  refused("arm_length_m: -1\n", "arm_length_m");
  refused("wings: 2\n", "wings");
  refused("battery: {cell: missing.json}\n", "battery.cell");
  refused("propulsion: [1]\n", "propulsion");
}

}  // namespace
}  // namespace uascma::sim
