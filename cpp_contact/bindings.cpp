// pybind11 bindings of the contact core: rubberfriction._contact.
//
// Python passes plain numpy arrays once at set-up (coordinates, dof indices, segments) and, per
// Newton iteration, the full local solution array plus petsc4py Mat/Vec objects (type-checked by
// petsc_caster.hpp). Python never loops over segments.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "contact_interface.hpp"
#include "friction_law.hpp"
#include "geometry.hpp"
#include "petsc_assembly.hpp"
#include "petsc_caster.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace py = pybind11;

namespace {

using DArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

std::vector<rf::V2<double>> points(const DArray& a, const char* name) {
  if (a.ndim() != 2 || a.shape(1) != 2)
    throw std::invalid_argument(std::string(name) + " must be an (n, 2) array of coordinates");
  std::vector<rf::V2<double>> out(static_cast<std::size_t>(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out[static_cast<std::size_t>(i)] = {r(i, 0), r(i, 1)};
  return out;
}

template <class T>
std::vector<std::array<T, 2>> pairs_of(const IArray& a, const char* name) {
  if (a.ndim() != 2 || a.shape(1) != 2)
    throw std::invalid_argument(std::string(name) + " must be an (n, 2) integer array");
  std::vector<std::array<T, 2>> out(static_cast<std::size_t>(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    out[static_cast<std::size_t>(i)] = {static_cast<T>(r(i, 0)), static_cast<T>(r(i, 1))};
  return out;
}

std::vector<rf::DofIndex> vector_of(const py::object& o, const char* name) {
  if (o.is_none()) return {};
  const IArray a = IArray::ensure(o);
  if (!a || a.ndim() != 1) throw std::invalid_argument(std::string(name) + " must be a 1D integer array or None");
  return std::vector<rf::DofIndex>(a.data(), a.data() + a.shape(0));
}

rf::SurfaceMesh surface(const std::string& name, const DArray& X, const IArray& dofs, const IArray& segments,
                        const py::object& temperature_dofs, const py::object& interior) {
  std::vector<rf::V2<double>> inner;
  if (!interior.is_none()) inner = points(DArray::ensure(interior), "interior_points");
  return rf::make_surface(name, points(X, (name + " X").c_str()), pairs_of<rf::DofIndex>(dofs, "dofs"),
                          pairs_of<int>(segments, "segments"), vector_of(temperature_dofs, "temperature_dofs"), inner);
}

const double* solution(const DArray& u, std::size_t& n) {
  if (u.ndim() != 1) throw std::invalid_argument("u must be a 1D float array (the full local solution)");
  n = static_cast<std::size_t>(u.shape(0));
  return u.data();
}

// The solution a sparsity query is taken at: u, or the reference state (zeros) when u is None.
struct QueryState {
  QueryState(const rf::ContactInterface& c, const py::object& u) {
    if (u.is_none()) {
      zero.assign(static_cast<std::size_t>(c.max_dof() + 1), 0.0);
      x = zero.data();
      n = zero.size();
    } else {
      array = DArray::ensure(u);
      x = solution(array, n);
    }
  }
  std::vector<double> zero;
  DArray array;
  const double* x = nullptr;
  std::size_t n = 0;
};

rf::V2<double> offset_of(const std::array<double, 2>& o) { return {o[0], o[1]}; }

void evaluate(rf::ContactInterface& c, const DArray& u, const std::array<double, 2>& offset, double dt,
              double temperature, bool blocks) {
  const rf::FrictionLaw* law = c.friction();
  if (law && law->depends_on_temperature() && !c.slave().has_temperature() && c.slave_temperatures().empty() &&
      std::isnan(temperature))
    throw std::invalid_argument(
        "the friction law depends on temperature: pass temperature=T [K], set the slave node temperatures or "
        "give the slave temperature dofs");
  std::size_t n = 0;
  const double* x = solution(u, n);
  c.evaluate(x, n, offset_of(offset), dt, temperature, blocks);
}

template <class T>
py::array_t<T> as_array(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::dict state_dict(const rf::ContactInterface& c) {
  const rf::NodeOutput& o = c.nodes();
  const rf::InterfaceTotals& t = c.totals();
  py::dict d;
  d["status"] = as_array(o.status);
  py::array_t<bool> paired(static_cast<py::ssize_t>(o.paired.size()));
  for (std::size_t i = 0; i < o.paired.size(); ++i) paired.mutable_data()[i] = o.paired[i] != 0;
  d["paired"] = paired;
  d["gap"] = as_array(o.gap);
  d["pressure"] = as_array(o.pressure);
  d["tangential_traction"] = as_array(o.t_T);
  d["slip_increment"] = as_array(o.dgamma);
  d["tangential_increment"] = as_array(o.dg_T);
  d["slip_velocity"] = as_array(o.velocity);
  d["mu"] = as_array(o.mu);
  d["friction_power_density"] = as_array(o.power);
  d["weight"] = as_array(o.area);
  d["heat_flux_slave"] = as_array(o.q_slave);
  d["heat_flux_master"] = as_array(o.q_master);
  py::array_t<double> normal({static_cast<py::ssize_t>(o.nx.size()), py::ssize_t{2}});
  auto nr = normal.mutable_unchecked<2>();
  for (std::size_t i = 0; i < o.nx.size(); ++i) {
    nr(static_cast<py::ssize_t>(i), 0) = o.nx[i];
    nr(static_cast<py::ssize_t>(i), 1) = o.ny[i];
  }
  d["normal"] = normal;
  d["elastic_gap_committed"] = as_array(c.committed_elastic_gap());
  d["elastic_gap_trial"] = as_array(o.elastic_gap);
  d["contact_length"] = t.contact_length;
  d["force_x"] = t.force_x;
  d["force_z"] = t.force_z;
  d["dissipation"] = t.dissipation;
  d["friction_power"] = t.friction_power;
  d["heat_slave"] = t.heat_slave;
  d["heat_master"] = t.heat_master;
  d["n_paired"] = t.n_paired;
  d["n_active"] = t.n_active;
  d["n_stick"] = t.n_stick;
  d["n_slip"] = t.n_slip;
  d["n_pairs"] = t.n_pairs;
  d["cumulative_dissipation"] = c.cumulative_dissipation();
  d["committed_steps"] = c.committed_steps();
  d["time_search"] = t.time_search;
  d["time_integration"] = t.time_integration;
  d["time_assembly"] = t.time_assembly;
  return d;
}

py::dict report_dict(const rf::ContactInterface& c) {
  py::dict d;
  d["method"] = c.method() == rf::Method::mortar            ? "mortar"
                : c.method() == rf::Method::node_to_surface ? "node_to_surface"
                                                            : "node_to_segment";
  const rf::PenaltyChoice& p = c.penalty();
  py::dict pen;
  pen["set"] = p.set;
  pen["c_N"] = p.cN;
  pen["c_T"] = p.cT;
  pen["automatic"] = p.automatic;
  if (p.automatic) {
    pen["alpha"] = p.alpha;
    pen["tangential_fraction"] = p.tangential_fraction;
    pen["E_eff"] = p.E_eff;
    pen["h_min"] = p.h;
  }
  d["penalty"] = pen;
  d["friction"] = c.friction() ? py::object(py::str(c.friction()->describe())) : py::object(py::none());
  d["thermal"] = c.thermal().enabled ? py::object(py::str(c.thermal().describe())) : py::object(py::none());
  d["search_radius"] = c.search_radius();
  d["gauss_points"] = c.gauss_points();
  d["evaluations"] = c.evaluations();
  d["reused_evaluations"] = c.reused_evaluations();
  const rf::SurfaceMesh& s = c.slave();
  py::dict sl;
  sl["nodes"] = s.num_nodes();
  sl["segments"] = static_cast<int>(s.segments.size());
  sl["h_min"] = s.h_min;
  sl["h_max"] = s.h_max;
  sl["temperature"] = s.has_temperature();
  d["slave"] = sl;
  py::dict m;
  if (const rf::RigidPolyline* r = c.rigid_master()) {
    m["type"] = "rigid";
    m["segments"] = r->num_segments();
    m["period"] = r->period();
    m["h_min"] = r->h_min();
    m["h_max"] = r->h_max();
    m["dropped_closing_vertex"] = r->dropped_closing_vertex();
  } else if (const rf::SurfaceMesh* ms = c.deformable_master()) {
    m["type"] = "deformable";
    m["nodes"] = ms->num_nodes();
    m["segments"] = static_cast<int>(ms->segments.size());
    m["h_min"] = ms->h_min;
    m["h_max"] = ms->h_max;
    m["temperature"] = ms->has_temperature();
  } else {
    m["type"] = "none";
  }
  d["master"] = m;
  d["fixed_dofs"] = static_cast<int>(c.fixed_dofs().size());
  d["allow_new_nonzeros"] = c.allow_new_nonzeros();
  return d;
}

}  // namespace

PYBIND11_MODULE(_contact, m) {
  m.doc() = "C++ mortar contact core of rubberfriction (2D, plane strain x-z stored as x-y)";

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

  py::class_<rf::FrictionLaw, std::shared_ptr<rf::FrictionLaw>>(m, "FrictionLaw")
      .def(
          "evaluate",
          [](const rf::FrictionLaw& f, double p, double v, double T) {
            const rf::FrictionValue r = f.evaluate(p, v, T);
            return py::make_tuple(r.mu, r.dmu_dp, r.dmu_dv, r.dmu_dT);
          },
          py::arg("p"), py::arg("v"), py::arg("T") = 293.15,
          "(mu, dmu/dp, dmu/dv, dmu/dT) at pressure p [MPa], sliding velocity v [mm/s], temperature T [K]")
      .def(
          "evaluate_many",
          [](const rf::FrictionLaw& f, const DArray& p, const DArray& v, const DArray& T) {
            if (p.size() != v.size() || p.size() != T.size())
              throw std::invalid_argument("p, v, T must have the same size");
            py::array_t<double> out({p.size(), py::ssize_t{4}});
            auto o = out.mutable_unchecked<2>();
            for (py::ssize_t i = 0; i < p.size(); ++i) {
              const rf::FrictionValue r = f.evaluate(p.data()[i], v.data()[i], T.data()[i]);
              o(i, 0) = r.mu;
              o(i, 1) = r.dmu_dp;
              o(i, 2) = r.dmu_dv;
              o(i, 3) = r.dmu_dT;
            }
            return out;
          },
          py::arg("p"), py::arg("v"), py::arg("T"), "columns: mu, dmu/dp, dmu/dv, dmu/dT")
      .def_property_readonly("depends_on_velocity", &rf::FrictionLaw::depends_on_velocity)
      .def_property_readonly("depends_on_temperature", &rf::FrictionLaw::depends_on_temperature)
      .def("describe", &rf::FrictionLaw::describe);

  py::class_<rf::ConstantFriction, rf::FrictionLaw, std::shared_ptr<rf::ConstantFriction>>(m, "ConstantFriction")
      .def(py::init<double>(), py::arg("mu"))
      .def_property_readonly("mu", &rf::ConstantFriction::mu);

  py::class_<rf::SplineFriction, rf::FrictionLaw, std::shared_ptr<rf::SplineFriction>>(m, "SplineFriction")
      .def(py::init([](const std::vector<std::vector<double>>& knots, const std::vector<int>& degrees,
                       const DArray& coefficients, const std::vector<std::string>& transforms, double log_floor,
                       double mu_min) {
             if (knots.size() != degrees.size())
               throw std::invalid_argument("SplineFriction: one degree per knot vector is required");
             std::vector<rf::BSplineAxis> axes;
             for (std::size_t a = 0; a < knots.size(); ++a) axes.emplace_back(knots[a], degrees[a]);
             std::vector<rf::AxisTransform> tr;
             for (const auto& s : transforms) {
               if (s == "linear")
                 tr.push_back(rf::AxisTransform::linear);
               else if (s == "log10")
                 tr.push_back(rf::AxisTransform::log10);
               else
                 throw std::invalid_argument("SplineFriction: axis transform must be 'linear' or 'log10', got '" + s +
                                             "'");
             }
             std::vector<double> c(coefficients.data(), coefficients.data() + coefficients.size());
             return std::make_shared<rf::SplineFriction>(std::move(axes), std::move(c), std::move(tr), log_floor,
                                                         mu_min);
           }),
           py::arg("knots"), py::arg("degrees"), py::arg("coefficients"), py::arg("transforms"),
           py::arg("log_floor") = 1e-12, py::arg("mu_min") = 0.0,
           "Tensor-product B-spline mu over (p, v) or (p, v, T); knots/coefficients in scipy's tck layout");

  py::class_<rf::HeightField>(m, "HeightField",
                              "periodic C2 cubic spline z = h(x) through uniformly spaced vertices (the smooth rigid "
                              "master of node-to-surface contact)")
      .def(py::init([](const DArray& vertices, double period) {
             return rf::HeightField(points(vertices, "height field vertices"), period);
           }),
           py::arg("vertices"), py::arg("period"))
      .def(
          "__call__",
          [](const rf::HeightField& f, double x) {
            const rf::HeightValue v = f(x);
            return py::make_tuple(v.h, v.d1, v.d2, v.d3);
          },
          py::arg("x"), "(h, dh/dx, d2h/dx2, d3h/dx3) at x")
      .def_property_readonly("period", &rf::HeightField::period)
      .def_property_readonly("spacing", &rf::HeightField::spacing);

  py::class_<rf::ContactInterface>(m, "ContactInterface")
      .def(py::init([](const DArray& X, const IArray& dofs, const IArray& segments, const py::object& temperature_dofs,
                       const py::object& interior_points, const std::string& method) {
             rf::Method meth;
             if (method == "mortar")
               meth = rf::Method::mortar;
             else if (method == "node_to_segment" || method == "nts")
               meth = rf::Method::node_to_segment;
             else if (method == "node_to_surface" || method == "surface")
               meth = rf::Method::node_to_surface;
             else
               throw std::invalid_argument("method must be 'mortar', 'node_to_segment' or 'node_to_surface', got '" +
                                           method + "'");
             return std::make_unique<rf::ContactInterface>(
                 surface("slave", X, dofs, segments, temperature_dofs, interior_points), meth);
           }),
           py::arg("X"), py::arg("dofs"), py::arg("segments"), py::arg("temperature_dofs") = py::none(),
           py::arg("interior_points") = py::none(), py::arg("method") = "mortar")
      .def(
          "set_rigid_master",
          [](rf::ContactInterface& c, const DArray& vertices, double period) {
            c.set_rigid_master(rf::RigidPolyline(points(vertices, "master vertices"), period));
          },
          py::arg("vertices"), py::arg("period") = 0.0)
      .def(
          "set_deformable_master",
          [](rf::ContactInterface& c, const DArray& X, const IArray& dofs, const IArray& segments,
             const py::object& temperature_dofs, const py::object& interior_points) {
            c.set_deformable_master(surface("master", X, dofs, segments, temperature_dofs, interior_points));
          },
          py::arg("X"), py::arg("dofs"), py::arg("segments"), py::arg("temperature_dofs") = py::none(),
          py::arg("interior_points") = py::none())
      .def("set_penalty", &rf::ContactInterface::set_penalty, py::arg("c_N"), py::arg("c_T"))
      .def("set_auto_penalty", &rf::ContactInterface::set_auto_penalty, py::arg("E_eff"), py::arg("alpha"),
           py::arg("tangential_fraction"))
      .def(
          "set_friction",
          [](rf::ContactInterface& c, std::shared_ptr<rf::FrictionLaw> law) { c.set_friction(std::move(law)); },
          py::arg("law").none(true))
      .def(
          "set_thermal",
          [](rf::ContactInterface& c, double h0, double h1, double beta, double kappa, double master_temperature) {
            rf::ThermalParameters t;
            t.enabled = true;
            t.h0 = h0;
            t.h1 = h1;
            t.beta = beta;
            t.kappa = kappa;
            t.master_temperature = master_temperature;
            c.set_thermal(t);
          },
          py::arg("h0"), py::arg("h1") = 0.0, py::arg("beta") = 1.0, py::arg("kappa") = 0.5,
          py::arg("master_temperature") = std::numeric_limits<double>::quiet_NaN())
      .def(
          "set_slave_temperatures",
          [](rf::ContactInterface& c, const py::object& T) {
            std::vector<double> v;
            if (!T.is_none()) v = py::cast<std::vector<double>>(T);
            c.set_slave_temperatures(std::move(v));
          },
          py::arg("T").none(true))
      .def("disable_thermal", [](rf::ContactInterface& c) { c.set_thermal(rf::ThermalParameters{}); })
      .def(
          "set_fixed_dofs",
          [](rf::ContactInterface& c, const py::object& d) { c.set_fixed_dofs(vector_of(d, "fixed dofs")); },
          py::arg("dofs"))
      .def("set_search_radius", &rf::ContactInterface::set_search_radius, py::arg("radius"))
      .def("set_gauss_points", &rf::ContactInterface::set_gauss_points, py::arg("n"))
      .def("set_allow_new_nonzeros", &rf::ContactInterface::set_allow_new_nonzeros, py::arg("allow"))
      .def("set_periodic_seam", &rf::ContactInterface::set_periodic_seam, py::arg("seam"),
           "The slave's chain ends are the seam of a periodic cell: they keep the slave normal")
      .def("set_master_frame", &rf::ContactInterface::set_master_frame, py::arg("on"),
           "Every slave node takes the master's normal averaged over its support as contact frame")
      .def(
          "reset_history",
          [](rf::ContactInterface& c, const DArray& u, const std::array<double, 2>& offset) {
            std::size_t n = 0;
            const double* x = solution(u, n);
            c.reset_history(x, n, offset_of(offset));
          },
          py::arg("u"), py::arg("offset") = std::array<double, 2>{0.0, 0.0})
      .def("set_elastic_gap", &rf::ContactInterface::set_elastic_gap, py::arg("gap"),
           "Committed tangential elastic gaps per slave node (stick history of an earlier run)")
      .def("committed_elastic_gap", &rf::ContactInterface::committed_elastic_gap,
           "Committed tangential elastic gaps per slave node (0 where open)")
      .def(
          "evaluate",
          [](rf::ContactInterface& c, const DArray& u, const std::array<double, 2>& offset, double dt,
             double temperature) { evaluate(c, u, offset, dt, temperature, false); },
          py::arg("u"), py::arg("offset") = std::array<double, 2>{0.0, 0.0}, py::arg("dt") = 0.0,
          py::arg("temperature") = std::numeric_limits<double>::quiet_NaN(),
          "Search, project and evaluate the nodal laws at u (updates state(), assembles nothing)")
      .def(
          "local_system",
          [](rf::ContactInterface& c, const DArray& u, const std::array<double, 2>& offset, double dt,
             double temperature) {
            evaluate(c, u, offset, dt, temperature, true);
            std::vector<std::int64_t> rr, jr, jc;
            std::vector<double> rv, jv;
            for (const rf::LocalBlock& b : c.blocks()) {
              for (std::size_t i = 0; i < b.rows.size(); ++i) {
                if (c.is_fixed(b.rows[i])) continue;
                rr.push_back(b.rows[i]);
                rv.push_back(b.r[i]);
                for (std::size_t j = 0; j < b.cols.size(); ++j) {
                  if (b.cols[j] < 0 || c.is_fixed(b.cols[j])) continue;
                  jr.push_back(b.rows[i]);
                  jc.push_back(b.cols[j]);
                  jv.push_back(b.K[i * b.cols.size() + j]);
                }
              }
            }
            return py::make_tuple(as_array(rr), as_array(rv), as_array(jr), as_array(jc), as_array(jv));
          },
          py::arg("u"), py::arg("offset") = std::array<double, 2>{0.0, 0.0}, py::arg("dt") = 0.0,
          py::arg("temperature") = std::numeric_limits<double>::quiet_NaN(),
          "Contact residual and Jacobian as COO triplets (res_rows, res_vals, J_rows, J_cols, J_vals), duplicates "
          "to be summed; fixed dofs removed. For tests and debugging; production code uses assemble().")
      .def(
          "assemble",
          [](rf::ContactInterface& c, const DArray& u, std::optional<Mat> A, std::optional<Vec> b,
             const std::array<double, 2>& offset, double dt, double temperature) {
            const Mat mat = A.value_or(nullptr);
            const Vec vec = b.value_or(nullptr);
            evaluate(c, u, offset, dt, temperature, mat != nullptr || vec != nullptr);
            const auto t0 = std::chrono::steady_clock::now();
            const rf::AssemblyReport rep = rf::add_to_petsc(c, mat, vec);
            c.totals().time_assembly = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            py::dict d;
            d["mallocs"] = rep.mallocs;
            d["entries"] = rep.entries;
            return d;
          },
          py::arg("u"), py::arg("A") = py::none(), py::arg("b") = py::none(),
          py::arg("offset") = std::array<double, 2>{0.0, 0.0}, py::arg("dt") = 0.0,
          py::arg("temperature") = std::numeric_limits<double>::quiet_NaN(),
          "Evaluate at u and ADD the contact residual into b and its tangent into A (a petsc4py.PETSc.Mat and "
          "Vec; None skips; other types raise TypeError). Returns {'mallocs', 'entries'}.")
      .def("commit", &rf::ContactInterface::commit, "Accept the last evaluation as the converged state of the step")
      .def("state", &state_dict)
      .def(
          "last_pairs",
          [](const rf::ContactInterface& c) {
            const auto& v = c.last_pairs();
            py::array_t<double> out({static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(6)});
            auto m = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < v.size(); ++i)
              for (int j = 0; j < 6; ++j) m(static_cast<py::ssize_t>(i), j) = v[i][static_cast<std::size_t>(j)];
            return out;
          },
          "Pairs of the last evaluation, rows (slave, master image, master segment, lo xi, hi xi, "
          "10 lo kind + hi kind), for debugging and tests")
      .def("report", &report_dict)
      .def(
          "sparsity_pairs",
          [](const rf::ContactInterface& c, const py::object& u, double margin) {
            const QueryState s(c, u);
            const auto p = c.sparsity(s.x, s.n, margin);
            py::array_t<std::int64_t> r(static_cast<py::ssize_t>(p.size())), cc(static_cast<py::ssize_t>(p.size()));
            for (std::size_t i = 0; i < p.size(); ++i) {
              r.mutable_data()[i] = p[i].first;
              cc.mutable_data()[i] = p[i].second;
            }
            return py::make_tuple(r, cc);
          },
          py::arg("u") = py::none(), py::arg("margin") = -1.0,
          "(rows, cols) of every coupling the contact can write (see ContactInterface::sparsity)")
      .def(
          "sparsity_blocks",
          [](const rf::ContactInterface& c, const py::object& u, double margin) {
            const QueryState s(c, u);
            py::list out;
            for (const auto& [rows, cols] : c.sparsity_blocks(s.x, s.n, margin))
              out.append(py::make_tuple(as_array(rows), as_array(cols)));
            return out;
          },
          py::arg("u") = py::none(), py::arg("margin") = -1.0,
          "The couplings as a list of dense (rows, cols) blocks (for sparsity patterns built block-wise)")
      .def_property_readonly("max_dof", &rf::ContactInterface::max_dof);
}
