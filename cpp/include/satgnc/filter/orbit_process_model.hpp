#pragma once
/// @file orbit_process_model.hpp
/// The orbit filter's process model (issue 15 items 2-3): propagates an orbit state (GCRF, km, km/s)
/// between measurement epochs with satgnc's DOP853 on any dynamics::ForceModel, together with the
/// state transition matrix and the discrete process noise.
///
/// State layout (dimension n = 6 + 3 dmc + parameters):
///   [ r (3, km, GCRF) | v (3, km/s, GCRF) | w (3, km/s^2, GCRF; only with DMC) | p (parameters) ]
/// The parameters (per-station range biases in km, time biases in s, Cd, Cr) are constants: their rows
/// of the transition matrix are the identity and they receive no process noise; Cd and Cr (cd_state,
/// cr_state) also drive the force model, and their columns of the STM come from the sensitivity to them.
///
/// Process noise (continuous white noise, discretized with the STM):
/// - **SNC** (state-noise compensation): a white acceleration with power spectral density
///   `snc_psd_ric` (km^2/s^3 per axis) in the radial / in-track / cross-track frame of the current
///   state (R = r/|r|, C = r x v/|r x v|, I = C x R), rotated to GCRF at each quadrature node;
/// - **DMC** (dynamic-model compensation): a first-order Gauss-Markov acceleration w (GCRF axes),
///   dw/dt = -w / tau + white noise of PSD 2 sigma^2 / tau (steady-state standard deviation sigma,
///   km/s^2), added to the force model's acceleration. Its own block is discretized exactly:
///   Phi_ww = exp(-dt/tau), Q_ww = sigma^2 (1 - exp(-2 dt/tau)); the coupling to r, v through the
///   sensitivity S = d(r, v)/dw0, integrated with the STM (dS/dt = A S + [0; I] exp(-t/tau)).
///
/// Discretization: Q = int_{t0}^{t1} Phi(t1, s) G(s) Qc(s) G(s)^T Phi(t1, s)^T ds, evaluated with
/// Gauss-Legendre quadrature (`quadrature_nodes` nodes) on sub-intervals of at most `noise_step` s,
/// Phi(t1, s) = Phi(t1, t0) Phi(s, t0)^-1 taken from the same DOP853 run's outputs at the nodes (the
/// sub-interval results compose as Q <- Phi_k Q Phi_k^T + Q_k). With >= 2 nodes the rule is exact for
/// force-free motion (the integrand is then a polynomial of degree 2 in s); on a J2 LEO orbit with
/// 300 s sub-intervals the default 5 nodes agree with an independent RK4 integration of
/// dP/dt = A P + P A^T + G Qc G^T to 1e-12 relative, 3 nodes to 1.3e-6
/// (tests/cpp/test_orbit_filter_process.cpp).
///
/// Flight grade: propagate() is noexcept and allocates nothing (the workspace, with both DOP853
/// integrators, is built by the constructor); a failure is a status.
#include <Eigen/Core>
#include <memory>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/filter/process_model.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace satgnc::filter {

/// Settings of OrbitProcessModel (plain struct; validate() throws std::invalid_argument naming the field).
struct OrbitProcessSettings {
  propagation::Dop853Settings integrator{};  ///< DOP853 tolerances (default: satgnc's orbit defaults)
  Vec3 snc_psd_ric =
      Vec3::Zero();  ///< SNC white-acceleration PSD, radial / in-track / cross-track, km^2/s^3 (>= 0)
  bool dmc = false;  ///< append the three Gauss-Markov acceleration states w (GCRF axes)
  Vec3 dmc_tau = Vec3::Constant(600.0);  ///< DMC time constants per GCRF axis, s (> 0)
  Vec3 dmc_sigma = Vec3::Zero();         ///< DMC steady-state standard deviations per axis, km/s^2 (>= 0)
  int parameters = 0;                    ///< constant parameter states appended after r, v (, w), >= 0
  double noise_step = 300.0;             ///< longest quadrature sub-interval, s (> 0)
  int quadrature_nodes = 5;              ///< Gauss-Legendre nodes per sub-interval, 1..5
  /// State index of an estimated drag coefficient Cd (a parameter state, -1: none). The force model flies
  /// the state's value (drag and atmosphere_drag), and the STM gets its column from the sensitivity
  /// dS/dt = A S + [0; da/dCd] (ForceModel::acceleration_partial), integrated with the STM.
  int cd_state = -1;
  /// State index of an estimated SRP reflectivity Cr (-1: none); as cd_state, through srp.
  int cr_state = -1;
  /// Throws std::invalid_argument("field: rule"): negative PSD or sigma, non-positive tau or
  /// noise_step, quadrature_nodes outside 1..5, parameters < 0, invalid integrator settings.
  void validate() const;
};

