// One contact interface: a deformable slave surface against a rigid (optionally periodic)
// polyline or a deformable master surface; mortar segment-to-segment or node-to-segment;
// penalty normal contact, Coulomb friction with mu(p, v, T), thermal contact.
//
// Per Newton iteration `evaluate(u, offset, dt, T)` re-runs the search and the projections at the
// current configuration and produces one dense local block per slave node (rows: the dofs that
// receive the node's traction through D_AB / M_AC; columns: the node's stencil). Residual
// convention: R(u) = F_int - F_ext, the contact adds dPi_c/du (the slave receives -D^T P), Newton
// solves J du = -R. History (tangential elastic gap, positions of the last converged step) is
// updated only by `commit()`.
#pragma once

#include "friction_law.hpp"
#include "height_field.hpp"
#include "mortar_segment.hpp"
#include "nodal_contact_law.hpp"
#include "surface.hpp"
#include "thermal_contact.hpp"

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rf {

/// mortar: segment-to-segment (5.33-5.38); node_to_segment: its collocation at the slave nodes;
/// node_to_surface: slave nodes against the smooth periodic height field of a rigid master
/// (height_field.hpp), gap g = (z - h(x)) / sqrt(1 + h'(x)^2), constant reference nodal weights,
/// so the contact force is the gradient of the penalty potential sum_A w_A c_N <-g_A>^2 / 2.
enum class Method { mortar, node_to_segment, node_to_surface };

struct PenaltyChoice {
  bool set = false;
  bool automatic = false;
  double cN = 0.0, cT = 0.0;
  double alpha = 0.0, tangential_fraction = 0.0, E_eff = 0.0, h = 0.0;
};

/// Dense contribution of one slave node's traction.
struct LocalBlock {
  std::vector<DofIndex> rows, cols;
  std::vector<double> K;  ///< row-major, rows.size() x cols.size()
  std::vector<double> r;  ///< residual entries for `rows`
};

/// Per slave node results of the last evaluation.
struct NodeOutput {
  std::vector<int> status;  ///< 0 open (or unpaired), 1 stick, 2 slip
  std::vector<char> paired;
  std::vector<double> gap, pressure, t_T, dgamma, dg_T, velocity, mu, area, q_slave, q_master, nx, ny;
  std::vector<double> power;        ///< frictional power density |t_T| dgamma/dt [mW/mm^2] (zero in stick)
  std::vector<double> elastic_gap;  ///< trial tangential elastic gap (committed by commit())
  void resize(std::size_t n);
};

struct InterfaceTotals {
  double force_x = 0.0, force_z = 0.0;         ///< total contact force on the slave body [N/mm]
  double contact_length = 0.0;                 ///< sum of nodal weights of nodes in contact [mm]
  double dissipation = 0.0;                    ///< frictional dissipation of the step [mJ/mm]
  double friction_power = 0.0;                 ///< [mW/mm]
  double heat_slave = 0.0, heat_master = 0.0;  ///< heat flow into slave / master [mW/mm]
  int n_paired = 0, n_active = 0, n_stick = 0, n_slip = 0, n_pairs = 0;
  double time_search = 0.0, time_integration = 0.0, time_assembly = 0.0;  ///< [s]
};

class ContactInterface {
 public:
  ContactInterface(SurfaceMesh slave, Method method);

  void set_rigid_master(RigidPolyline master);
  void set_deformable_master(SurfaceMesh master);
  void set_penalty(double cN, double cT);
  void set_auto_penalty(double E_eff, double alpha, double tangential_fraction);
  void set_friction(std::shared_ptr<const FrictionLaw> law) {
    friction_ = std::move(law);
    forget_evaluation();
  }
  void set_thermal(const ThermalParameters& t);
  void set_fixed_dofs(std::vector<DofIndex> dofs);
  void set_search_radius(double r);
  void set_gauss_points(int n);
  void set_allow_new_nonzeros(bool allow) { allow_new_nonzeros_ = allow; }
  /// The slave's two chain ends are the seam of a periodic cell (see vertex_end)
  void set_periodic_seam(bool seam) {
    periodic_seam_ = seam;
    forget_evaluation();
  }
  /// Every node's contact frame is the master's normal averaged over its support (as a chain
  /// end's always is): the pressure acts along the road's normal and the friction along its
  /// tangent, whatever the slave's bending (a sharp corner folding over a flat road)
  void set_master_frame(bool on) {
    master_frame_ = on;
    forget_evaluation();
  }
  /// Temperature of each slave node for mu(p, v, T) when the slave carries no temperature dofs
  /// (staggered thermomechanical coupling: the heat solver owns the temperature); empty: T_ref.
  void set_slave_temperatures(std::vector<double> T);
  const std::vector<double>& slave_temperatures() const { return slave_T_; }

  /// History reference: positions at u and the rigid offset become the last converged state;
  /// tangential elastic gaps are cleared.
  void reset_history(const double* u, std::size_t n, const V2<double>& offset);
  /// Committed tangential elastic gaps of the slave nodes (stick history), e.g. from
  /// committed_elastic_gap() of an earlier run on the same slave: a run that slides on from it.
  void set_elastic_gap(const std::vector<double>& gap);

  /// Search, project, integrate and apply the nodal law at u (full local solution array).
  void evaluate(const double* u, std::size_t n, const V2<double>& offset, double dt, double T_ref, bool with_blocks);
  void commit();

  const std::vector<LocalBlock>& blocks() const { return blocks_; }
  const NodeOutput& nodes() const { return out_; }
  const InterfaceTotals& totals() const { return totals_; }
  InterfaceTotals& totals() { return totals_; }
  const std::vector<DofIndex>& fixed_dofs() const { return fixed_; }
  bool is_fixed(DofIndex d) const;
  bool allow_new_nonzeros() const { return allow_new_nonzeros_; }
  double cumulative_dissipation() const { return cumulative_dissipation_; }
  int committed_steps() const { return steps_; }
  /// Calls of evaluate() and those of them answered by the last evaluation (same inputs, same
  /// history: Newton assembles the residual, then the tangent, at the same iterate).
  long evaluations() const { return evaluations_; }
  long reused_evaluations() const { return reused_evaluations_; }
  const std::vector<double>& committed_elastic_gap() const { return ge_; }

  /// Every (row, col) the contact may write. Rigid master: slave dofs within chain distance 3
  /// (static). Deformable master: additionally master nodes within `margin` of the slave nodes at
  /// displacement u (margin < 0: 2 x search radius).
  std::vector<std::pair<DofIndex, DofIndex>> sparsity(const double* u, std::size_t n, double margin) const;
  /// The same couplings as dense blocks (rows x cols), one or two per slave node.
  std::vector<std::pair<std::vector<DofIndex>, std::vector<DofIndex>>> sparsity_blocks(const double* u, std::size_t n,
                                                                                       double margin) const;

  const PenaltyChoice& penalty() const { return penalty_; }
  double search_radius() const;
  int gauss_points() const { return n_gauss_; }
  Method method() const { return method_; }
  const SurfaceMesh& slave() const { return slave_; }
  bool has_rigid_master() const { return rigid_ != nullptr; }
  bool has_deformable_master() const { return master_ != nullptr; }
  const RigidPolyline* rigid_master() const { return rigid_.get(); }
  const SurfaceMesh* deformable_master() const { return master_.get(); }
  const FrictionLaw* friction() const { return friction_.get(); }
  const ThermalParameters& thermal() const { return thermal_; }
  DofIndex max_dof() const { return max_dof_; }
  /// The pairs of the last evaluation, one row each: slave segment (node for node-to-segment),
  /// master image, master segment, lo xi, hi xi, 10 lo kind + hi kind (debugging and tests).
  const std::vector<std::array<double, 6>>& last_pairs() const { return last_pairs_; }

 private:
  struct MasterRef {
    long image = 0;
    int seg = -1;
  };
  struct PairRecord {
    int slave = -1;  ///< slave segment (mortar) or slave node (node-to-segment)
    MasterRef master;
    Breakpoint lo, hi;
  };
  /// Entities in the six slots of a pair's integrals (mortar_segment.hpp; entity A < ns: slave
  /// node A, ns + C: master node C; -1: none) and the slave nodes receiving the integrals.
  struct PairSlots {
    std::array<int, 6> entity{-1, -1, -1, -1, -1, -1};
    std::array<int, 2> receivers{-1, -1};
    int n_receivers = 0;
  };
  /// The dual variables of one slave node: its sorted entities, `stride` variables each (x, y[, T]).
  using Stencil = std::vector<int>;
  struct Stencils {
    std::vector<PairSlots> pairs;  ///< per pair
    std::vector<Stencil> nodes;    ///< per slave node; empty: the node is not paired
  };
  /// Mortar quantities of one slave node summed over its pairs, as duals over the node's stencil.
  struct NodalIntegrals {
    DX gx, gy, area;                       ///< gbar_A, A_A
    std::vector<std::pair<int, DX>> D, M;  ///< D_AB by slave node B, M_AC by entity ns + C
    V2<DX> nu;                             ///< Int M_A nu2 da (chain ends only: their frame)
    V2<DX> frame;                          ///< node_to_surface: n_A = -grad g_A
    double current_weight = 0.0;           ///< node_to_surface: current nodal length (outputs)
  };

  void positions(const double* u, std::size_t n, std::vector<V2<double>>& xs, std::vector<V2<double>>& xm) const;
  MasterSegment master_segment(const MasterRef& m) const;
  std::array<int, 2> master_nodes(const MasterRef& m) const;
  void candidates(const V2<double>& lo, const V2<double>& hi, std::vector<MasterRef>& out) const;
  void search_mortar(std::vector<PairRecord>& pairs) const;
  void search_nts(std::vector<PairRecord>& pairs) const;
  void search_surface(std::vector<PairRecord>& pairs) const;
  /// node_to_surface: gap, frame and weights of slave node A over its stencil L = {A}.
  void surface_integrals(int A, const Stencil& L, NodalIntegrals& a) const;
  SlaveSegment slave_segment(int e) const;
  void check_ready(std::size_t n, double dt) const;
  /// Whether evaluate(u, n, offset, dt, T_ref, with_blocks) would repeat the last evaluation.
  bool repeats_last(const double* u, std::size_t n, const V2<double>& offset, double dt, double T_ref,
                    bool with_blocks) const;
  void forget_evaluation() { last_.valid = false; }

  // phases of evaluate() (contact_interface.cpp says what each computes): 1 search, 2 stencils,
  // 3 integrate (+ scatter_pair), 4 nodal_kinematics, nodal law, record_node, 5 local_block
  std::vector<PairRecord> search(const double* u, std::size_t n, const V2<double>& offset);
  PairSlots pair_slots(const PairRecord& pr) const;
  Stencils stencils(const std::vector<PairRecord>& pairs) const;
  std::vector<NodalIntegrals> integrate(const std::vector<PairRecord>& pairs, const Stencils& st) const;
  void scatter_pair(const PairIntegrals& pi, const PairSlots& ps, int k, const Stencil& L, NodalIntegrals& a) const;
  NodalKinematics nodal_kinematics(int A, const Stencil& L, const NodalIntegrals& a, const double* u,
                                   double T_ref) const;
  void record_node(int A, const NodalIntegrals& a, const NodalKinematics& kin, const NodalResponse& resp, double dt,
                   InterfaceTotals& tot);
  LocalBlock local_block(const Stencil& L, const NodalIntegrals& a, const NodalResponse& resp) const;

  // helpers of the phases
  LawParameters law_parameters(double dt) const;
  int prev_node(int A) const { return slave_.prev[static_cast<std::size_t>(A)]; }
  int next_node(int A) const { return slave_.next[static_cast<std::size_t>(A)]; }
  bool chain_end(int A) const { return prev_node(A) < 0 || next_node(A) < 0; }
  /// A chain end that is a vertex of the body touching the master's face, not the seam of a
  /// periodic cell (there the two ends are one point of a closed chain, tied by the cell's
  /// constraint, and keep the one-sided slave normal of 5.36)
  bool vertex_end(int A) const { return chain_end(A) && !periodic_seam_; }
  /// Node A's contact frame is the master's averaged normal (a vertex end, or every node with
  /// set_master_frame(true)); else the averaged slave normal of 5.36.
  bool master_frame_node(int A) const { return master_frame_ || vertex_end(A); }
  int stride() const;  ///< dual variables per entity: 2 (x, y) or 3 (x, y, T)
  bool conduction_possible() const;
  V2<DX> position_dual(const Stencil& L, int e) const;
  DX temperature_dual(const Stencil& L, int e, const double* u) const;

  SurfaceMesh slave_;
  Method method_;
  std::unique_ptr<RigidPolyline> rigid_;
  std::unique_ptr<HeightField> height_;  ///< node_to_surface: the rigid master as a C2 spline
  std::vector<double> w_ref_;            ///< reference nodal weights of the slave (half segments)
  std::unique_ptr<SurfaceMesh> master_;
  PenaltyChoice penalty_;
  std::shared_ptr<const FrictionLaw> friction_;
  ThermalParameters thermal_;
  std::vector<double> slave_T_;
  std::vector<DofIndex> fixed_;  // sorted
  double search_radius_ = -1.0;
  std::vector<std::array<double, 6>> last_pairs_;
  int n_gauss_ = 4;
  bool allow_new_nonzeros_ = false;
  bool periodic_seam_ = false;
  bool master_frame_ = false;
  DofIndex max_dof_ = -1;

  // state of the current evaluation
  std::vector<V2<double>> xs_, xm_;
  V2<double> offset_{0.0, 0.0};
  SegmentGrid master_grid_;  // deformable master, current configuration
  std::vector<LocalBlock> blocks_;
  NodeOutput out_;
  InterfaceTotals totals_;
  bool evaluated_ = false;
  /// The inputs of the last evaluation; every change of history or parameters invalidates it.
  struct EvaluationInputs {
    std::vector<double> u;
    V2<double> offset{0.0, 0.0};
    double dt = 0.0, T_ref = 0.0;
    bool with_blocks = false, valid = false;
  };
  EvaluationInputs last_;
  long evaluations_ = 0, reused_evaluations_ = 0;

  // committed history
  std::vector<V2<double>> xs_n_, xm_n_;
  V2<double> offset_n_{0.0, 0.0};
  std::vector<double> ge_;
  double cumulative_dissipation_ = 0.0;
  int steps_ = 0;
};

}  // namespace rf
