#include "satgnc/od/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "detail/od_workspace.hpp"
#include "detail/root.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::od {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kLambdaFloor = 1e-12;  // below: pure Gauss-Newton steps
constexpr double kGnAccept = 0.25;      // GN: fraction of the model's decrease (t - t^2/2)|c|^2 required
constexpr double kGeoStep = 0.1;        // finite-difference step (fraction of v) of the geodesic probe
constexpr double kGeoRatio = 0.75;      // LM keeps the acceleration a only if 2 |D a| <= this |D v|
constexpr double kExtrapMin = 2.0;      // extrapolate an accepted step only when the parabola's t* >= this
constexpr double kExtrapMax = 10.0;     // ... and at most this far
constexpr int kGnPlainTrials = 3;       // GN: uncorrected trials t = 1, 1/2, 1/4 before the corrected ones
}  // namespace

void OdSettings::validate() const {
  using core::require;
  require(max_iterations >= 1 && max_iterations <= 100000, "settings.max_iterations", "must be in 1..100000");
  core::require_nonnegative(step_tol, "settings.step_tol");
  core::require_nonnegative(step_sigma_tol, "settings.step_sigma_tol");
  core::require_nonnegative(cost_tol, "settings.cost_tol");
  core::require_nonnegative(residual_tol, "settings.residual_tol");
  require(std::isfinite(rank_tol) && rank_tol > 0.0 && rank_tol < 1.0, "settings.rank_tol",
          "must be in (0, 1)");
  core::require_nonnegative(min_radius, "settings.min_radius");
  core::require_positive(mu, "settings.mu");
  core::require_positive(fit_sigma, "settings.fit_sigma");
  core::require_positive(min_range, "settings.min_range");
  core::require_positive(lm_lambda0, "settings.lm_lambda0");
  require(std::isfinite(lm_increase) && lm_increase > 1.0, "settings.lm_increase", "must be > 1");
  require(std::isfinite(lm_decrease) && lm_decrease > 0.0 && lm_decrease < 1.0, "settings.lm_decrease",
          "must be in (0, 1)");
  require(lm_max_rejections >= 1, "settings.lm_max_rejections", "must be >= 1");
  require(gn_max_halvings >= 0 && gn_max_halvings <= 60, "settings.gn_max_halvings", "must be in 0..60");
  require(lm_polish_iterations >= 0, "settings.lm_polish_iterations", "must be >= 0");
  require(valley_corrections >= 0 && valley_corrections <= 100, "settings.valley_corrections",
          "must be in 0..100");
  core::require_nonnegative(lm_stall_tol, "settings.lm_stall_tol");
  require(method == OdMethod::newton || method == OdMethod::gauss_newton ||
              method == OdMethod::levenberg_marquardt,
          "settings.method", "unknown method");
}

OdSolver OdSolver::from_measurements(std::vector<Station> stations, const std::vector<Measurement>& meas,
                                     std::shared_ptr<StmPropagator> propagator, const OdSettings& settings) {
  core::require(!stations.empty(), "stations", "need at least one station");
  for (std::size_t i = 0; i < stations.size(); ++i) stations[i].validate();
  validate_measurements(meas, static_cast<int>(stations.size()));
  settings.validate();
  if (settings.method == OdMethod::newton)
    core::require(
        meas.size() == 6, "measurements",
        "the six-point Newton-Raphson needs exactly 6 observations, got " + std::to_string(meas.size()),
        "use gauss_newton or levenberg_marquardt for more");
  else
    core::require(meas.size() >= 6, "measurements",
                  "need at least 6 observations for 6 unknowns, got " + std::to_string(meas.size()));
  std::vector<Row> rows;
  std::vector<double> t;
  Eigen::VectorXd sigma(meas.size());
  for (std::size_t i = 0; i < meas.size(); ++i) {
    const auto& m = meas[i];
    const bool is_range = m.type == MeasurementType::range;
    rows.push_back({is_range ? RowKind::obs_range : RowKind::obs_range_rate, 0, m.station,
                    is_range ? m.value : kNaN, is_range ? kNaN : m.value});
    t.push_back(m.t);
    sigma(static_cast<Eigen::Index>(i)) = m.sigma;
  }
  OdSolver s;
  s.setup(std::move(stations), std::move(rows), std::move(t), std::move(sigma), std::move(propagator),
          settings);
  return s;
}

