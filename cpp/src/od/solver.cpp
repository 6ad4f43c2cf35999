#include "satgnc/od/solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "satgnc/core/validate.hpp"

namespace satgnc::od {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kLambdaFloor = 1e-12;  // below: pure Gauss-Newton steps
}  // namespace

const char* od_status_message(OdStatus s) {
  switch (s) {
    case OdStatus::converged:
      return "converged";
    case OdStatus::max_iterations:
      return "maximum number of iterations reached";
    case OdStatus::singular:
      return "Jacobian is rank deficient (see rank): the data do not determine the state";
    case OdStatus::diverged:
      return "diverged: an iterate went below the minimum radius or became unbound (energy >= 0)";
    case OdStatus::propagation_failed:
      return "propagation failed";
    case OdStatus::degenerate_geometry:
      return "zero range: the satellite is at the station, range-rate is undefined";
  }
  return "unknown status";
}

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
  require(lm_polish_iterations >= 0, "settings.lm_polish_iterations", "must be >= 0");
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
  states_.assign(times_.size(), Vec6::Zero());
  stms_.assign(times_.size(), Mat6::Identity());
  r_.setZero(m);
  rn_.setZero(m);
  rr_.setZero(m);
  rrr_.setZero(m);
  jn_.setZero(m, 6);
  aug_.setZero(m, 7);
  qr_ = Eigen::HouseholderQR<Eigen::MatrixXd>(m, 7);
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

OdStatus OdSolver::eval_at(const Vec6& x0, bool with_jac) {
  ++res_.evaluations;
  if (!physical(x0)) return OdStatus::diverged;
  const int nt = static_cast<int>(times_.size());
  if (!prop_->propagate(x0, times_.data(), nt, states_.data(), stms_.data()))
    return OdStatus::propagation_failed;
  for (int i = 0; i < nt; ++i)
    if (!physical(states_[static_cast<std::size_t>(i)])) return OdStatus::diverged;
  Row6 g;
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const Row& row = rows_[k];
    const Eigen::Index ki = static_cast<Eigen::Index>(k);
    const Vec6& x = states_[static_cast<std::size_t>(row.time_index)];
    const Vec6 R = stations_[static_cast<std::size_t>(row.station)].state(
        times_[static_cast<std::size_t>(row.time_index)]);
    const Vec3 d = x.head<3>() - R.head<3>();
    const Vec3 dv = x.tail<3>() - R.tail<3>();
    const double rho = d.norm();
    if (!(rho >= settings_.min_range)) return OdStatus::degenerate_geometry;
    const double rhodot = d.dot(dv) / rho;
    rr_(ki) = std::isnan(row.range) ? kNaN : rho - row.range;
    rrr_(ki) = std::isnan(row.range_rate) ? kNaN : rhodot - row.range_rate;
    switch (row.kind) {
      case RowKind::obs_range:
        r_(ki) = rho - row.range;
        g.head<3>() = d.transpose() / rho;
        g.tail<3>().setZero();
        break;
      case RowKind::obs_range_rate:
        r_(ki) = rhodot - row.range_rate;
        g.head<3>() = (dv - rhodot * d / rho).transpose() / rho;
        g.tail<3>() = d.transpose() / rho;
        break;
      case RowKind::cond_range:
        r_(ki) = d.squaredNorm() - row.range * row.range;
        g.head<3>() = 2.0 * d.transpose();
        g.tail<3>().setZero();
        break;
      case RowKind::cond_doppler:
        r_(ki) = d.dot(dv) - row.range * row.range_rate;
        g.head<3>() = dv.transpose();
        g.tail<3>() = d.transpose();
        break;
    }
    rn_(ki) = r_(ki) / sigma_(ki);
    if (with_jac) jn_.row(ki).noalias() = (g * stms_[static_cast<std::size_t>(row.time_index)]) / sigma_(ki);
  }
  if (!rn_.allFinite()) return OdStatus::diverged;
  return OdStatus::converged;
}

