#include "contact_search.hpp"

#include <algorithm>
#include <cmath>

namespace rf {

void SegmentGrid::build(const std::vector<V2<double>>& a, const std::vector<V2<double>>& b) {
  nseg_ = static_cast<int>(a.size());
  lo_.resize(a.size());
  hi_.resize(a.size());
  start_.clear();
  items_.clear();
  if (nseg_ == 0) {
    nx_ = ny_ = 0;
    return;
  }
  x0_ = y0_ = INFINITY;
  x1_ = y1_ = -INFINITY;
  double ext = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    lo_[i] = {std::min(a[i].x, b[i].x), std::min(a[i].y, b[i].y)};
    hi_[i] = {std::max(a[i].x, b[i].x), std::max(a[i].y, b[i].y)};
    x0_ = std::min(x0_, lo_[i].x);
    y0_ = std::min(y0_, lo_[i].y);
    x1_ = std::max(x1_, hi_[i].x);
    y1_ = std::max(y1_, hi_[i].y);
    ext += std::max(hi_[i].x - lo_[i].x, hi_[i].y - lo_[i].y);
  }
  const double W = x1_ - x0_, H = y1_ - y0_;
  h_ = std::max(ext / nseg_, 1e-12 * std::max({W, H, 1.0}));
  const double max_cells = 4.0 * nseg_ + 64.0;
  auto cells = [&](double h) { return (std::floor(W / h) + 1.0) * (std::floor(H / h) + 1.0); };
  while (cells(h_) > max_cells) h_ *= 1.5;
  nx_ = static_cast<int>(std::floor(W / h_)) + 1;
  ny_ = static_cast<int>(std::floor(H / h_)) + 1;

  auto cell_range = [&](const V2<double>& lo, const V2<double>& hi, int& i0, int& i1, int& j0, int& j1) {
    i0 = std::clamp(static_cast<int>(std::floor((lo.x - x0_) / h_)), 0, nx_ - 1);
    i1 = std::clamp(static_cast<int>(std::floor((hi.x - x0_) / h_)), 0, nx_ - 1);
    j0 = std::clamp(static_cast<int>(std::floor((lo.y - y0_) / h_)), 0, ny_ - 1);
    j1 = std::clamp(static_cast<int>(std::floor((hi.y - y0_) / h_)), 0, ny_ - 1);
  };
  std::vector<int> count(static_cast<std::size_t>(nx_ * ny_) + 1, 0);
  for (int s = 0; s < nseg_; ++s) {
    int i0, i1, j0, j1;
    cell_range(lo_[static_cast<std::size_t>(s)], hi_[static_cast<std::size_t>(s)], i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) ++count[static_cast<std::size_t>(j * nx_ + i + 1)];
  }
  for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
  start_ = count;
  items_.resize(static_cast<std::size_t>(start_.back()));
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (int s = 0; s < nseg_; ++s) {
    int i0, i1, j0, j1;
    cell_range(lo_[static_cast<std::size_t>(s)], hi_[static_cast<std::size_t>(s)], i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        items_[static_cast<std::size_t>(fill[static_cast<std::size_t>(j * nx_ + i)]++)] = s;
  }
}

void SegmentGrid::query(const V2<double>& lo, const V2<double>& hi, std::vector<int>& out) const {
  if (nseg_ == 0) return;
  if (hi.x < x0_ || lo.x > x1_ || hi.y < y0_ || lo.y > y1_) return;
  const int i0 = std::clamp(static_cast<int>(std::floor((lo.x - x0_) / h_)), 0, nx_ - 1);
  const int i1 = std::clamp(static_cast<int>(std::floor((hi.x - x0_) / h_)), 0, nx_ - 1);
  const int j0 = std::clamp(static_cast<int>(std::floor((lo.y - y0_) / h_)), 0, ny_ - 1);
  const int j1 = std::clamp(static_cast<int>(std::floor((hi.y - y0_) / h_)), 0, ny_ - 1);
  const std::size_t first = out.size();
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const std::size_t c = static_cast<std::size_t>(j * nx_ + i);
      for (int k = start_[c]; k < start_[c + 1]; ++k) {
        const int s = items_[static_cast<std::size_t>(k)];
        const auto& a = lo_[static_cast<std::size_t>(s)];
        const auto& b = hi_[static_cast<std::size_t>(s)];
        if (b.x < lo.x || a.x > hi.x || b.y < lo.y || a.y > hi.y) continue;
        out.push_back(s);
      }
    }
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
  out.erase(std::unique(out.begin() + static_cast<std::ptrdiff_t>(first), out.end()), out.end());
}

}  // namespace rf