OdSolver OdSolver::from_conditions(std::vector<Station> stations, const std::vector<BoundaryCondition>& conds,
                                   std::shared_ptr<StmPropagator> propagator, const OdSettings& settings) {
  using core::require;
  require(!stations.empty(), "stations", "need at least one station");
  for (auto& st : stations) st.validate();
  settings.validate();
  if (settings.method == OdMethod::newton)
    require(conds.size() == 6, "conditions",
            "the six-point Newton-Raphson needs exactly 6 conditions, got " + std::to_string(conds.size()));
  else
    require(conds.size() >= 6, "conditions",
            "need at least 6 conditions for 6 unknowns, got " + std::to_string(conds.size()));
  std::vector<Row> rows;
  std::vector<double> t;
  Eigen::VectorXd sigma(conds.size());
  const int ns = static_cast<int>(stations.size());
  for (std::size_t i = 0; i < conds.size(); ++i) {
    const auto& c = conds[i];
    const std::string p = "conditions[" + std::to_string(i) + "]";
    require(std::isfinite(c.t), p + ".t", "must be finite");
    require(c.type == ConditionType::range || c.type == ConditionType::doppler, p + ".type",
            "unknown condition type (hint: range or doppler)");
    require(std::isfinite(c.range) && c.range > 0.0, p + ".range", "must be finite and > 0 km",
            "a zero range puts the station at the satellite");
    require(std::isfinite(c.sigma_range) && c.sigma_range > 0.0, p + ".sigma_range",
            "must be finite and > 0");
    require(c.station >= 0 && c.station < ns, p + ".station", "index out of range");
    double sig = 2.0 * c.range * c.sigma_range;
    if (c.type == ConditionType::doppler) {
      require(std::isfinite(c.range_rate), p + ".range_rate", "must be finite");
      require(std::isfinite(c.sigma_range_rate) && c.sigma_range_rate > 0.0, p + ".sigma_range_rate",
              "must be finite and > 0");
      sig = std::hypot(c.range * c.sigma_range_rate, c.range_rate * c.sigma_range);
    }
    for (std::size_t k = 0; k < i; ++k)
      require(!(conds[k].t == c.t && conds[k].type == c.type && conds[k].station == c.station), p + ".t",
              "duplicate time " + std::to_string(c.t) + " s (same type and station as conditions[" +
                  std::to_string(k) + "])");
    rows.push_back({c.type == ConditionType::range ? RowKind::cond_range : RowKind::cond_doppler, 0,
                    c.station, c.range, c.type == ConditionType::doppler ? c.range_rate : kNaN});
    t.push_back(c.t);
    sigma(static_cast<Eigen::Index>(i)) = sig;
  }
  OdSolver s;
  s.setup(std::move(stations), std::move(rows), std::move(t), std::move(sigma), std::move(propagator),
          settings);
  return s;
}

OdSolver::OdSolver() : ws_(std::make_unique<detail::OdWorkspace>()) {}
OdSolver::~OdSolver() = default;
OdSolver::OdSolver(OdSolver&&) noexcept = default;
OdSolver& OdSolver::operator=(OdSolver&&) noexcept = default;

void OdSolver::setup(std::vector<Station> stations, std::vector<Row> rows, std::vector<double> row_times,
                     Eigen::VectorXd sigma, std::shared_ptr<StmPropagator> propagator,
                     const OdSettings& settings) {
  core::require(propagator != nullptr, "propagator", "must not be null");
  stations_ = std::move(stations);
  settings_ = settings;
  max_iter_cap_ = settings.max_iterations;
  prop_ = std::move(propagator);
  sigma_ = std::move(sigma);
  times_ = row_times;
  std::sort(times_.begin(), times_.end());
  times_.erase(std::unique(times_.begin(), times_.end()), times_.end());
  for (std::size_t i = 0; i < rows.size(); ++i)
    rows[i].time_index =
        static_cast<int>(std::lower_bound(times_.begin(), times_.end(), row_times[i]) - times_.begin());
  rows_ = std::move(rows);
  const Eigen::Index m = static_cast<Eigen::Index>(rows_.size());
  const Eigen::Index h = max_iter_cap_ + 1;
  ws_->resize(m, times_.size());
  res_.residuals.setZero(m);
  res_.normalized.setZero(m);
  res_.range_residuals.setZero(m);
  res_.range_rate_residuals.setZero(m);
  res_.history_x0.setConstant(h, 6, kNaN);
  res_.history_residuals.setConstant(h, m, kNaN);
  res_.history_range_residuals.setConstant(h, m, kNaN);
  res_.history_range_rate_residuals.setConstant(h, m, kNaN);
  res_.history_cost.setConstant(h, kNaN);
  res_.history_lambda.setConstant(h, kNaN);
}

void OdSolver::set_settings(const OdSettings& s) {
  s.validate();
  core::require(s.max_iterations <= max_iter_cap_, "settings.max_iterations",
                "may not exceed the value given at setup (" + std::to_string(max_iter_cap_) + ")");
  core::require((s.method == OdMethod::newton) == (settings_.method == OdMethod::newton) || rows_.size() == 6,
                "settings.method", "newton needs exactly 6 rows");
  settings_ = s;
}

bool OdSolver::physical(const Vec6& x) const {
  if (!x.allFinite()) return false;
  const double r = x.head<3>().norm();
  if (r < settings_.min_radius) return false;
  return 0.5 * x.tail<3>().squaredNorm() - settings_.mu / r < 0.0;
}

// The one call into user code inside solve(): an exception thrown by a propagator is a failed
// propagation (status propagation_failed), so that solve() is noexcept.
bool OdSolver::propagate_noexcept(const Vec6& x0) noexcept {
  try {
    return prop_->propagate(x0, times_.data(), static_cast<int>(times_.size()), ws_->states_.data(),
                            ws_->stms_.data());
  } catch (...) {
    return false;
  }
}