void OdSolver::factor() {
  aug_.leftCols<6>() = jn_;
  aug_.col(6) = rn_;
  qr_.compute(aug_);
  const auto& qr = qr_.matrixQR();
  R_ = qr.topLeftCorner<6, 6>().triangularView<Eigen::Upper>();
  c_ = qr.block<6, 1>(0, 6);
  svd_.compute(R_, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec6 s = svd_.singularValues();
  res_.singular_values = s;
  int rank = 0;
  for (int i = 0; i < 6; ++i)
    if (s(i) > settings_.rank_tol * s(0)) ++rank;
  res_.rank = rank;
  res_.condition_number = s(5) > 0.0 ? s(0) / s(5) : kInf;
}

void OdSolver::record(int k, double lambda) {
  res_.history_x0.row(k) = res_.x0.transpose();
  res_.history_residuals.row(k) = r_.transpose();
  res_.history_range_residuals.row(k) = rr_.transpose();
  res_.history_range_rate_residuals.row(k) = rrr_.transpose();
  res_.history_cost(k) = 0.5 * rn_.squaredNorm();
  res_.history_lambda(k) = lambda;
}

bool OdSolver::small_step(const Vec6& dx, const Vec6& x) const {
  if ((R_.triangularView<Eigen::Upper>() * dx).norm() <= settings_.step_sigma_tol) return true;
  for (int i = 0; i < 6; ++i)
    if (std::abs(dx(i)) > settings_.step_tol * (1.0 + std::abs(x(i)))) return false;
  return true;
}

void OdSolver::finish(const Vec6& x, bool buffers_valid) {
  res_.x0 = x;
  if (!buffers_valid) {
    const OdStatus st = eval_at(x, true);
    if (st != OdStatus::converged) {
      res_.fits = false;
      return;
    }
  }
  factor();
  res_.residuals = r_;
  res_.normalized = rn_;
  res_.range_residuals = rr_;
  res_.range_rate_residuals = rrr_;
  res_.cost = 0.5 * rn_.squaredNorm();
  res_.max_abs_normalized = rn_.cwiseAbs().maxCoeff();
  res_.fits = std::sqrt(rn_.squaredNorm() / static_cast<double>(rn_.size())) <= settings_.fit_sigma;
  const Vec6 s = res_.singular_values;
  if (res_.rank == 6) {
    const Mat6& V = svd_.matrixV();
    res_.covariance.noalias() = V * s.cwiseInverse().cwiseAbs2().asDiagonal() * V.transpose();
    const Vec6 sd = res_.covariance.diagonal().cwiseSqrt();
    res_.correlation = res_.covariance.cwiseQuotient(sd * sd.transpose());
  } else {
    res_.covariance.setConstant(kInf);
    res_.correlation.setConstant(kNaN);
  }
}

const OdResult& OdSolver::solve(const Vec6& guess) {
  const int max_it = settings_.max_iterations;
  res_.iterations = 0;
  res_.evaluations = 0;
  res_.rank = 0;
  res_.fits = false;
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
  rr_.setConstant(kNaN);
  rrr_.setConstant(kNaN);
  r_.setConstant(kNaN);
  rn_.setConstant(kNaN);
  OdStatus st = eval_at(guess, true);
  if (st != OdStatus::converged) {
    res_.status = st;
    res_.residuals = r_;
    res_.normalized = rn_;
    res_.range_residuals = rr_;
    res_.range_rate_residuals = rrr_;
    return res_;
  }
  record(0, 0.0);
  Vec6 x = guess;
  const bool lm = settings_.method == OdMethod::levenberg_marquardt;
  double lambda = settings_.lm_lambda0;
  Vec6 diag = Vec6::Zero();
  bool buffers_valid = true;  // r_/jn_ belong to x
  bool gn_converged = false;
  int stall = 0;
  res_.status = OdStatus::max_iterations;
  for (int k = 1; k <= max_it; ++k) {
    if (settings_.residual_tol > 0.0 && rn_.cwiseAbs().maxCoeff() <= settings_.residual_tol) {
      res_.status = OdStatus::converged;
      break;
    }
    factor();
    Vec6 dx;
    if (!lm) {
      if (res_.rank < 6) {
        res_.status = OdStatus::singular;
        break;
      }
      dx.noalias() =
          -(svd_.matrixV() * (svd_.matrixU().transpose() * c_).cwiseQuotient(res_.singular_values));
      x += dx;
      res_.x0 = x;
      st = eval_at(x, true);
      if (st != OdStatus::converged) {
        res_.status = st;
        res_.iterations = k;
        buffers_valid = false;
        break;
      }
      res_.iterations = k;
      record(k, 0.0);
      const double c_old = res_.history_cost(k - 1), c_new = res_.history_cost(k);
      if (small_step(dx, x) || (c_new <= c_old && c_old - c_new <= settings_.cost_tol * c_old)) {
        res_.status = OdStatus::converged;
        break;
      }
      continue;
    }
    // Levenberg-Marquardt: minimize |R dx + c|^2 + lambda |D dx|^2 by a fixed-size QR (no squaring of
    // the condition number). Damping follows the gain ratio rho = actual / predicted decrease and is
    // switched off (pure Gauss-Newton) once small, so the end game converges quadratically.
    for (int i = 0; i < 6; ++i) diag(i) = std::max(diag(i), R_.col(i).norm());
    const double cost = 0.5 * rn_.squaredNorm();
    bool accepted = false, tiny = false;
    for (int rej = 0; rej < settings_.lm_max_rejections; ++rej) {
      Eigen::Matrix<double, 12, 7> A = Eigen::Matrix<double, 12, 7>::Zero();
      A.topLeftCorner<6, 6>() = R_;
      A.block<6, 1>(0, 6) = c_;
      A.bottomLeftCorner<6, 6>() = (std::sqrt(lambda) * diag).asDiagonal();
      Eigen::HouseholderQR<Eigen::Matrix<double, 12, 7>> q(A);
      const Mat6 Rl = q.matrixQR().topLeftCorner<6, 6>().triangularView<Eigen::Upper>();
      const Vec6 cl = q.matrixQR().block<6, 1>(0, 6);
      dx = -Rl.triangularView<Eigen::Upper>().solve(cl);
      if (!dx.allFinite() || (lambda == 0.0 && res_.rank < 6)) {
        lambda = std::max(lambda * settings_.lm_increase, kLambdaFloor);
        continue;
      }
      const double pred = 0.5 * (c_.squaredNorm() - (R_ * dx + c_).squaredNorm());
      const Vec6 xt = x + dx;
      st = eval_at(xt, true);
      buffers_valid = false;
      const double actual = st == OdStatus::converged ? cost - 0.5 * rn_.squaredNorm() : -1.0;
      if (st == OdStatus::converged && actual > 0.0) {
        x = xt;
        buffers_valid = true;
        accepted = true;
        const double rho = pred > 0.0 ? actual / pred : 0.0;
        if (rho > 0.75) {
          lambda *= settings_.lm_decrease;
          if (lambda < kLambdaFloor) lambda = 0.0;
        } else if (rho < 0.25) {
          lambda = std::max(2.0 * lambda, kLambdaFloor);
        }
        break;
      }
      if (small_step(dx, x)) {
        tiny = true;
        break;
      }
      lambda = std::max(lambda * settings_.lm_increase, kLambdaFloor);
    }
    if (!accepted) {
      // No decrease possible: a stationary point (converged, maybe not fitting) or a stall.
      res_.status = tiny ? OdStatus::converged : OdStatus::max_iterations;
      break;
    }
    res_.x0 = x;
    res_.iterations = k;
    record(k, lambda);
    const double new_cost = 0.5 * rn_.squaredNorm();
    if ((small_step(dx, x) && lambda == 0.0) || new_cost == 0.0 ||
        cost - new_cost <= settings_.cost_tol * cost) {
      res_.status = OdStatus::converged;
      gn_converged = true;
      break;
    }
    // Slow creep along a curved, nearly flat valley: stop and let the Newton polish finish.
    stall = (cost - 0.5 * rn_.squaredNorm() < settings_.lm_stall_tol * cost) ? stall + 1 : 0;
    if (stall >= 3) {
      stall = -10;  // do not retry the polish for a while if it fails
      if (polish(x, buffers_valid)) {
        gn_converged = true;
        break;
      }
      if (!buffers_valid) {
        if (eval_at(x, true) != OdStatus::converged) break;
        buffers_valid = true;
      }
    }
  }
  if (lm && !gn_converged && res_.status != OdStatus::diverged) polish(x, buffers_valid);
  finish(x, buffers_valid);
  if (res_.status == OdStatus::converged && res_.rank < 6 && !lm) res_.status = OdStatus::singular;
  return res_;
}

bool OdSolver::polish(Vec6& x, bool& buffers_valid) {
  // Undamped Newton (Gauss-Newton) steps from the LM point, kept only if they converge to a point
  // with a cost no larger: LM's monotone decrease rejects the first Newton step in the curved valleys
  // of the six-point problem although Newton then converges quadratically.
  const int max_it = settings_.max_iterations;
  if (settings_.lm_polish_iterations <= 0 || res_.iterations >= max_it) return false;
  if (!buffers_valid) {
    if (eval_at(x, true) != OdStatus::converged) return false;
    buffers_valid = true;
  }
  const int k_lm = res_.iterations;
  const double cost_lm = 0.5 * rn_.squaredNorm();
  Vec6 xp = x;
  int k = k_lm;
  bool ok = false;
  for (int j = 0; j < settings_.lm_polish_iterations && k < max_it; ++j) {
    factor();
    if (res_.rank < 6) break;
    const Vec6 dx = -(svd_.matrixV() * (svd_.matrixU().transpose() * c_).cwiseQuotient(res_.singular_values));
    xp += dx;
    ++k;
    if (eval_at(xp, true) != OdStatus::converged) break;
    res_.x0 = xp;
    record(k, 0.0);
    if (small_step(dx, xp)) {
      ok = 0.5 * rn_.squaredNorm() <= cost_lm;
      break;
    }
  }
  if (ok) {
    x = xp;
    res_.iterations = k;
    res_.status = OdStatus::converged;
    return true;
  }
  for (int i = k_lm + 1; i <= k; ++i) {
    res_.history_x0.row(i).setConstant(kNaN);
    res_.history_residuals.row(i).setConstant(kNaN);
    res_.history_range_residuals.row(i).setConstant(kNaN);
    res_.history_range_rate_residuals.row(i).setConstant(kNaN);
    res_.history_cost(i) = kNaN;
    res_.history_lambda(i) = kNaN;
  }
  res_.x0 = x;
  buffers_valid = false;
  return false;
}

OdStatus OdSolver::evaluate(const Vec6& x0, Eigen::VectorXd& residuals, Eigen::MatrixXd* jac) {
  const OdStatus st = eval_at(x0, jac != nullptr);
  residuals = r_;
  if (jac) *jac = sigma_.asDiagonal() * jn_;
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
    // Converged solutions, and stalled ones that fit (LM creeping along a flat valley).
    const bool usable = r.status == OdStatus::converged || (r.status == OdStatus::max_iterations && r.fits);
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
      root.x0 = r.x0;
      root.covariance = r.covariance;
      root.residuals = r.residuals;
      root.normalized = r.normalized;
      root.max_abs_normalized = r.max_abs_normalized;
      root.condition_number = r.condition_number;
      root.fits = r.fits;
      root.converged = r.status == OdStatus::converged;
      root.first_guess = static_cast<int>(g);
      out.roots.push_back(root);
      found = static_cast<int>(out.roots.size()) - 1;
    } else if (r.max_abs_normalized < out.roots[static_cast<std::size_t>(found)].max_abs_normalized) {
      Root& root = out.roots[static_cast<std::size_t>(found)];
      root.x0 = r.x0;
      root.covariance = r.covariance;
      root.residuals = r.residuals;
      root.normalized = r.normalized;
      root.max_abs_normalized = r.max_abs_normalized;
      root.condition_number = r.condition_number;
      root.fits = r.fits;
      root.converged = r.status == OdStatus::converged;
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
