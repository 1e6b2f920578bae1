// libFuzzer harness: the SQLite results store as `uascma report FILE` reads it (ResultsStore::Open,
// MakeCampaignReport, both renderings).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "uascma/campaign/report.h"
#include "uascma/campaign/store.h"
#include "uascma/common/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace uascma::campaign;
  const auto path = uascma::fuzz::WriteScratchFile(data, size, ".db");
  try {
    const ResultsStore store = ResultsStore::Open(path, StoreOptions{.busy_timeout_ms = 0});
    const CampaignReport report = MakeCampaignReport(store);
    (void)CampaignReportJson(report).dump(2, ' ', false, nlohmann::json::error_handler_t::replace);  // as PrintJson
    (void)CampaignReportText(report);
  } catch (const uascma::InputError&) {
  }
  return 0;
}
