#pragma once
// The identified models as JSON files (docs/identification.md "Files"): CELL.json (the cell model of eqs. 3.1-3.3 with
// its OCV table, uncertainties and what was not identified) and PROP.json (eq. 2.12's surface with its
// normalisation, range and prediction-bound data, eq. 2.1's C_T). A file is the same document `--json` prints, so
// its top-level keys are what scripts read (capacity_ah, r0_ohm, fit_rms_mv; c_t, loo_rpm_median_relative_error).
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "uascma/identification/battery_data.h"
#include "uascma/identification/battery_identification.h"
#include "uascma/identification/propulsion_identification.h"
#include "uascma/models/battery_cell.h"
#include "uascma/models/battery_pack.h"

namespace uascma::identification {

inline constexpr const char* kCellModelFormat = "uascma-cell-model-1";
inline constexpr const char* kPropulsionModelFormat = "uascma-propulsion-model-1";

// CELL.json's "parameters" block: the cell model as ReadCellModelFile reads it (every RC pair in use).
nlohmann::json CellParamsJson(const models::CellParams& params);
// The CELL.json document; `charge` the charge record when the identification had one (its "charge" block; null
// without).
nlohmann::json CellIdentificationJson(const CellIdentification& identification, const BatteryRecord& record,
                                      const std::optional<BatteryRecord>& charge = std::nullopt);
// Reads CELL.json through JsonDocument: InputError naming the file and the field for anything missing or invalid
// (parameters checked by CellParams::IsValid, the OCV table by its contract).
models::SelfCorrectingCell ReadCellModelFile(const std::filesystem::path& path);

// The pack of Fig. 4.1 (two 3S packs in parallel) built from one identified cell: every cell gets its parameters
// with Table 3.2's health and temperature applied (models::ApplyCellConditions), and its OCV table.
models::PackParams MakeIdentifiedPackParams(const models::SelfCorrectingCell& cell,
                                            const models::PerCell<models::CellHealth>& health, double ambient_temp_degf);

nlohmann::json PropulsionIdentificationJson(const PropulsionIdentification& identification,
                                            const PropulsionIdentificationOptions& options);
struct PropulsionModel {
  RpmSurface surface;
  double thrust_coefficient_n_per_rpm2 = 0.0;
  std::optional<double> torque_coefficient_nm_per_rpm2;
  std::optional<double> max_thrust_n;               // N, the largest measured thrust (absent in older files)
  std::optional<double> power_law_w_at_one_newton;  // W, k of P = k T^b (absent: not fitted)
  std::optional<double> power_law_exponent;         // b
};
PropulsionModel ReadPropulsionModelFile(const std::filesystem::path& path);

}  // namespace uascma::identification
