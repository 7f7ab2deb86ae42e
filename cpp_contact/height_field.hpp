// Smooth rigid road for node-to-surface contact: the periodic C2 cubic spline z = h(x) through the
// vertices of a periodic rigid polyline sampled at uniform x (the band-limited surface samples of
// the lower scales).
//
// Why: the piecewise linear master of mortar and node-to-segment contact has a normal that jumps at
// every vertex. On samples whose peaks are sharper than the contact elements (rms slope ~4 on the
// lowest scale) the discrete penalty problem then has no equilibrium for some boundary nodes (an
// exact 2-cycle of the active set; README, lowest-scale failures). With a C2 surface and the gap
// of ContactInterface's node_to_surface method, the contact force is the gradient of a potential
// that is C1 in the slave positions, so every step of the incremental problem has a solution.
#pragma once

#include "vec2.hpp"

#include <vector>

namespace rf {

/// h and its first three derivatives at one x.
struct HeightValue {
  double h = 0.0, d1 = 0.0, d2 = 0.0, d3 = 0.0;
};

class HeightField {
 public:
  /// vertices: one period of a profile with uniformly spaced, increasing x (x_i = x_0 + i dx,
  /// n dx = period); throws std::invalid_argument otherwise (open or non-uniform polylines have
  /// no height field here: use mortar or node-to-segment contact).
  HeightField(const std::vector<V2<double>>& vertices, double period);

  /// The spline at any x (periodic continuation).
  HeightValue operator()(double x) const;

  double period() const { return period_; }
  double spacing() const { return dx_; }
  int num_points() const { return static_cast<int>(z_.size()); }

 private:
  double x0_ = 0.0, dx_ = 0.0, period_ = 0.0;
  std::vector<double> z_;  ///< heights at the vertices
  std::vector<double> m_;  ///< spline second derivatives at the vertices
};

}  // namespace rf
