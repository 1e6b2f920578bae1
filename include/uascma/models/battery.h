#pragma once
// The battery models of uascma in one include (dissertation §3.3, §4.3):
//   ocv_table.h     OCV(SOC), the default table of docs/defaults.md#battery and a CSV loader;
//   battery_cell.h  the Enhanced Self-Correcting cell model (eqs. 3.1–3.3), Table 3.1 parameters,
//                   degradation and temperature (Table 3.2);
//   battery_pack.h  two 3S packs in parallel with switches and diodes (eqs. 3.4–3.7, Fig. 4.1,
//                   Table 4.3) and the G/M/P health classes (docs/modelling-choices.md#battery-health-label).
// The end-of-discharge prognosis built on them is uascma/prognostics/eod.h.
#include "uascma/models/battery_cell.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/ocv_table.h"
