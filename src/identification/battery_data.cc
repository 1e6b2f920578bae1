// Reading a recorded cell charge/discharge (see battery_data.h).
#include "uascma/identification/battery_data.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/identification/numeric_csv.h"

namespace uascma::identification {
namespace {

MappedColumn ParseMapped(const std::string& text) {
  MappedColumn column;
  column.negate = !text.empty() && text.front() == '-';
  column.name = column.negate ? text.substr(1) : text;
  if (column.name.empty()) throw InputError("--columns", "column", "key=NAME or key=-NAME with a non-empty NAME");
  return column;
}

std::vector<double> ReadMapped(const NumericCsv& csv, const MappedColumn& column) {
  std::vector<double> values = csv.Column(column.name);
  if (column.negate) {
    for (double& value : values) value = -value;
  }
  return values;
}

BatteryLayout RecogniseLayout(const NumericCsv& csv, const BatteryReadOptions& options) {
  if (options.columns) return BatteryLayout{"custom", *options.columns};
  const BatteryLayout nasa = NasaBatteryLayout();
  if (csv.HasColumn(nasa.map.time.name) && csv.HasColumn(nasa.map.current.name) && csv.HasColumn(nasa.map.voltage.name)) {
    return nasa;
  }
  BatteryLayout ours = OurBatteryLayout();
  if (!csv.HasColumn("temperature_degc")) ours.map.temperature.reset();
  if (!csv.HasColumn("cycle")) ours.map.cycle.reset();
  return ours;
}

// The rows of the chosen cycle (all rows without a cycle column).
std::vector<int> SelectRows(const NumericCsv& csv, const BatteryLayout& layout, const BatteryReadOptions& options,
                            std::optional<int>* cycle) {
  std::vector<int> rows;
  if (!layout.map.cycle) {
    if (options.cycle) {
      throw InputError(csv.source(), "--cycle", "a file with a cycle column (the NASA layout's cycle_idx, ours' cycle)");
    }
    for (int r = 0; r < csv.row_count(); ++r) rows.push_back(r);
    return rows;
  }
  const std::vector<double> cycles = csv.Column(layout.map.cycle->name);
  if (cycles.empty()) return rows;
  const double wanted = options.cycle ? static_cast<double>(*options.cycle) : cycles.front();
  for (int r = 0; r < csv.row_count(); ++r) {
    if (cycles[r] == wanted) rows.push_back(r);
  }
  if (rows.empty()) {
    std::set<double> present(cycles.begin(), cycles.end());
    throw InputError(csv.source(), "--cycle",
                     fmt::format("a cycle present in the file ({} to {}), got {}", *present.begin(), *present.rbegin(),
                                 wanted));
  }
  *cycle = static_cast<int>(wanted);
  return rows;
}

void CheckRecord(const BatteryRecord& record, const BatteryLayout& layout, const BatteryReadOptions& options) {
  for (int k = 1; k < record.size(); ++k) {
    if (!(record.time_s[k] > record.time_s[k - 1])) {
      throw InputError(fmt::format("{}:{}", record.source, record.line[k]), layout.map.time.name,
                       fmt::format("time strictly increasing, got {} after {}", record.time_s[k], record.time_s[k - 1]));
    }
  }
  if (record.size() < options.min_samples) {
    throw InputError(record.source, "samples",
                     fmt::format("at least {} samples for the cell model's order (eqs. 3.1-3.3), got {}",
                                 options.min_samples, record.size()));
  }
  const auto largest = std::max_element(record.current_a.begin(), record.current_a.end(),
                                        [](double a, double b) { return std::abs(a) < std::abs(b); });
  const int k = static_cast<int>(largest - record.current_a.begin());
  if (!options.charge && !(*largest > 0.0)) {
    throw InputError(fmt::format("{}:{}", record.source, record.line[k]), layout.map.current.name,
                     fmt::format("a discharge current positive in the {} layout, but the largest current is {} A "
                                 "(map a discharge-negative column with --columns current=-NAME)",
                                 layout.name, *largest));
  }
  if (options.charge && !(*largest < 0.0)) {
    throw InputError(fmt::format("{}:{}", record.source, record.line[k]), layout.map.current.name,
                     fmt::format("a charge record: its largest current negative (charging) in the {} layout, but it "
                                 "is {} A (a discharge record, or a column of the other sign)",
                                 layout.name, *largest));
  }
}

}  // namespace

BatteryLayout OurBatteryLayout() {
  return BatteryLayout{"ours", {{"time_s"}, {"current_a"}, {"voltage_v"}, MappedColumn{"temperature_degc"},
                                MappedColumn{"cycle"}}};
}

BatteryLayout NasaBatteryLayout() {
  // Saha & Goebel (2007): Current_measured is negative on discharge.
  return BatteryLayout{"nasa", {{"Time"}, {"Current_measured", true}, {"Voltage_measured"},
                                MappedColumn{"Temperature_measured"}, MappedColumn{"cycle_idx"}}};
}

BatteryColumnMap ParseBatteryColumnMap(const std::string& text) {
  BatteryColumnMap map;
  std::set<std::string> seen;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    start = comma == std::string::npos ? text.size() + 1 : comma + 1;
    const std::size_t equals = item.find('=');
    if (equals == std::string::npos) throw InputError("--columns", item, "key=NAME, e.g. current=-Current_measured");
    const std::string key = item.substr(0, equals);
    if (!seen.insert(key).second) throw InputError("--columns", key, "each key once, but it is given twice");
    const MappedColumn column = ParseMapped(item.substr(equals + 1));
    if (key == "time") map.time = column;
    else if (key == "current") map.current = column;
    else if (key == "voltage") map.voltage = column;
    else if (key == "temperature") map.temperature = column;
    else if (key == "cycle") map.cycle = column;
    else throw InputError("--columns", key, "one of time, current, voltage, temperature, cycle");
  }
  for (const char* required : {"time", "current", "voltage"}) {
    if (!seen.count(required)) throw InputError("--columns", required, "a column for it (key=NAME), but it is missing");
  }
  return map;
}

BatteryRecord ParseBatteryRecord(const std::string& text, const std::string& source, const BatteryReadOptions& options) {
  const NumericCsv csv = NumericCsv::Parse(text, source);
  const BatteryLayout layout = RecogniseLayout(csv, options);
  BatteryRecord record;
  record.source = source;
  record.layout = layout.name;
  record.cells_in_series = options.cells_in_series;
  const std::vector<int> rows = SelectRows(csv, layout, options, &record.cycle);
  const std::vector<double> time = ReadMapped(csv, layout.map.time);
  const std::vector<double> current = ReadMapped(csv, layout.map.current);
  const std::vector<double> voltage = ReadMapped(csv, layout.map.voltage);
  std::vector<double> temperature;
  if (layout.map.temperature) temperature = ReadMapped(csv, *layout.map.temperature);
  for (int r : rows) {
    record.time_s.push_back(time[r] - time[rows.front()]);
    record.current_a.push_back(current[r]);
    record.voltage_v.push_back(voltage[r] / options.cells_in_series);
    if (!temperature.empty()) record.temperature_degc.push_back(temperature[r]);
    record.line.push_back(csv.line_of_row(r));
  }
  CheckRecord(record, layout, options);
  return record;
}

BatteryRecord ReadBatteryRecord(const std::string& path, const BatteryReadOptions& options) {
  return ParseBatteryRecord(uascma::ReadFile(path), path, options);
}

}  // namespace uascma::identification
