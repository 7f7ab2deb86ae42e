// Contact search: a uniform grid (binning) of segment bounding boxes.
//
// Build is O(n), a query touches only the cells overlapping its box, so searching all slave
// segments against n master segments costs O(n_slave + n) per Newton iteration. The cell size is
// the mean segment extent, capped so that the grid has at most ~4 n cells (a long, flat profile
// gets a long, one-cell-high grid).
#pragma once

#include "vec2.hpp"

#include <vector>

namespace rf {

class SegmentGrid {
 public:
  SegmentGrid() = default;
  /// Segments i = [a[i], b[i]].
  void build(const std::vector<V2<double>>& a, const std::vector<V2<double>>& b);
  /// Appends to `out` (sorted, unique) every segment whose bounding box meets [lo, hi].
  void query(const V2<double>& lo, const V2<double>& hi, std::vector<int>& out) const;
  bool empty() const { return nseg_ == 0; }
  V2<double> lower() const { return {x0_, y0_}; }
  V2<double> upper() const { return {x1_, y1_}; }
  int num_cells() const { return nx_ * ny_; }

 private:
  double x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0, h_ = 1;
  int nx_ = 0, ny_ = 0, nseg_ = 0;
  std::vector<int> start_;           // CSR offsets per cell
  std::vector<int> items_;           // segment ids
  std::vector<V2<double>> lo_, hi_;  // segment boxes
};

}  // namespace rf