/// Outcome of one OrbitProcessModel::propagate: the integrator's status (success, max_steps,
/// step_size_too_small, rhs_failure, invalid_input for non-finite input) and its work.
struct OrbitProcessInfo {
  propagation::Dop853Status status = propagation::Dop853Status::unsolved;  ///< success or why not
  long steps = 0;      ///< accepted DOP853 steps, all sub-intervals
  long rhs_evals = 0;  ///< right-hand-side evaluations
};

namespace detail {
struct OrbitProcessWorkspace;
}

/// Orbit process model: state, STM and discrete process noise between two epochs (see the file doc).
/// Implements filter::ProcessModel, so that the generic KalmanFilter (filter/kalman_filter.hpp) runs on it.
class OrbitProcessModel final : public ProcessModel {
 public:
  /// Validates the settings and the force model (copied), sizes the workspace. Throws
  /// std::invalid_argument naming the field. Time axis: the force model's (s after its epoch).
  OrbitProcessModel(const dynamics::ForceModel& force_model, const OrbitProcessSettings& settings);
  ~OrbitProcessModel();
  OrbitProcessModel(OrbitProcessModel&&) noexcept;             ///< movable (the workspace moves)
  OrbitProcessModel& operator=(OrbitProcessModel&&) noexcept;  ///< movable
  OrbitProcessModel(const OrbitProcessModel&) = delete;
  OrbitProcessModel& operator=(const OrbitProcessModel&) = delete;

  /// State dimension n = 6 + 3 (DMC) + parameters.
  int dimension() const noexcept { return n_; }
  /// ProcessModel: the state dimension n.
  int state_dimension() const noexcept override { return n_; }
  /// ProcessModel: x1 = x0 propagated from t0 to t1 with phi and qd (the same arithmetic as the other
  /// overload; the STM is always integrated, with_jacobian notwithstanding: DOP853 integrates the
  /// state and the STM together, and qd needs the STM). Status failed when the integrator fails.
  ModelStatus propagate(const Eigen::Ref<const Eigen::VectorXd>& x0, double t0, double t1,
                        Eigen::Ref<Eigen::VectorXd> x1, Eigen::Ref<Eigen::MatrixXd> phi,
                        Eigen::Ref<Eigen::MatrixXd> qd, bool with_jacobian) noexcept override;
  /// DOP853 steps taken by the ProcessModel overload since construction (a running count; the
  /// orbit filter reports the difference over a run).
  long total_steps() const noexcept { return total_steps_; }
  /// Index of the first parameter state (6 or 9).
  int parameter_offset() const noexcept { return settings_.dmc ? 9 : 6; }
  /// The validated settings.
  const OrbitProcessSettings& settings() const noexcept { return settings_; }
  /// The force model (a copy).
  const dynamics::ForceModel& force_model() const noexcept { return force_model_; }

  /// Propagate x (size n, in place) from t0 to t1 (s; t1 < t0 runs backward, with Q the noise of the
  /// forward interval mapped back, i.e. the negative of a covariance: use forward intervals in a
  /// filter); fills phi (n x n) = d x(t1) / d x(t0) and q (n x n), the discrete process noise.
  /// t1 == t0 gives the identity and zero. noexcept, allocation-free; phi and q must be n x n.
  OrbitProcessInfo propagate(double t0, double t1, Eigen::Ref<Eigen::VectorXd> x,
                             Eigen::Ref<Eigen::MatrixXd> phi, Eigen::Ref<Eigen::MatrixXd> q) noexcept;

  /// The GCRF-to-RIC rotation rows (R, I, C unit vectors, km-free) of a state r (km), v (km/s).
  static Mat3 ric_rows(const Vec3& r, const Vec3& v) noexcept;

 private:
  dynamics::ForceModel force_model_;
  OrbitProcessSettings settings_;
  int n_ = 6;
  long total_steps_ = 0;
  std::unique_ptr<detail::OrbitProcessWorkspace> ws_;
};

}  // namespace satgnc::filter
