#include "uascma/campaign/run_summary.h"

#include <cstdio>

namespace uascma::campaign {

double CampaignRunSummary::flights_per_s() const {
  return outcome.wall_time_s > 0.0 ? static_cast<double>(outcome.flights_flown) / outcome.wall_time_s : 0.0;
}

std::string CampaignRunSummary::Text() const {
  // printf's formatting: the line `uascma campaign` has always printed, its rounding included.
  const char* format =
      "flew %lld flights (%lld already stored, %lld flown meanwhile by other processes, %lld in the campaign) in "
      "%.1f s: %.1f flights/s on %d rank%s x %d thread%s; results in %s\n";
  auto print = [&](char* buffer, std::size_t size) {
    return std::snprintf(
        buffer, size, format, static_cast<long long>(outcome.flights_flown),
        static_cast<long long>(outcome.flights_before), static_cast<long long>(outcome.flights_by_others),
        static_cast<long long>(outcome.flights_total), outcome.wall_time_s, flights_per_s(), outcome.ranks,
        outcome.ranks == 1 ? "" : "s", outcome.jobs, outcome.jobs == 1 ? "" : "s", db.c_str());
  };
  std::string text(static_cast<std::size_t>(print(nullptr, 0)), '\0');
  print(text.data(), text.size() + 1);
  return text;
}

nlohmann::json CampaignRunSummary::Json() const {
  return {{"db", db},
          {"flights_total", outcome.flights_total},
          {"flights_before", outcome.flights_before},
          {"flights_flown", outcome.flights_flown},
          {"flights_by_others", outcome.flights_by_others},
          {"wall_time_s", outcome.wall_time_s},
          {"flights_per_s", flights_per_s()},
          {"jobs_per_rank", outcome.jobs},
          {"ranks", outcome.ranks}};
}

}  // namespace uascma::campaign