OdStatus OdSolver::eval_at(const Vec6& x0, bool with_jac) {
  ++res_.evaluations;
  if (!physical(x0)) return OdStatus::diverged;
  const int nt = static_cast<int>(times_.size());
  if (!propagate_noexcept(x0)) return OdStatus::propagation_failed;
  for (int i = 0; i < nt; ++i)
    if (!physical(ws_->states_[static_cast<std::size_t>(i)])) return OdStatus::diverged;
  Row6 g;
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const Row& row = rows_[k];
    const Eigen::Index ki = static_cast<Eigen::Index>(k);
    const Vec6& x = ws_->states_[static_cast<std::size_t>(row.time_index)];
    const Vec6 R = stations_[static_cast<std::size_t>(row.station)].state(
        times_[static_cast<std::size_t>(row.time_index)]);
    const Vec3 d = x.head<3>() - R.head<3>();
    const Vec3 dv = x.tail<3>() - R.tail<3>();
    const double rho = d.norm();
    if (!(rho >= settings_.min_range)) return OdStatus::degenerate_geometry;
    const double rhodot = d.dot(dv) / rho;
    ws_->rr_(ki) = std::isnan(row.range) ? kNaN : rho - row.range;
    ws_->rrr_(ki) = std::isnan(row.range_rate) ? kNaN : rhodot - row.range_rate;
    switch (row.kind) {
      case RowKind::obs_range:
        ws_->r_(ki) = rho - row.range;
        g.head<3>() = d.transpose() / rho;
        g.tail<3>().setZero();
        break;
      case RowKind::obs_range_rate:
        ws_->r_(ki) = rhodot - row.range_rate;
        g.head<3>() = (dv - rhodot * d / rho).transpose() / rho;
        g.tail<3>() = d.transpose() / rho;
        break;
      case RowKind::cond_range:
        ws_->r_(ki) = d.squaredNorm() - row.range * row.range;
        g.head<3>() = 2.0 * d.transpose();
        g.tail<3>().setZero();
        break;
      case RowKind::cond_doppler:
        ws_->r_(ki) = d.dot(dv) - row.range * row.range_rate;
        g.head<3>() = dv.transpose();
        g.tail<3>() = d.transpose();
        break;
    }
    ws_->rn_(ki) = ws_->r_(ki) / sigma_(ki);
    if (with_jac)
      ws_->jn_.row(ki).noalias() = (g * ws_->stms_[static_cast<std::size_t>(row.time_index)]) / sigma_(ki);
  }
  if (!ws_->rn_.allFinite()) return OdStatus::diverged;
  return OdStatus::converged;
}

