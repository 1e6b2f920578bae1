#include "uascma/models/drag.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/csv.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/common/frames.h"

namespace uascma::models {
namespace {

// The uniform spacing of an axis, or 0 when its steps differ by more than round-off.
double UniformStep(const std::vector<double>& axis) {
  const double step = (axis.back() - axis.front()) / static_cast<double>(axis.size() - 1);
  for (std::size_t i = 1; i < axis.size(); ++i) {
    if (std::abs(axis[i] - axis[i - 1] - step) > 1e-9 * std::max(1.0, std::abs(step))) return 0.0;
  }
  return step;
}

}  // namespace

DragTable::Axis::Axis(std::vector<double> axis_values, double uniform_step)
    : values(std::move(axis_values)),
      inverse_uniform_step(uniform_step > 0.0 ? 1.0 / uniform_step : 0.0),
      front(values.front()),
      back(values.back()),
      last_cell(static_cast<int>(values.size()) - 2) {
  for (std::size_t i = 0; i + 1 < values.size(); ++i) inverse_width.push_back(1.0 / (values[i + 1] - values[i]));
}

int DragTable::Axis::SearchCell(double x) const {
  return static_cast<int>(std::upper_bound(values.begin(), values.end(), x) - values.begin()) - 1;
}

DragTable::DragTable(std::vector<double> airspeeds, std::vector<double> pitches_rad, std::vector<double> drag_n,
                     const std::string& source)
    : airspeeds_(std::move(airspeeds)), pitches_(std::move(pitches_rad)), drag_(std::move(drag_n)) {
  if (airspeeds_.size() < 2 || pitches_.size() < 2) {
    throw InputError(source, "axes", "at least two airspeeds and two pitches");
  }
  for (std::size_t i = 1; i < airspeeds_.size(); ++i) {
    if (!(airspeeds_[i] > airspeeds_[i - 1])) throw InputError(source, "airspeed axis", "strictly increasing values");
  }
  for (std::size_t j = 1; j < pitches_.size(); ++j) {
    if (!(pitches_[j] > pitches_[j - 1])) throw InputError(source, "pitch axis", "strictly increasing values");
  }
  if (airspeeds_.front() < 0.0) throw InputError(source, "airspeed axis", "non-negative airspeeds");
  if (drag_.size() != airspeeds_.size() * pitches_.size()) {
    throw InputError(source, "table", fmt::format("{} × {} drag values", airspeeds_.size(), pitches_.size()));
  }
  for (double d : drag_) {
    if (!std::isfinite(d) || d < 0.0) throw InputError(source, "table", "finite non-negative drag values (N)");
  }
  airspeed_axis_ = Axis(airspeeds_, UniformStep(airspeeds_));
  pitch_axis_ = Axis(pitches_, UniformStep(pitches_));
  constexpr double kQuarterTurn = std::numbers::pi / 2;
  if (pitches_.front() > -kQuarterTurn) below_pitch_axis_sine_ = std::sin(pitches_.front()) - kEdgeSineMargin;
  if (pitches_.back() < kQuarterTurn) above_pitch_axis_sine_ = std::sin(pitches_.back()) + kEdgeSineMargin;
}

DragTable DragTable::Default(PropellerConfiguration configuration) {
  const double scale = configuration == PropellerConfiguration::kPusher ? 1.25 : 1.0;
  std::vector<double> airspeeds, pitches, drag;
  for (int v = 0; v <= 10; ++v) airspeeds.push_back(v);
  for (int p = -30; p <= 30; p += 5) pitches.push_back(p / kDegreesPerRadian);
  for (double v : airspeeds) {
    for (double theta : pitches) {
      const double area = 0.05 * std::abs(std::cos(theta)) + 0.10 * std::abs(std::sin(theta));  // m²
      drag.push_back(scale * 0.5 * kAirDensity * area * v * v);
    }
  }
  return DragTable(std::move(airspeeds), std::move(pitches), std::move(drag), "default drag table");
}

DragTable DragTable::FromCsv(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::ifstream probe(path);
  if (!probe) throw InputError(source, "file", "a readable CSV drag table");
  auto parse = [&](const std::string& cell, int row, int column) {
    try {
      std::size_t used = 0;
      const double value = std::stod(cell, &used);
      if (used != cell.size()) throw std::invalid_argument("");
      return value;
    } catch (const std::exception&) {
      throw InputError(source, fmt::format("row {}, column {}", row, column), "a number, got '" + cell + "'");
    }
  };
  // RFC 4180 (common/csv.h): quoted cells, CRLF or LF, blank lines skipped; a row's number is its line.
  std::vector<double> pitches, airspeeds, drag;
  bool header = true;
  for (const CsvRecord& record : SplitCsv(ReadFile(path), source)) {
    std::vector<double> values;
    for (std::size_t column = header ? 1 : 0; column < record.fields.size(); ++column) {  // header: skip the corner
      values.push_back(parse(record.fields[column], record.line, static_cast<int>(column) + 1));
    }
    if (header) {
      for (double degrees : values) pitches.push_back(degrees / kDegreesPerRadian);
      header = false;
      continue;
    }
    if (values.size() != pitches.size() + 1) {
      throw InputError(source, fmt::format("row {}", record.line), fmt::format("{} values", pitches.size() + 1));
    }
    airspeeds.push_back(values.front());
    drag.insert(drag.end(), values.begin() + 1, values.end());
  }
  return DragTable(std::move(airspeeds), std::move(pitches), std::move(drag), source);
}

double DragTable::DragSlope(double airspeed, double pitch) const {
  constexpr double kStep = 1e-3;  // m/s, central difference across at most one table breakpoint
  const double low = std::max(airspeed - kStep, 0.0);
  return (Drag(airspeed + kStep, pitch) - Drag(low, pitch)) / (airspeed + kStep - low);
}

}  // namespace uascma::models
