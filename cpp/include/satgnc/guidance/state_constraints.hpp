#pragma once
/// @file state_constraints.hpp
/// State constraints in the L1 ADMM (issue 16 item 1): affine half-spaces a' x_k <= b per node,
/// per-node state boxes, an approach cone (second-order cone on the relative position about a
/// docking axis) and a closing-velocity limit that tightens with range (piecewise-linear, expanded
/// into half-spaces). Same problem as admm.hpp (LtvProblem: Qf, Q, diagonal R, per-axis L1 weights,
/// control box, hard terminal state) plus
///   C_k x_k in K_k,  k = 1..N  (x_0 is given),
/// with K_k a product of intervals [l, u] (half-spaces, boxes, the terminal state x_N = x_f) and
/// shifted second-order cones (approach cones).
///
/// Splitting: U = Y (controls, closed-form prox of L1 + box + diagonal R, as in AdmmSolver) and
/// s = C x = Z (one consensus variable per constraint row, projected exactly: clip for interval
/// rows, the second-order cone projection for cone blocks), each with its own multiplier and
/// penalty. The x/u step stays one LQR solved by a Riccati recursion: the penalty of the state rows
/// enters as a per-node state weight sum_j rho_j c_j c_j' and a linear term, the gains are cached
/// while rho is fixed. Penalties: rho_u = rho for the controls, rho_j = rho kappa_j for row j with
/// kappa_j = 1 / ||c_j' dx_k/dU||^2 (the row's sensitivity to the controls, one Ruiz-like row
/// scaling), times 1e3 on equality rows (OSQP's rule); rho is adapted by OSQP's residual balancing.
/// Rows are normalized to ||c_j|| = 1 (cone blocks: rows tan(alpha) a, b1, b2).
///
/// Status `solved` is given only when, on the problem as given (no scaling): the flown plan Y rolled
/// out violates no constraint row by more than eps_abs + eps_rel ||X_flown||_inf (length / velocity
/// units of the state), the ADMM residuals hold, and the relative duality gap (P - D) / max(|P|, |D|)
/// <= eps_gap with D a Fenchel dual bound built from the state multipliers (docs/guidance.md,
/// "State constraints"). `primal_infeasible` only with a checked Farkas certificate over the
/// constraint rows. Units are the caller's (the scenario: m, m/s, N).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "satgnc/guidance/admm.hpp"

