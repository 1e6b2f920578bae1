#pragma once
// What the identification commands draw (`identify … --plot`, `validate … --plot`; docs/identification.md): the
// results of the identification library laid out as the JSON the scripts python/plots/battery_identification.py,
// propulsion_identification.py and drag_table.py read (each script's docstring gives the layout). Every number
// drawn is computed here or by the library; the scripts only draw.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/identification/battery_data.h"
#include "uascma/identification/battery_identification.h"
#include "uascma/identification/battery_validation.h"
#include "uascma/identification/drag_identification.h"
#include "uascma/identification/propulsion_identification.h"

namespace uascma::cli {

// The fit of eqs. 3.1-3.3 to its record (§3.3.1.1): voltages, current, error and the OCV(z) identified (with a
// charge record, the two branches it is the mean of).
nlohmann::json CellFitPlotJson(const identification::CellIdentification& result,
                               const identification::BatteryRecord& record,
                               const std::optional<identification::BatteryRecord>& charge = std::nullopt);

// Fig. 3.5: a cell model against a record not used in its fit, the summary window and the EOD checks (§3.3.2.1).
nlohmann::json CellValidationPlotJson(const identification::CellValidation& result,
                                      const identification::BatteryRecord& record,
                                      const identification::CellValidationOptions& options, const std::string& model);

// Fig. 2.10: eq. 2.12's surface along each file's measured power with its 95 % prediction bounds, the
// leave-one-step-out predictions, and eq. 2.1's thrust against the measured one.
nlohmann::json PropulsionFitPlotJson(const identification::PropulsionIdentification& result,
                                     const std::vector<identification::ThrustStandRecord>& records,
                                     const identification::PropulsionIdentificationOptions& options);

// Fig. 2.11: a pair's model on files not used in its fit, points outside the fitted range flagged.
nlohmann::json PropulsionValidationPlotJson(const identification::PropulsionValidation& result,
                                            const std::vector<identification::ThrustStandRecord>& records,
                                            const std::string& model);

// The drag table against airspeed, one line per pitch, over the bare-airframe rows it was reduced from.
nlohmann::json DragTablePlotJson(const identification::DragIdentification& result,
                                 const identification::WindTunnelRecord& record);

}  // namespace uascma::cli
