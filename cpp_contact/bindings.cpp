// pybind11 bindings of the contact core: rubberfriction._contact.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "geometry.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_contact, m) {
  m.doc() = "C++ mortar contact core of rubberfriction (2D, plane strain)";

  m.def(
      "project_on_polyline",
      [](const Eigen::Vector2d& p, const Eigen::Ref<const Eigen::Matrix<double, -1, 2, Eigen::RowMajor>>& xy) {
        std::vector<rf::Vec2> v(static_cast<std::size_t>(xy.rows()));
        for (Eigen::Index i = 0; i < xy.rows(); ++i) v[static_cast<std::size_t>(i)] = xy.row(i).transpose();
        const rf::Projection pr = rf::project_on_polyline(p, v);
        return py::make_tuple(pr.segment, pr.xi, pr.distance, pr.point);
      },
      py::arg("point"), py::arg("vertices"),
      "Closest point of `point` on the open polyline `vertices` (n x 2).\n"
      "Returns (segment, xi, signed_distance, closest_point); distance > 0 on the left-normal side.");
}
