#include "uascma/planning/map_grid.h"

#include "uascma/common/error.h"

namespace uascma::planning {

double UniformGrid::SuggestCellSize(const Eigen::AlignedBox2d& bounds, std::size_t count, double items_per_cell,
                                    double min_size, double max_size) {
  if (count == 0 || bounds.isEmpty()) return max_size;
  const Eigen::Vector2d size = bounds.sizes();
  const double area = std::max(size.x(), 1.0) * std::max(size.y(), 1.0);
  return std::clamp(std::sqrt(items_per_cell * area / static_cast<double>(count)), min_size, max_size);
}

UniformGrid::UniformGrid(std::span<const Eigen::AlignedBox2d> boxes, double cell_size, long max_cells) {
  UASCMA_CHECK(cell_size > 0.0 && std::isfinite(cell_size), "grid cell size must be positive");
  Eigen::AlignedBox2d bounds;  // empty
  for (const auto& box : boxes) {
    if (!box.isEmpty()) bounds.extend(box);
  }
  if (bounds.isEmpty()) return;
  // Enough cells to cover the bounds (the far edge included), enlarging the cells if there would be too many.
  const Eigen::Vector2d size = bounds.sizes();
  cell_size_ = cell_size;
  while ((std::floor(size.x() / cell_size_) + 1.0) * (std::floor(size.y() / cell_size_) + 1.0) >
         static_cast<double>(max_cells)) {
    cell_size_ *= 2.0;
  }
  inverse_cell_size_ = 1.0 / cell_size_;
  origin_ = bounds.min();
  rows_ = static_cast<int>(std::floor(size.x() / cell_size_)) + 1;
  cols_ = static_cast<int>(std::floor(size.y() / cell_size_)) + 1;

  // Two passes over the boxes: count the items of each cell, then fill the compressed rows.
  cell_begin_.assign(static_cast<std::size_t>(rows_) * cols_ + 1, 0);
  auto for_each_cell = [&](const Eigen::AlignedBox2d& box, auto&& action) {
    const int i0 = std::max(Row(box.min().x()), 0), i1 = std::min(Row(box.max().x()), rows_ - 1);
    const int j0 = std::max(Col(box.min().y()), 0), j1 = std::min(Col(box.max().y()), cols_ - 1);
    for (int i = i0; i <= i1; ++i) {
      for (int j = j0; j <= j1; ++j) action(i * cols_ + j);
    }
  };
  for (const auto& box : boxes) {
    if (!box.isEmpty()) for_each_cell(box, [&](int cell) { ++cell_begin_[cell + 1]; });
  }
  for (std::size_t k = 1; k < cell_begin_.size(); ++k) cell_begin_[k] += cell_begin_[k - 1];
  items_.resize(cell_begin_.back());
  std::vector<int> fill(cell_begin_.begin(), cell_begin_.end() - 1);
  for (std::size_t item = 0; item < boxes.size(); ++item) {
    if (boxes[item].isEmpty()) continue;
    for_each_cell(boxes[item], [&](int cell) { items_[fill[cell]++] = static_cast<int>(item); });
  }
}

}  // namespace uascma::planning
