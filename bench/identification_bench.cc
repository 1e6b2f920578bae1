// CPU time of one identification, from the parsed record to the model (docs/identification.md "Speed"):
//  - one cell: NASA B0005 cycle 1 (~200 samples, 2 A discharge and rest), the cell model of eqs. 3.1-3.3;
//  - one motor-propeller pair: its 2S and 3S thrust-stand files (21 points), eq. 2.12 by LAR with the
//    leave-one-step-out choice among three orders, and C_T.
// Reading the files is outside the timed loop (it is a few milliseconds of parsing). The figure to hold: < 1 s each.
#include <string>

#include <benchmark/benchmark.h>

#include "uascma/identification/battery_identification.h"
#include "uascma/identification/propulsion_identification.h"
#include "uascma/identification/thrust_stand_data.h"

namespace {

using namespace uascma::identification;

const std::string kData = std::string(UASCMA_SOURCE_DIR) + "/data/bench/";

void IdentifyNasaCell(benchmark::State& state) {
  BatteryReadOptions read;
  read.cycle = 1;
  const BatteryRecord record = ReadBatteryRecord(kData + "battery-nasa/B0005.csv", read);
  for (auto _ : state) {
    CellIdentification result = IdentifyCell(record);
    benchmark::DoNotOptimize(result);
  }
  state.counters["samples"] = record.size();
}
BENCHMARK(IdentifyNasaCell)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void IdentifyThrustStandPair(benchmark::State& state) {
  const std::vector<ThrustStandRecord> records = {ReadThrustStandRecord(kData + "dyno-strawson/g8_7.csv", 1),
                                                  ReadThrustStandRecord(kData + "dyno-strawson/g8_11.csv", 1)};
  PropulsionIdentificationOptions options;
  options.pole_pairs = 1;
  for (auto _ : state) {
    PropulsionIdentification result = IdentifyPropulsion(records, options);
    benchmark::DoNotOptimize(result);
  }
}
BENCHMARK(IdentifyThrustStandPair)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
