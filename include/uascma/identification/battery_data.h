#pragma once
// A recorded charge/discharge of one cell (or a pack of N cells in series), read from CSV for the identification
// and validation of the Enhanced Self-Correcting cell model (dissertation §3.3.1.1, eqs. 3.1-3.3;
// docs/identification.md "Battery layouts").
//
// Sign convention (the cell model's, Plett's): current is POSITIVE ON DISCHARGE. A layout that records discharge
// as negative (NASA's) is read through a column map that negates the column ("current=-Current_measured").
//
// Layouts:
//   ours   time_s,current_a,voltage_v[,temperature_degc][,cycle]     current positive on discharge
//   NASA   Voltage_measured,Current_measured,Temperature_measured,Current_load,Voltage_load,Time,cycle_idx
//          (Saha & Goebel 2007; recognised by its header; discharge negative, so the map negates it)
//   other  any header, through --columns "time=NAME,current=[-]NAME,voltage=NAME[,temperature=NAME][,cycle=NAME]"
#include <optional>
#include <string>
#include <vector>

namespace uascma::identification {

// One column of the map: its header name, and whether the values are negated on reading.
struct MappedColumn {
  std::string name;
  bool negate = false;
};

struct BatteryColumnMap {
  MappedColumn time;                        // s
  MappedColumn current;                     // A, positive on discharge after the optional negation
  MappedColumn voltage;                     // V, terminal
  std::optional<MappedColumn> temperature;  // °C
  std::optional<MappedColumn> cycle;        // cycle number: rows of one cycle are read together
};

// "ours", "nasa" or "custom", for reports.
struct BatteryLayout {
  std::string name;
  BatteryColumnMap map;
};

// Our documented layout (above).
BatteryLayout OurBatteryLayout();
// NASA's layout (above), with the current negated.
BatteryLayout NasaBatteryLayout();
// Parses "--columns" text; throws InputError("--columns", …) for an unknown key, a key given twice or a missing one
// of time/current/voltage.
BatteryColumnMap ParseBatteryColumnMap(const std::string& text);

struct BatteryRecord {
  std::string source;  // the file
  std::string layout;  // "ours", "nasa", "custom"
  std::optional<int> cycle;              // the cycle read, when the layout has a cycle column
  int cells_in_series = 1;               // the voltage below is per cell: the file's divided by this
  std::vector<double> time_s;            // [samples], strictly increasing, from the record's start
  std::vector<double> current_a;         // [samples], positive on discharge
  std::vector<double> voltage_v;         // [samples], per cell
  std::vector<double> temperature_degc;  // [samples] or empty
  std::vector<int> line;                 // [samples], the file line of each sample
  int size() const { return static_cast<int>(time_s.size()); }
};

struct BatteryReadOptions {
  std::optional<BatteryColumnMap> columns;  // nullopt: the layout is recognised by the header
  std::optional<int> cycle;                 // nullopt: the first cycle in the file
  int cells_in_series = 1;
  int min_samples = 20;  // fewer: InputError (the model's order needs more; ours, docs/identification.md)
  // The record is a charge (current negative: the cell charged from empty to full, identify battery --charge);
  // false: a discharge (its largest current positive).
  bool charge = false;
};

// Reads one record. Throws InputError naming the file, the line and the column for: a missing or misnamed column,
// a cell that is not a finite number, time not strictly increasing, a record with no discharge or whose largest
// current is negative (the wrong sign for the layout; for a charge record: its largest current positive), a cycle
// that is not in the file, too few samples.
BatteryRecord ReadBatteryRecord(const std::string& path, const BatteryReadOptions& options);
// The same from text (tests, fuzzing); `source` names it in errors.
BatteryRecord ParseBatteryRecord(const std::string& text, const std::string& source, const BatteryReadOptions& options);

}  // namespace uascma::identification
