#pragma once
// What `uascma validate battery` prints of a cell's validation on one or several records (battery_validation.h):
// each record's voltage errors and EOD checks as text and JSON, and the errors of several records pooled.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/identification/battery_validation.h"

namespace uascma::identification {

// The voltage errors of several validations together: RMS over every record's window (each window's RMS weighted by
// its samples), the largest error of any.
struct PooledValidationError {
  double rms_mv = 0.0;
  double max_mv = 0.0;
  int samples = 0;
};
PooledValidationError PoolValidationErrors(const std::vector<CellValidation>& results);

// One record's validation: {file, cycle, voltage_rms_mv, ..., eod: [...]}, and its text (a line, then one per EOD
// check).
nlohmann::json CellValidationJson(const CellValidation& result, const BatteryRecord& record,
                                  const CellValidationOptions& options);
std::string CellValidationText(const CellValidation& result, const BatteryRecord& record,
                               const CellValidationOptions& options);

// results[r] is records[r]'s. One record: its object with "records": [it]. Several: the pooled errors, every EOD
// check with its file and cycle, and "records". The text: each record's, then the pooled line when there are several.
nlohmann::json CellValidationsJson(const std::vector<CellValidation>& results,
                                   const std::vector<BatteryRecord>& records, const CellValidationOptions& options);
std::string CellValidationsText(const std::vector<CellValidation>& results, const std::vector<BatteryRecord>& records,
                                const CellValidationOptions& options);

}  // namespace uascma::identification