namespace satgnc::guidance {

namespace detail {
struct StateAdmmWorkspace;  // src/guidance/state_admm.cpp
}  // namespace detail

/// Affine half-space a' x_node <= b on the state at one node (units of the state and of b).
struct StateHalfSpace {
  int node = 1;       ///< node k in 1..N (x_0 is given)
  Eigen::VectorXd a;  ///< nx, nonzero
  double b = 0.0;     ///< bound (finite)
};

/// Per-component bounds lower <= x_k <= upper at the listed nodes (entries may be -inf / +inf).
struct StateBox {
  std::vector<int> nodes;  ///< nodes in 1..N
  Eigen::VectorXd lower;   ///< nx (state units), lower <= upper
  Eigen::VectorXd upper;   ///< nx (state units)
};

/// Approach cone: || p - (a.p) a || <= tan(half_angle) (a.p - apex_offset) at the listed nodes,
/// p = the position entries of the state, a the unit docking axis (the target's approach corridor,
/// apex at apex_offset a). Second-order cone, exact projection.
struct ApproachCone {
  std::vector<int> nodes;                      ///< nodes in 1..N
  Eigen::Vector3d axis{1.0, 0.0, 0.0};         ///< docking axis (normalized at setup; nonzero)
  double half_angle = 0.5;                     ///< rad, in (0, pi/2)
  double apex_offset = 0.0;                    ///< apex along the axis (position units)
  std::array<int, 3> position_index{0, 1, 2};  ///< state entries of the position
};

/// Closing-velocity limit tightening with range: |a.v| <= min_i (intercept_i + slope_i (a.p)) at the
/// listed nodes (a.p the range along the unit axis a, v the velocity entries). Concave
/// piecewise-linear bound, so the set is polyhedral: two half-spaces per segment and node,
///   a.v - slope_i a.p <= intercept_i  and  -a.v - slope_i a.p <= intercept_i.
struct ClosingVelocityLimit {
  std::vector<int> nodes;                      ///< nodes in 1..N
  Eigen::Vector3d axis{1.0, 0.0, 0.0};         ///< along-axis direction (normalized; nonzero)
  Eigen::VectorXd intercept;                   ///< velocity units, one per segment (finite)
  Eigen::VectorXd slope;                       ///< 1/s, one per segment (finite)
  std::array<int, 3> position_index{0, 1, 2};  ///< state entries of the position
  std::array<int, 3> velocity_index{3, 4, 5};  ///< state entries of the velocity
};

/// All state constraints of one problem.
struct StateConstraints {
  std::vector<StateHalfSpace> half_spaces;
  std::vector<StateBox> boxes;
  std::vector<ApproachCone> cones;
  std::vector<ClosingVelocityLimit> closing_velocity;
  /// True when there is no constraint at all.
  bool empty() const {
    return half_spaces.empty() && boxes.empty() && cones.empty() && closing_velocity.empty();
  }
};

/// Result of StateConstrainedAdmm::solve(): the AdmmResult fields (X, U, Y, Lambda, X_flown, info)
/// and the state side. For `primal_infeasible`, infeasibility_certificate holds the unit multiplier
/// over the constraint rows (size rows()), see the file comment.
struct StateAdmmResult : AdmmResult {
  Eigen::VectorXd state_multipliers;  ///< multipliers of C x = Z, one per row (unscaled)
  Eigen::VectorXd state_consensus;    ///< Z, one per row (normalized-row units)
  double max_violation = 0.0;         ///< largest violation of a row by X_flown (state units)
  double violation_tolerance = 0.0;   ///< eps_abs + eps_rel ||X_flown||_inf (state units)
  /// Method admm_ipm, neither method certified: true when the returned plan is the interior-point
  /// method's last one, not ADMM's (lower true objective within the violation tolerance, or the
  /// smaller scaled violation when neither plan is within it); the status stays unsolved-type.
  bool ipm_plan = false;
};

/// L1 ADMM with state constraints. The constructor validates (std::invalid_argument
/// "name: rule") and allocates; solve(), set_half_space() and set_x0() do not allocate.
/// Settings used: rho, max_iterations, eps_abs, eps_rel, relaxation, adaptive_rho*, rho_min/max,
/// eps_gap, gap_floor, gap_check_interval, inaccurate_factor, time_limit,
/// infeasibility_check_interval. The paper stopping rule, group-L2, the norm ball and a
/// non-diagonal R are rejected (no closed-form prox with the state rows).
class StateConstrainedAdmm {
 public:
  /// @throws std::invalid_argument naming the offending field (e.g. "cones[0].half_angle: ...")
  StateConstrainedAdmm(const LtvProblem& problem, const StateConstraints& constraints,
                       const AdmmSettings& settings = AdmmSettings());
  ~StateConstrainedAdmm();
  StateConstrainedAdmm(StateConstrainedAdmm&&) noexcept;
  StateConstrainedAdmm& operator=(StateConstrainedAdmm&&) noexcept;
  StateConstrainedAdmm(const StateConstrainedAdmm&) = delete;
  StateConstrainedAdmm& operator=(const StateConstrainedAdmm&) = delete;

  /// Run ADMM from the previous iterate if warm (default after the first solve) or from zeros.
  const StateAdmmResult& solve() noexcept;
  /// Replace half-space i (its index in StateConstraints::half_spaces) by a' x_node <= b, without
  /// allocation (sequential convex programming: supporting half-spaces of a keep-out zone).
  /// Refactors the Riccati gains. Returns false (nothing changed) on a bad index, node, size or a
  /// zero / non-finite a or b.
  bool set_half_space(int i, int node, const Eigen::Ref<const Eigen::VectorXd>& a, double b) noexcept;
  /// New initial state (gains reused). Returns false on a wrong size or non-finite entry.
  bool set_x0(const Eigen::Ref<const Eigen::VectorXd>& x0) noexcept;
  /// Next solve starts from zeros.
  void cold_start() noexcept;
  /// Number of constraint rows (interval rows + 3 per cone and node).
  int rows() const;
  /// Node of each row, and its kind: 0 interval row, 1 cone block row.
  const Eigen::VectorXi& row_nodes() const;
  /// Largest violation of the constraints by a state trajectory X (nx x (N+1)), state units; allocates.
  double violation(const Eigen::Ref<const Eigen::MatrixXd>& X) const;
  const StateAdmmResult& result() const;  ///< last result
  int nx() const;
  int nu() const;
  int horizon() const;

 private:
  std::unique_ptr<detail::StateAdmmWorkspace> ws_;
};

}  // namespace satgnc::guidance
