// Landing-site CSV reader: columns found by name with the aliases of include/uascma/planning/map_sites_csv.h.
#include "uascma/planning/map_sites_csv.h"

#include <algorithm>
#include <array>
#include <cctype>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "map_import_detail.h"
#include "uascma/common/bounds.h"
#include "uascma/common/csv.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/text.h"

namespace uascma::planning {
namespace {

enum Column { kId = 0, kLat, kLon, kAlt, kRisk, kRadius, kNumColumns };

struct ColumnSpec {
  const char* name;  // the canonical name, used in messages
  std::vector<std::string_view> aliases;
};

const std::array<ColumnSpec, kNumColumns>& Columns() {
  static const std::array<ColumnSpec, kNumColumns> columns = {{
      {"osm_id", {"osm_id", "id", "site_id"}},
      {"lat", {"lat", "gps.lat", "latitude"}},
      {"lon", {"lon", "gps.lon", "lng", "longitude"}},
      {"alt", {"alt", "gps.alt", "altitude"}},
      {"risk", {"risk", "landing_site_risk"}},
      {"radius", {"radius"}},
  }};
  return columns;
}

std::string LowerCsvHeader(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}

}  // namespace

void ParseLandingSitesCsv(std::string_view text, const std::string& source, const MapImportOptions& /*options*/,
                          GeoMapData* data) {
  // Records, RFC 4180 (csv.h): a quoted field may hold commas, doubled quotes and line breaks.
  const std::vector<CsvRecord> records = SplitCsv(text, source);
  if (records.empty())
    throw InputError(source, "header", "a header row naming the columns osm_id, lat, lon, alt, risk, radius");

  // The header: where each column is.
  const std::vector<std::string>& header = records.front().fields;
  std::array<int, kNumColumns> where;
  where.fill(-1);
  for (int c = 0; c < kNumColumns; ++c) {
    for (std::size_t f = 0; f < header.size(); ++f) {
      const std::string name = LowerCsvHeader(header[f]);
      for (std::string_view alias : Columns()[c].aliases) {
        if (name != alias) continue;
        if (where[c] >= 0) {  // a column given twice: which one holds the value would be a guess
          throw InputError(source, fmt::format("line {} column {}", records.front().line, f + 1),
                           fmt::format("each column once, but '{}' is column {} and '{}' column {} (both name {}): "
                                       "remove one",
                                       BriefForMessage(header[where[c]]), where[c] + 1, BriefForMessage(header[f]),
                                       f + 1, Columns()[c].name));
        }
        where[c] = static_cast<int>(f);
      }
    }
    if (where[c] < 0) {
      std::string aliases;
      for (std::string_view alias : Columns()[c].aliases)
        aliases += (aliases.empty() ? "" : " | ") + std::string(alias);
      throw InputError(source, "header",
                       fmt::format("a column '{}' (accepted names: {}); the header is '{}'", Columns()[c].name, aliases,
                                   BriefForMessage(fmt::format("{}", fmt::join(header, ",")))));
    }
  }
  const int needed = *std::max_element(where.begin(), where.end()) + 1;

  ImportSummary& summary = data->summary;
  summary.sources.push_back(source);
  for (std::size_t r = 1; r < records.size(); ++r) {
    const std::vector<std::string>& fields = records[r].fields;
    const std::string row = fmt::format("line {}", records[r].line);
    if (static_cast<int>(fields.size()) < needed) {
      throw InputError(source, row, fmt::format("{} comma-separated fields, got {}", header.size(), fields.size()));
    }
    auto number_at = [&](Column c) {
      const auto value = detail::ParseNumber(fields[where[c]]);
      if (!value) {
        throw InputError(source, fmt::format("{} column {}", row, Columns()[c].name),
                         fmt::format("a number, got '{}'", BriefForMessage(fields[where[c]])));
      }
      return *value;
    };
    GeoLandingSite site;
    site.id = std::string(fields[where[kId]]);
    if (site.id.empty()) throw InputError(source, row + " column osm_id", "a site id");
    const std::string feature = fmt::format("{} (site {})", row, BriefForMessage(site.id));
    site.position = {number_at(kLat), number_at(kLon)};
    detail::CheckGeoPoint(site.position, source, feature);
    site.altitude = number_at(kAlt);
    site.risk = number_at(kRisk);
    site.radius = number_at(kRadius);
    // Alt and radius had no upper bound (1e9 m was accepted). alt: 0 to 1000 m above ground, the
    // cruise-altitude bound (above the tallest building of any city; Midtown's sites reach 221 m). radius: 0.1 m
    // (smaller than any vehicle) to 1000 m (a site larger than a city park; Midtown's are 2-16 m). Our bounds.
    constexpr Bounds kSiteAltitude{0.0, 1000.0, "m"};
    constexpr Bounds kSiteRadius{0.1, 1000.0, "m"};
    if (!kSiteAltitude.Contains(site.altitude)) {
      throw InputError(source, feature + " alt", OutsideBoundsMessage(kSiteAltitude, site.altitude) + " above ground");
    }
    if (!kSiteRadius.Contains(site.radius)) {
      throw InputError(source, feature + " radius", OutsideBoundsMessage(kSiteRadius, site.radius));
    }
    if (!(site.risk >= 0.0 && site.risk <= 1.0)) {
      throw InputError(source, feature, fmt::format("risk in [0, 1], got {}", site.risk));
    }
    data->sites.push_back(std::move(site));
    ++summary.sites;
  }
}

void ReadLandingSitesCsv(const std::filesystem::path& path, const MapImportOptions& options, GeoMapData* data) {
  ParseLandingSitesCsv(ReadFile(path), path.string(), options, data);
}

}  // namespace uascma::planning
