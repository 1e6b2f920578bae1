#pragma once
// The options that read battery records (identify battery, validate battery): the files, the column map, the cells
// in series and the cycle (identification/battery_data.h).
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bounded_option.h"
#include "uascma/common/bounds.h"
#include "uascma/identification/battery_data.h"

namespace uascma::cli {

// Cells in series of one record: 1 to 24 (ours: a 24S pack is the largest small-UAS pack in common use).
constexpr Bounds kRecordCellsBounds{1.0, 24.0, ""};
constexpr Bounds kRecordCycleBounds{0.0, 1e6, ""};

struct BatteryOptions {
  std::vector<std::string> data;
  std::string out, columns, plot;
  int cells = 1;
  int cycle = 1;
  CLI::Option* cycle_option = nullptr;  // given or not
  bool json = false;
};

inline void AddBatteryReadOptions(CLI::App* command, BatteryOptions* options) {
  command->add_option("DATA", options->data, "CSV of a recorded discharge (layouts: docs/identification.md)")
      ->required();
  command->add_option("--columns", options->columns,
                      "Column map for another layout: time=NAME,current=[-]NAME,voltage=NAME[,temperature=NAME]"
                      "[,cycle=NAME]; a leading '-' negates (current must be positive on discharge)");
  AddBoundedOption(command, "--cells", options->cells, "Cells in series in the record (voltage divided by it)", kRecordCellsBounds);
  options->cycle_option = AddBoundedOption(command, "--cycle", options->cycle,
                                            "Cycle to read where the layout has a cycle column (default: the first)",
                                            kRecordCycleBounds);
}

// The read options of the records: the column map, the cells, and `cycle` when given.
inline identification::BatteryReadOptions MakeReadOptions(const BatteryOptions& options, std::optional<int> cycle) {
  identification::BatteryReadOptions read;
  if (!options.columns.empty()) read.columns = identification::ParseBatteryColumnMap(options.columns);
  read.cycle = cycle;
  read.cells_in_series = options.cells;
  return read;
}

inline identification::BatteryRecord ReadRecord(const BatteryOptions& options, const std::string& path) {
  const std::optional<int> cycle = options.cycle_option->count() > 0 ? std::optional<int>(options.cycle) : std::nullopt;
  return identification::ReadBatteryRecord(path, MakeReadOptions(options, cycle));
}

}  // namespace uascma::cli
