// Contact surfaces: the deformable slave boundary (and a deformable master boundary) as chains of
// linear segments, and the rigid master polyline, optionally periodic.
//
// Orientation rules (checked):
//  * Deformable surfaces: every segment (a, b) runs counter-clockwise around its own body, i.e.
//    the body lies on the LEFT of a -> b and the outward normal is the tangent rotated clockwise,
//    n = (t_y, -t_x)/|t|. The bottom face of a block runs from left to right (+x) and has n = -z.
//    The top face of a road body runs from right to left and has n = +z.
//  * Rigid polyline: the rigid body lies on the RIGHT of the vertex order, the outward normal is
//    the tangent rotated counter-clockwise, n = (-t_y, t_x)/|t|. A road profile z(x) given with
//    increasing x therefore has its material below and n = +z.
#pragma once

#include "contact_search.hpp"
#include "vec2.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rf {

using DofIndex = std::int64_t;

/// Chains of linear segments of a deformable body.
struct SurfaceMesh {
  std::string name;                           ///< "slave" or "master", used in messages
  std::vector<V2<double>> X;                  ///< reference coordinates
  std::vector<std::array<DofIndex, 2>> dofs;  ///< displacement dofs (x, z) per node
  std::vector<DofIndex> temperature_dofs;     ///< empty, or one per node
  std::vector<std::array<int, 2>> segments;   ///< node pairs, counter-clockwise around the body
  std::vector<int> prev, next;                ///< chain neighbours (-1 at the ends of open chains)
  double h_min = 0.0, h_max = 0.0;            ///< reference segment lengths

  int num_nodes() const { return static_cast<int>(X.size()); }
  bool has_temperature() const { return !temperature_dofs.empty(); }
};

/// Validates and completes a surface. `interior` is either empty or one reference point per
/// segment that lies inside the body (e.g. the centroid of the cell owning the facet); it is used
/// to check the orientation rule.
SurfaceMesh make_surface(const std::string& name, std::vector<V2<double>> X, std::vector<std::array<DofIndex, 2>> dofs,
                         std::vector<std::array<int, 2>> segments, std::vector<DofIndex> temperature_dofs,
                         const std::vector<V2<double>>& interior);

/// Rigid master polyline (open, or periodic with period L along x).
class RigidPolyline {
 public:
  RigidPolyline() = default;
  /// period = 0: open polyline through all vertices. period = L > 0: the vertices are one period
  /// of a profile that repeats with period L along x; segment k-1 joins the last vertex to the
  /// first vertex shifted by (L, 0). A duplicated closing vertex (last = first + (L, 0)) is
  /// accepted and dropped. Throws std::invalid_argument on bad input.
  RigidPolyline(std::vector<V2<double>> vertices, double period);

  int num_segments() const { return nseg_; }
  bool periodic() const { return period_ > 0.0; }
  double period() const { return period_; }
  const std::vector<V2<double>>& vertices() const { return V_; }
  /// Segment s of periodic image `image`, in the master reference frame (no rigid offset).
  void segment(int s, long image, V2<double>& a, V2<double>& b) const;
  /// Search structure of the reference period (image 0).
  const SegmentGrid& grid() const { return grid_; }
  double h_min() const { return h_min_; }
  double h_max() const { return h_max_; }
  bool dropped_closing_vertex() const { return dropped_closing_; }

 private:
  std::vector<V2<double>> V_;
  double period_ = 0.0;
  int nseg_ = 0;
  double h_min_ = 0.0, h_max_ = 0.0;
  bool dropped_closing_ = false;
  SegmentGrid grid_;
};

/// True if segments [p1, p2] and [q1, q2] intersect (including touching and collinear overlap).
bool segments_intersect(const V2<double>& p1, const V2<double>& p2, const V2<double>& q1, const V2<double>& q2);

}  // namespace rf
