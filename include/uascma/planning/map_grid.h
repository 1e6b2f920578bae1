#pragma once
// A uniform grid over the horizontal plane that indexes items (buildings, landing sites) by their bounding
// boxes, so that map queries look only at the items near the query instead of scanning all of them.
//
// The grid covers the union of the item boxes with square cells of side `cell_size` (m); cell (i, j) spans
// x ∈ [x0 + i c, x0 + (i + 1) c) (north) and y ∈ [y0 + j c, y0 + (j + 1) c) (east). Each item is listed in
// every cell its box overlaps, in increasing item order, in one flat array (compressed rows: cell k's items
// are items_[cell_begin_[k] .. cell_begin_[k + 1])). Queries visit the items of the cells a query region
// overlaps: a superset of the items that can meet the region, where an item that spans several cells may be
// visited more than once — the caller filters (and deduplicates when it matters).
//
// Immutable after construction; the queries are const and safe to call from many threads.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace uascma::planning {

class UniformGrid {
 public:
  UniformGrid() = default;
  // Indexes `boxes` (item k has box boxes[k]; empty boxes are not indexed) with cells of `cell_size` m
  // (> 0). The number of cells is capped at `max_cells` by enlarging the cells if needed.
  UniformGrid(std::span<const Eigen::AlignedBox2d> boxes, double cell_size, long max_cells = 4'000'000);

  // A cell size (m) for `count` items spread over `bounds`: about `items_per_cell` items per cell if they
  // were spread evenly, clamped to [min_size, max_size].
  static double SuggestCellSize(const Eigen::AlignedBox2d& bounds, std::size_t count, double items_per_cell,
                                double min_size, double max_size);

  double cell_size() const { return cell_size_; }
  int rows() const { return rows_; }  // cells along x (north)
  int cols() const { return cols_; }  // cells along y (east)
  bool empty() const { return rows_ == 0 || cols_ == 0; }

  // The cell holding the point p (VisitBox's cell for a box of one point), −1 outside the grid; a cell's items.
  int CellAt(const Eigen::Vector2d& p) const {
    if (empty()) return -1;
    const int i = Row(p.x()), j = Col(p.y());
    if (i < 0 || i >= rows_ || j < 0 || j >= cols_) return -1;
    return i * cols_ + j;
  }
  std::span<const int> CellItems(int cell) const {
    return std::span<const int>(items_.data() + cell_begin_[cell],
                                static_cast<std::size_t>(cell_begin_[cell + 1] - cell_begin_[cell]));
  }
  int cell_count() const { return rows_ * cols_; }

  // Calls visit(item) for the items listed in the cells that `box` overlaps. `visit` returns true to go on,
  // false to stop; the function returns false when it was stopped.
  template <typename Visit>
  bool VisitBox(const Eigen::AlignedBox2d& box, Visit&& visit) const {
    if (empty() || box.isEmpty()) return true;
    const int i0 = Row(box.min().x()), i1 = Row(box.max().x());
    const int j0 = Col(box.min().y()), j1 = Col(box.max().y());
    if (i1 < 0 || i0 >= rows_ || j1 < 0 || j0 >= cols_) return true;
    for (int i = std::max(i0, 0); i <= std::min(i1, rows_ - 1); ++i) {
      if (!VisitRowSpan(i, j0, j1, false, visit)) return false;
    }
    return true;
  }

  // Calls visit(item) for the items listed in the cells that come within `half_width` (m, ≥ 0) of the segment
  // a → b, row by row from a's end towards b's (and within a row, column by column in the direction of b), so
  // items near a tend to come first. In row i the points of the segment that can be within half_width of the
  // row are those with x in the row's x-range widened by half_width; their y-range, widened by half_width, gives
  // the columns. This covers the whole capsule around the segment (a point within half_width of the segment has
  // a nearest segment point less than half_width away in x and in y).
  template <typename Visit>
  bool VisitNearSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double half_width, Visit&& visit) const {
    if (empty()) return true;
    const double x_low = std::min(a.x(), b.x()) - half_width, x_high = std::max(a.x(), b.x()) + half_width;
    const int i0 = std::max(Row(x_low), 0), i1 = std::min(Row(x_high), rows_ - 1);
    const double dx = b.x() - a.x();
    const double inverse_dx = dx != 0.0 ? 1.0 / dx : 0.0;
    const bool rows_down = dx < 0.0, cols_down = b.y() < a.y();
    for (int n = 0; n <= i1 - i0; ++n) {
      const int i = rows_down ? i1 - n : i0 + n;
      const double slab_low = origin_.x() + i * cell_size_ - half_width;
      const double slab_high = slab_low + cell_size_ + 2.0 * half_width;
      double t_low = 0.0, t_high = 1.0;
      if (dx != 0.0) {
        const double t_a = (slab_low - a.x()) * inverse_dx, t_b = (slab_high - a.x()) * inverse_dx;
        t_low = std::max(0.0, std::min(t_a, t_b));
        t_high = std::min(1.0, std::max(t_a, t_b));
        if (t_low > t_high) continue;
      }
      const double y_a = a.y() + t_low * (b.y() - a.y()), y_b = a.y() + t_high * (b.y() - a.y());
      const int j0 = Col(std::min(y_a, y_b) - half_width), j1 = Col(std::max(y_a, y_b) + half_width);
      if (!VisitRowSpan(i, j0, j1, cols_down, visit)) return false;
    }
    return true;
  }

 private:
  int Row(double x) const { return CellIndex((x - origin_.x()) * inverse_cell_size_); }
  int Col(double y) const { return CellIndex((y - origin_.y()) * inverse_cell_size_); }
  // floor(u) as an int for u = (x − x0)/c, with everything before the grid (and NaN) as −1 and far beyond it
  // saturated so it never overflows. Truncation equals floor for u ≥ 0, which avoids a libm call in the hot path.
  static int CellIndex(double u) {
    if (!(u >= 0.0)) return -1;
    return static_cast<int>(std::min(u, 1.0e9));
  }

  // Visits the items of cells (i, j0 … j1), clamped to the grid, in increasing j or (`down`) decreasing j.
  template <typename Visit>
  bool VisitRowSpan(int i, int j0, int j1, bool down, Visit& visit) const {
    j0 = std::max(j0, 0);
    j1 = std::min(j1, cols_ - 1);
    for (int n = 0; n <= j1 - j0; ++n) {
      const int cell = i * cols_ + (down ? j1 - n : j0 + n);
      for (int k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k) {
        if (!visit(items_[k])) return false;
      }
    }
    return true;
  }

  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();  // m, the (x0, y0) corner
  double cell_size_ = 1.0;                            // m
  double inverse_cell_size_ = 1.0;                    // 1/m
  int rows_ = 0;
  int cols_ = 0;
  std::vector<int> cell_begin_;  // rows_·cols_ + 1 offsets into items_
  std::vector<int> items_;
};

}  // namespace uascma::planning