void OdSolver::factor() {
  ws_->aug_.leftCols<6>() = ws_->jn_;
  ws_->aug_.col(6) = ws_->rn_;
  detail::householder_qr_inplace(ws_->aug_, ws_->qr_);
  ws_->R_ = ws_->aug_.topLeftCorner<6, 6>().triangularView<Eigen::Upper>();
  ws_->c_ = ws_->aug_.block<6, 1>(0, 6);
  ws_->svd_.compute(ws_->R_, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec6 s = ws_->svd_.singularValues();
  res_.singular_values = s;
  int rank = 0;
  for (int i = 0; i < 6; ++i)
    if (s(i) > settings_.rank_tol * s(0)) ++rank;
  res_.rank = rank;
  res_.condition_number = s(5) > 0.0 ? s(0) / s(5) : kInf;
}

void OdSolver::record(int k, double lambda) {
  res_.history_x0.row(k) = res_.x0.transpose();
  res_.history_residuals.row(k) = ws_->r_.transpose();
  res_.history_range_residuals.row(k) = ws_->rr_.transpose();
  res_.history_range_rate_residuals.row(k) = ws_->rrr_.transpose();
  res_.history_cost(k) = 0.5 * ws_->rn_.squaredNorm();
  res_.history_lambda(k) = lambda;
}

bool OdSolver::small_step(const Vec6& dx, const Vec6& x) const {
  if ((ws_->R_.triangularView<Eigen::Upper>() * dx).norm() <= settings_.step_sigma_tol) return true;
  for (int i = 0; i < 6; ++i)
    if (std::abs(dx(i)) > settings_.step_tol * (1.0 + std::abs(x(i)))) return false;
  return true;
}

// Convergence test of gauss_newton / levenberg_marquardt at the current iterate (after factor()):
// gradient |c_r| <= step_sigma_tol, predicted decrease 0.5 |c_r|^2 <= cost_tol * cost, or a relative
// step below step_tol, with c_r the part of c = Q^T r_n inside the numerical range of R. Needs
// rank 6 to say converged; with rank < 6 the test still stops the iteration (the caller reports
// singular).
bool OdSolver::converged_here(const Vec6& x) const {
  const Vec6 w = ws_->svd_.matrixU().transpose() * ws_->c_;
  const double g = w.head(res_.rank).norm();
  if (g <= settings_.step_sigma_tol) return true;
  if (0.5 * g * g <= settings_.cost_tol * 0.5 * ws_->rn_.squaredNorm()) return true;
  const Vec6 dx = gn_step();
  for (int i = 0; i < 6; ++i)
    if (std::abs(dx(i)) > settings_.step_tol * (1.0 + std::abs(x(i)))) return false;
  return true;
}

// -R^+ b by the SVD of R truncated at the numerical rank; gn_step() = -R^+ c.
Vec6 OdSolver::solve_r(const Vec6& b) const {
  Vec6 w = ws_->svd_.matrixU().transpose() * b;
  for (int i = 0; i < 6; ++i) w(i) = i < res_.rank ? w(i) / res_.singular_values(i) : 0.0;
  return -(ws_->svd_.matrixV() * w);
}

Vec6 OdSolver::gn_step() const { return solve_r(ws_->c_); }

// Geodesic acceleration (Transtrum & Sethna 2012): the second directional derivative of the
// normalized residuals along v by a finite difference of step kGeoStep, r_vv ~ (2/h)((r(x+hv) -
// r(x))/h - J v), projected by the Householder reflectors of the current factorization: returns
// Q1^T r_vv (6), or false when x + h v cannot be evaluated. Needs ws_->rn0_/ws_->jn0_ at x; clobbers the
// buffers.
bool OdSolver::second_derivative(const Vec6& x, const Vec6& v, Vec6& qt_rvv) {
  if (eval_at(x + kGeoStep * v, false) != OdStatus::converged) return false;
  ws_->gw_.noalias() = ws_->jn0_ * v;
  ws_->gw_ = (2.0 / kGeoStep) * ((ws_->rn_ - ws_->rn0_) / kGeoStep - ws_->gw_);
  if (!ws_->gw_.allFinite()) return false;
  const Eigen::Index m = ws_->gw_.size();
  const Eigen::MatrixXd& qr = ws_->aug_;  // factor()'s QR in place
  for (Eigen::Index j = 0; j < 6; ++j) {  // Q^T y = H_5 ... H_0 y, H_j = I - tau v v^T, v = [1; essential]
    const Eigen::Index n = m - j - 1;
    double sdot = ws_->gw_(j) + (n > 0 ? qr.col(j).tail(n).dot(ws_->gw_.tail(n)) : 0.0);
    sdot *= ws_->qr_.tau(j);
    ws_->gw_(j) -= sdot;
    if (n > 0) ws_->gw_.tail(n) -= sdot * qr.col(j).tail(n);
  }
  qt_rvv = ws_->gw_.head<6>();
  return true;
}

void OdSolver::finish(const Vec6& x, bool buffers_valid) {
  res_.x0 = x;
  // x was evaluated successfully before (it is an accepted iterate), so this cannot fail.
  if (!buffers_valid && eval_at(x, true) != OdStatus::converged) return;
  factor();
  res_.residuals = ws_->r_;
  res_.normalized = ws_->rn_;
  res_.range_residuals = ws_->rr_;
  res_.range_rate_residuals = ws_->rrr_;
  res_.cost = 0.5 * ws_->rn_.squaredNorm();
  res_.max_abs_normalized = ws_->rn_.cwiseAbs().maxCoeff();
  res_.fits = std::sqrt(ws_->rn_.squaredNorm() / static_cast<double>(ws_->rn_.size())) <= settings_.fit_sigma;
  const Vec6 s = res_.singular_values;
  if (res_.rank == 6) {
    const Mat6& V = ws_->svd_.matrixV();
    res_.covariance.noalias() = V * s.cwiseInverse().cwiseAbs2().asDiagonal() * V.transpose();
    const Vec6 sd = res_.covariance.diagonal().cwiseSqrt();
    res_.correlation = res_.covariance.cwiseQuotient(sd * sd.transpose());
  } else {
    res_.covariance.setConstant(kInf);
    res_.correlation.setConstant(kNaN);
  }
  const bool stopped = res_.status == OdStatus::max_iterations || res_.status == OdStatus::stalled;
  // A budget or line search that ran out exactly at a converged point is converged.
  if (stopped && settings_.method != OdMethod::newton && converged_here(x)) res_.status = OdStatus::converged;
  if (res_.rank < 6 && (stopped || res_.status == OdStatus::converged)) res_.status = OdStatus::singular;
}

void OdSolver::set_initial_guess(const Vec6& x0_guess) noexcept { guess_ = x0_guess; }

const OdResult& OdSolver::solve() noexcept {
  // Allocation-free after setup: every buffer is sized in setup() and the QRs run in place
  // (detail/householder_qr.hpp). The guard covers the propagator too (StmPropagator's contract).
  SATGNC_NO_MALLOC_SCOPE;
  const auto t_start = std::chrono::steady_clock::now();
  solve_iterate(guess_);
  // core::InfoBase mirrors of the result (read-only diagnostics, no effect on the iterates)
  OdInfo& info = res_.info;
  info.status = res_.status;
  info.iterations = res_.iterations;
  info.primal_residual = rows() > 0 ? std::sqrt(2.0 * res_.cost / rows()) : 0.0;
  info.dual_residual =
      res_.iterations > 0 && res_.iterations < res_.history_x0.rows()
          ? (res_.history_x0.row(res_.iterations) - res_.history_x0.row(res_.iterations - 1)).norm()
          : 0.0;
  info.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return res_;
}

void OdSolver::solve_iterate(const Vec6& guess) {
  res_.status = OdStatus::unsolved;
  res_.iterations = 0;
  res_.evaluations = 0;
  res_.rank = 0;
  res_.fits = false;
  res_.cost = kInf;
  res_.max_abs_normalized = kInf;
  res_.condition_number = kInf;
  res_.covariance.setConstant(kNaN);
  res_.correlation.setConstant(kNaN);
  res_.singular_values.setZero();
  res_.history_x0.setConstant(kNaN);
  res_.history_residuals.setConstant(kNaN);
  res_.history_range_residuals.setConstant(kNaN);
  res_.history_range_rate_residuals.setConstant(kNaN);
  res_.history_cost.setConstant(kNaN);
  res_.history_lambda.setConstant(kNaN);
  res_.x0 = guess;
  const OdStatus st = eval_at(guess, true);
  if (st != OdStatus::converged) {
    // Not even the guess has residuals: report that, with an infinite cost (never 0).
    res_.status = st;
    ws_->r_.setConstant(kNaN);
    ws_->rn_.setConstant(kNaN);
    ws_->rr_.setConstant(kNaN);
    ws_->rrr_.setConstant(kNaN);
    res_.residuals = ws_->r_;
    res_.normalized = ws_->rn_;
    res_.range_residuals = ws_->rr_;
    res_.range_rate_residuals = ws_->rrr_;
    res_.history_x0.row(0) = guess.transpose();
    res_.history_cost(0) = kInf;
    res_.history_lambda(0) = 0.0;
    return;
  }
  record(0, 0.0);
  Vec6 x = guess;
  bool buffers_valid = true;  // ws_->r_/ws_->jn_ belong to x
  switch (settings_.method) {
    case OdMethod::newton:
      buffers_valid = solve_newton(x);
      break;
    case OdMethod::gauss_newton:
      buffers_valid = solve_gauss_newton(x);
      break;
    case OdMethod::levenberg_marquardt:
      buffers_valid = solve_lm(x);
      break;
  }
  finish(x, buffers_valid);
}

// -argmin |R d + b|^2 + lambda |D d|^2 by a fixed-size QR of [R b; sqrt(lambda) D 0].
Vec6 OdSolver::damped_solve(const Vec6& b, double lambda, const Vec6& diag) const {
  Eigen::Matrix<double, 12, 7> A = Eigen::Matrix<double, 12, 7>::Zero();
  A.topLeftCorner<6, 6>() = ws_->R_;
  A.block<6, 1>(0, 6) = b;
  A.bottomLeftCorner<6, 6>() = (std::sqrt(lambda) * diag).asDiagonal();
  const Eigen::HouseholderQR<Eigen::Matrix<double, 12, 7>> q(A);
  const Mat6 Rl = q.matrixQR().topLeftCorner<6, 6>().triangularView<Eigen::Upper>();
  const Vec6 cl = q.matrixQR().block<6, 1>(0, 6);
  return -Rl.triangularView<Eigen::Upper>().solve(cl);
}

void OdSolver::save_buffers() {
  ws_->rs_ = ws_->r_;
  ws_->rns_ = ws_->rn_;
  ws_->rrs_ = ws_->rr_;
  ws_->rrrs_ = ws_->rrr_;
  ws_->jns_ = ws_->jn_;
}

void OdSolver::restore_buffers() {
  ws_->r_ = ws_->rs_;
  ws_->rn_ = ws_->rns_;
  ws_->rr_ = ws_->rrs_;
  ws_->rrr_ = ws_->rrrs_;
  ws_->jn_ = ws_->jns_;
}

// Predictor-corrector for curved valleys: from the trial point xt (buffers current, cost ct), up to
// valley_corrections Gauss-Newton steps min |r_n + J_n P y| over the 5-dimensional complement P of
// the step direction (orthonormal in the coordinates scaled by diag, so the correction is unit
// invariant and does not undo the progress along the valley); each is kept only if it lowers the
// cost. Leaves xt, ct and the buffers at the lowest point.
void OdSolver::valley_correct(Vec6& xt, double& ct, const Vec6& dir, const Vec6& diag) {
  if (settings_.valley_corrections <= 0) return;
  Vec6 u = diag.cwiseProduct(dir);
  const double nu = u.norm();
  if (!(nu > 0.0) || !std::isfinite(nu) || !(diag.array() > 0.0).all()) return;
  u /= nu;
  // Columns 1..5 of the Householder reflector that maps u to e1 span u's orthogonal complement.
  Vec6 w = u;
  w(0) += u(0) >= 0.0 ? 1.0 : -1.0;
  const Mat6 H = Mat6::Identity() - (2.0 / w.squaredNorm()) * (w * w.transpose());
  const Eigen::Matrix<double, 6, 5> P = diag.cwiseInverse().asDiagonal() * H.rightCols<5>();
  for (int j = 0; j < settings_.valley_corrections; ++j) {
    ws_->augc_.leftCols<5>().noalias() = ws_->jn_ * P;
    ws_->augc_.col(5) = ws_->rn_;
    detail::householder_qr_inplace(ws_->augc_, ws_->qrc_);
    const Eigen::MatrixXd& q = ws_->augc_;
    const Eigen::Matrix<double, 5, 5> Rc = q.topLeftCorner<5, 5>().triangularView<Eigen::Upper>();
    const Eigen::Matrix<double, 5, 1> cc = q.block<5, 1>(0, 5);
    const Eigen::Matrix<double, 5, 1> y = -Rc.triangularView<Eigen::Upper>().solve(cc);
    if (!y.allFinite()) return;
    const Vec6 xc = xt + P * y;
    save_buffers();
    if (eval_at(xc, true) == OdStatus::converged && 0.5 * ws_->rn_.squaredNorm() < ct) {
      xt = xc;
      ct = 0.5 * ws_->rn_.squaredNorm();
      continue;
    }
    restore_buffers();
    return;
  }
}

// Extrapolation of an accepted step d = xt - x: where the residuals' own curvature along the weak
// direction is comparable with J^T J there (noisy one-station passes), Gauss-Newton converges only
// linearly (measured: each step 0.95 of the previous one on the Gao-Luo pass, seed 5). The cost
// along x + t d is fitted by the parabola through cost(x), its slope c^T R d and cost(xt); its
// minimizer t* (kExtrapMax when the fit is not convex) is tried when t* >= kExtrapMin, corrected
// to the valley floor, and kept only if lower than xt. Needs ws_->R_/ws_->c_ of x; buffers end at xt.
void OdSolver::extrapolate(const Vec6& x, double cost, Vec6& xt, double& ct, const Vec6& diag) {
  if (!settings_.extrapolate) return;
  const Vec6 d = xt - x;
  const double slope = ws_->c_.dot(ws_->R_ * d);
  if (!(slope < 0.0)) return;
  const double curv = ct - cost - slope;
  const double ts = curv > 0.0 ? std::min(-slope / (2.0 * curv), kExtrapMax) : kExtrapMax;
  if (!(ts >= kExtrapMin)) return;
  Vec6 xe = x + ts * d;
  if (eval_at(xe, true) == OdStatus::converged) {
    double ce = 0.5 * ws_->rn_.squaredNorm();
    if (ce >= ct) valley_correct(xe, ce, d, diag);
    if (ce < ct) {
      xt = xe;
      ct = ce;
      return;
    }
  }
  eval_at(xt, true);  // xt was evaluated before: restores its buffers
}

bool OdSolver::residual_small() const {
  return settings_.residual_tol > 0.0 && ws_->rn_.cwiseAbs().maxCoeff() <= settings_.residual_tol;
}

// The paper's undamped Newton-Raphson (eqs. 9-18), kept exactly: full steps, converged when the step
// just taken is small. On failure x becomes the lowest-cost iterate.
bool OdSolver::take_step(bool accepted, const Vec6& xt, int k, double lambda, Vec6& x) {
  if (!accepted) {
    res_.status = OdStatus::stalled;
    return false;
  }
  x = xt;
  res_.x0 = x;
  res_.iterations = k;
  record(k, lambda);
  return true;
}

bool OdSolver::solve_newton(Vec6& x) {
  res_.status = OdStatus::max_iterations;
  bool buffers_valid = true;
  int best = 0;
  for (int k = 1; k <= settings_.max_iterations; ++k) {
    if (residual_small()) {
      res_.status = OdStatus::converged;
      break;
    }
    factor();
    if (res_.rank < 6) {
      res_.status = OdStatus::singular;
      break;
    }
    const Vec6 dx = -(ws_->svd_.matrixV() *
                      (ws_->svd_.matrixU().transpose() * ws_->c_).cwiseQuotient(res_.singular_values));
    const Vec6 xt = x + dx;
    const OdStatus st = eval_at(xt, true);
    if (st != OdStatus::converged) {
      res_.status = st;  // the failed trial is not an iterate
      buffers_valid = false;
      break;
    }
    x = xt;
    res_.x0 = x;
    res_.iterations = k;
    record(k, 0.0);
    const double c_old = res_.history_cost(k - 1), c_new = res_.history_cost(k);
    if (c_new < res_.history_cost(best)) best = k;
    if (small_step(dx, x) || (c_new <= c_old && c_old - c_new <= settings_.cost_tol * c_old)) {
      res_.status = OdStatus::converged;
      break;
    }
  }
  // converged and singular describe the last iterate: report that one.
  if (res_.status == OdStatus::converged || res_.status == OdStatus::singular || best == res_.iterations)
    return buffers_valid;
  x = res_.history_x0.row(best).transpose();
  return false;
}

// Gauss-Newton with a backtracking line search along the second-order (geodesic) path
// x(t) = x + t v + t^2 a / 2, v = -R^-1 c the full step and a the geodesic acceleration (zero when
// settings.geodesic is off, x + h v cannot be evaluated or 2 |D a| > 0.75 |D v|): t is halved until
// the cost drops by a quarter of the model's decrease along the path, cost(x(t)) <= cost -
// 0.25 (t - t^2/2) |c|^2 (a trust-region-like gain test: a first Armijo test at 1e-4 accepted
// 800 km jumps from far starts), at most gn_max_halvings times, then status stalled. A trial that
// fails is first pulled back to the valley floor (valley_correct); an accepted step is extrapolated
// (extrapolate). The cost never rises.
bool OdSolver::solve_gauss_newton(Vec6& x) {
  res_.status = OdStatus::max_iterations;
  for (int k = 1; k <= settings_.max_iterations; ++k) {
    if (residual_small()) {
      res_.status = OdStatus::converged;
      return true;
    }
    factor();
    if (res_.rank < 6) {
      res_.status = OdStatus::singular;
      return true;
    }
    if (converged_here(x)) {
      res_.status = OdStatus::converged;
      return true;
    }
    const Vec6 v = gn_step();
    const double cost = 0.5 * ws_->rn_.squaredNorm();
    const double slope = ws_->c_.squaredNorm();  // -d cost / dt at t = 0
    Vec6 a = Vec6::Zero();
    if (settings_.geodesic) {
      ws_->rn0_ = ws_->rn_;
      ws_->jn0_ = ws_->jn_;
      Vec6 w;
      if (second_derivative(x, v, w)) a = solve_r(w);
    }
    Vec6 diag;
    for (int i = 0; i < 6; ++i) diag(i) = ws_->R_.col(i).norm();
    // As in LM: an acceleration as large as the step means the second-order path is not trustworthy.
    if (2.0 * diag.cwiseProduct(a).norm() > kGeoRatio * diag.cwiseProduct(v).norm()) a.setZero();
    double t = 1.0;
    bool accepted = false;
    Vec6 xt;
    // First t = 1, 1/2, 1/4 plain; only then the corrected trials from t = 1. The corrector keeps
    // the along-valley progress of the full linear step, which far from the minimum can jump into
    // another basin (measured from 1 km / 1 m/s: 3 of 300 random passes ended at a worse local
    // minimum or crawled; with the plain trials first 1).
    for (int h = 0; h < kGnPlainTrials; ++h, t *= 0.5) {
      xt = x + t * v + (0.5 * t * t) * a;
      if (eval_at(xt, true) != OdStatus::converged) continue;
      double ct = 0.5 * ws_->rn_.squaredNorm();
      if (ct <= cost - kGnAccept * (t - 0.5 * t * t) * slope) {
        accepted = true;
        extrapolate(x, cost, xt, ct, diag);
        break;
      }
    }
    t = 1.0;
    for (int h = 0; !accepted && h <= settings_.gn_max_halvings; ++h, t *= 0.5) {
      xt = x + t * v + (0.5 * t * t) * a;
      if (eval_at(xt, true) != OdStatus::converged) continue;
      double ct = 0.5 * ws_->rn_.squaredNorm();
      const double need = kGnAccept * (t - 0.5 * t * t) * slope;
      if (ct > cost - need) valley_correct(xt, ct, v, diag);
      if (ct <= cost - need) {
        accepted = true;
        extrapolate(x, cost, xt, ct, diag);
        break;
      }
    }
    if (!take_step(accepted, xt, k, 0.0, x)) return false;
  }
  return true;
}

// Levenberg-Marquardt: minimize |R dx + c|^2 + lambda |D dx|^2 by a fixed-size QR (no squaring of
// the condition number), Moré's column scaling D. Damping follows the gain ratio rho = actual /
// predicted decrease (x 0.1 when rho > 0.75, else Nielsen's max(1/3, 1 - (2 rho - 1)^3); after a
// rejection x lm_increase) and is switched off (pure Gauss-Newton) once small, so the end game
// converges quadratically. With settings.geodesic the step is v + a/2 with the geodesic acceleration
// a (same damped system), dropped when 2 |D a| > 0.75 |D v|. Only steps that lower the cost are taken.
bool OdSolver::solve_lm(Vec6& x) {
  res_.status = OdStatus::max_iterations;
  double lambda = settings_.lm_lambda0;
  Vec6 diag = Vec6::Zero();
  int stall = 0;
  for (int k = 1; k <= settings_.max_iterations; ++k) {
    if (residual_small()) {
      res_.status = OdStatus::converged;
      return true;
    }
    factor();
    if (converged_here(x)) {
      res_.status = OdStatus::converged;
      return true;
    }
    for (int i = 0; i < 6; ++i) diag(i) = std::max(diag(i), ws_->R_.col(i).norm());
    const double cost = 0.5 * ws_->rn_.squaredNorm();
    if (settings_.geodesic) {
      ws_->rn0_ = ws_->rn_;
      ws_->jn0_ = ws_->jn_;
    }
    bool accepted = false;
    Vec6 dx, xt;
    for (int rej = 0; rej < settings_.lm_max_rejections; ++rej) {
      dx = damped_solve(ws_->c_, lambda, diag);
      if (!dx.allFinite() || (lambda == 0.0 && res_.rank < 6)) {
        lambda = std::max(lambda * settings_.lm_increase, kLambdaFloor);
        continue;
      }
      const double pred = 0.5 * (ws_->c_.squaredNorm() - (ws_->R_ * dx + ws_->c_).squaredNorm());
      xt = x + dx;
      Vec6 w;
      if (settings_.geodesic && second_derivative(x, dx, w)) {
        const Vec6 a = damped_solve(w, lambda, diag);
        if (a.allFinite() && 2.0 * diag.cwiseProduct(a).norm() <= kGeoRatio * diag.cwiseProduct(dx).norm())
          xt += 0.5 * a;
      }
      const OdStatus st = eval_at(xt, true);
      double actual = st == OdStatus::converged ? cost - 0.5 * ws_->rn_.squaredNorm() : -1.0;
      if (st == OdStatus::converged && actual < pred) {
        // Worse than the model: on a curved valley, pull the trial back to the floor before judging it.
        double ct = cost - actual;
        valley_correct(xt, ct, dx, diag);
        actual = cost - ct;
      }
      if (st == OdStatus::converged && actual > 0.0) {
        accepted = true;
        const double rho = pred > 0.0 ? actual / pred : 0.0;
        // Not x lm_decrease right after a rejection: that returns to the rejected damping and the
        // next iteration repeats the rejection (measured: a 200-iteration ping-pong 1e-11 <-> 1e-10
        // on one guess of the six-point map).
        if (rho > 0.75 && rej == 0) {
          lambda *= settings_.lm_decrease;
        } else {
          const double q = 2.0 * rho - 1.0;
          lambda *= std::max(1.0 / 3.0, 1.0 - q * q * q);
        }
        if (lambda < kLambdaFloor) lambda = 0.0;
        double ct = cost - actual;
        extrapolate(x, cost, xt, ct, diag);
        break;
      }
      lambda = std::max(lambda * settings_.lm_increase, kLambdaFloor);
    }
    if (!take_step(accepted, xt, k, lambda, x)) return false;
    // Slow creep along a curved, nearly flat valley: try undamped Newton steps from here.
    const double new_cost = 0.5 * ws_->rn_.squaredNorm();
    stall = (cost - new_cost < settings_.lm_stall_tol * cost) ? stall + 1 : 0;
    if (stall >= 3) {
      stall = -10;  // do not retry the polish for a while if it fails
      if (!polish(x)) {
        if (eval_at(x, true) != OdStatus::converged) return false;  // cannot happen: x was evaluated
      }
    }
  }
  return true;
}

// Undamped Gauss-Newton steps from the LM point x (whose buffers are current), kept up to the
// lowest-cost point of the walk if that is lower than x: LM's monotone decrease rejects the first
// Newton step in the curved valleys of the six-point problem although Newton then converges
// quadratically. Returns true when a point was kept (x and the buffers are there); otherwise the
// history rows of the walk are cleared and the buffers are stale.
bool OdSolver::polish(Vec6& x) {
  const int max_it = settings_.max_iterations;
  if (settings_.lm_polish_iterations <= 0 || res_.iterations >= max_it) return false;
  const int k_lm = res_.iterations;
  double best_cost = 0.5 * ws_->rn_.squaredNorm();
  int best = k_lm;
  Vec6 xp = x;
  int k = k_lm;
  bool fresh = true;  // the buffers belong to xp
  for (int j = 0; j < settings_.lm_polish_iterations && k < max_it; ++j) {
    factor();
    if (res_.rank < 6) break;
    const Vec6 dx = gn_step();
    if (eval_at(xp + dx, true) != OdStatus::converged) {
      fresh = false;
      break;
    }
    xp += dx;
    ++k;
    res_.x0 = xp;
    record(k, 0.0);
    if (res_.history_cost(k) < best_cost) {
      best_cost = res_.history_cost(k);
      best = k;
    }
    if (small_step(dx, xp)) break;
  }
  for (int i = best + 1; i <= k; ++i) {
    res_.history_x0.row(i).setConstant(kNaN);
    res_.history_residuals.row(i).setConstant(kNaN);
    res_.history_range_residuals.row(i).setConstant(kNaN);
    res_.history_range_rate_residuals.row(i).setConstant(kNaN);
    res_.history_cost(i) = kNaN;
    res_.history_lambda(i) = kNaN;
  }
  if (best == k_lm) {
    res_.x0 = x;
    return false;
  }
  x = res_.history_x0.row(best).transpose();
  res_.x0 = x;
  res_.iterations = best;
  if (best != k || !fresh) return eval_at(x, true) == OdStatus::converged;
  return true;
}

OdStatus OdSolver::evaluate(const Vec6& x0, Eigen::VectorXd& residuals, Eigen::MatrixXd* jac) {
  const OdStatus st = eval_at(x0, jac != nullptr);
  residuals = ws_->r_;
  if (jac) *jac = sigma_.asDiagonal() * ws_->jn_;
  return st;
}

RootSearchResult root_search(OdSolver& solver, const std::vector<Vec6>& guesses,
                             const RootSearchSettings& s) {
  core::require_positive(s.distinct_position_km, "settings.distinct_position_km");
  core::require_positive(s.distinct_velocity_kms, "settings.distinct_velocity_kms");
  core::require_nonnegative(s.distinct_sigma, "settings.distinct_sigma");
  RootSearchResult out;
  out.guess_root.assign(guesses.size(), -1);
  out.guess_status.assign(guesses.size(), OdStatus::max_iterations);
  out.guess_iterations.assign(guesses.size(), 0);
  for (std::size_t g = 0; g < guesses.size(); ++g) {
    const OdResult& r = solver.solve(guesses[g]);
    out.guess_status[g] = r.status;
    out.guess_iterations[g] = r.iterations;
    // Converged solutions, and stopped ones that fit (a creep along a flat valley).
    const bool stopped = r.status == OdStatus::max_iterations || r.status == OdStatus::stalled;
    const bool usable = r.status == OdStatus::converged || (stopped && r.fits);
    if (!usable) continue;
    int found = -1;
    for (std::size_t k = 0; k < out.roots.size(); ++k) {
      const Vec6 d = out.roots[k].x0 - r.x0;
      bool same = d.head<3>().norm() < s.distinct_position_km && d.tail<3>().norm() < s.distinct_velocity_kms;
      if (!same && out.roots[k].covariance.allFinite()) {
        const Eigen::LDLT<Mat6> ldlt(out.roots[k].covariance);
        const double m2 = d.dot(ldlt.solve(d));
        same = std::isfinite(m2) && m2 >= 0.0 && std::sqrt(m2) <= s.distinct_sigma;
      }
      if (same) {
        found = static_cast<int>(k);
        break;
      }
    }
    if (found < 0) {
      Root root;
      detail::take_solution(r, root);
      root.first_guess = static_cast<int>(g);
      out.roots.push_back(root);
      found = static_cast<int>(out.roots.size()) - 1;
    } else if (r.max_abs_normalized < out.roots[static_cast<std::size_t>(found)].max_abs_normalized) {
      detail::take_solution(r, out.roots[static_cast<std::size_t>(found)]);
    }
    ++out.roots[static_cast<std::size_t>(found)].hits;
    out.guess_root[g] = found;
  }
  // Order: fitting roots first, then by misfit; remap the per-guess indices.
  std::vector<int> order(out.roots.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const Root &ra = out.roots[static_cast<std::size_t>(a)], &rb = out.roots[static_cast<std::size_t>(b)];
    if (ra.fits != rb.fits) return ra.fits;
    return ra.max_abs_normalized < rb.max_abs_normalized;
  });
  std::vector<int> inv(order.size());
  std::vector<Root> sorted;
  for (std::size_t i = 0; i < order.size(); ++i) {
    inv[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
    sorted.push_back(out.roots[static_cast<std::size_t>(order[i])]);
  }
  out.roots = std::move(sorted);
  for (auto& gr : out.guess_root)
    if (gr >= 0) gr = inv[static_cast<std::size_t>(gr)];
  for (const auto& r : out.roots) out.fitting_roots += r.fits ? 1 : 0;
  out.ambiguous = out.fitting_roots >= 2;
  return out;
}

std::vector<Vec6> box_guesses(const Vec6& center, const Vec6& half_width, int n, std::uint64_t seed) {
  core::require_finite(center, "center");
  core::require(half_width.allFinite() && (half_width.array() >= 0.0).all(), "half_width",
                "must be finite and >= 0");
  core::require(n >= 1, "n", "must be >= 1");
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec6> out(static_cast<std::size_t>(n));
  for (auto& g : out)
    for (int i = 0; i < 6; ++i) g(i) = center(i) + half_width(i) * u(gen);
  return out;
}

}  // namespace satgnc::od
