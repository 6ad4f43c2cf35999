// Orbit EKF (Joseph update, chi-square gate, consider states) and RTS smoother
// (see satgnc/filter/orbit_filter.hpp).
#include "satgnc/filter/orbit_filter.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::filter {

using Eigen::MatrixXd;
using Eigen::VectorXd;

const char* status_name(OrbitStepStatus s) noexcept {
  switch (s) {
    case OrbitStepStatus::updated:
      return "updated";
    case OrbitStepStatus::rejected:
      return "rejected";
    case OrbitStepStatus::propagation_failed:
      return "propagation_failed";
    case OrbitStepStatus::measurement_failed:
      return "measurement_failed";
    case OrbitStepStatus::not_positive_definite:
      return "not_positive_definite";
    case OrbitStepStatus::not_run:
      return "not_run";
  }
  return "unknown";
}

double chi2_quantile(int dof, double p) {
  core::require(dof == 1 || dof == 2, "dof", "must be 1 or 2, got " + std::to_string(dof));
  core::require(std::isfinite(p) && p > 0.0 && p < 1.0, "gate_probability",
                "must be in (0, 1), got " + std::to_string(p));
  if (dof == 2) return -2.0 * std::log1p(-p);
  // dof 1: P(chi2 <= x) = erf(sqrt(x / 2)); bisection on sqrt(x) in [0, 40].
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erf(mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  const double z = 0.5 * (lo + hi);
  return z * z;
}

void OrbitFilterSettings::validate(int n) const {
  core::require(std::isfinite(gate_probability) && gate_probability > 0.0 && gate_probability < 1.0,
                "gate_probability", "must be in (0, 1), got " + std::to_string(gate_probability));
  core::require(warmup >= 0, "warmup", "must be >= 0, got " + std::to_string(warmup));
  core::require(method == OrbitFilterMethod::ekf || method == OrbitFilterMethod::ukf, "method",
                "must be ekf or ukf");
  core::require_positive(ukf_alpha, "ukf_alpha");
  core::require_finite(ukf_beta, "ukf_beta");
  core::require(std::isfinite(ukf_kappa) && n + ukf_kappa > 0.0, "ukf_kappa",
                "must be finite with n + kappa > 0, got " + std::to_string(ukf_kappa));
  std::vector<int> seen(static_cast<std::size_t>(n), 0);
  for (std::size_t i = 0; i < consider.size(); ++i) {
    const int c = consider[i];
    const std::string name = "consider[" + std::to_string(i) + "]";
    core::require(c >= 6 && c < n, name,
                  "must be a parameter index in [6, " + std::to_string(n) + "), got " + std::to_string(c));
    core::require(seen[static_cast<std::size_t>(c)] == 0, name, "index " + std::to_string(c) + " repeated");
    seen[static_cast<std::size_t>(c)] = 1;
  }
}

namespace detail {
struct OrbitFilterWorkspace {
  VectorXd x, xp;
  MatrixXd p, phi, q, tmp, ikh;
  Eigen::Matrix<double, Eigen::Dynamic, 2> pht, k, kr;
  MatrixXd h;  // 2 x n
  Eigen::LLT<MatrixXd> llt;
  VectorXd consider_mask;  // 1 for estimated, 0 for consider
  // UKF
  MatrixXd sig, dx, phi2, q2;                      // n x (2n+1), n x (2n+1), n x n, n x n
  Eigen::Matrix<double, 2, Eigen::Dynamic> z, dz;  // 2 x (2n+1)
  VectorXd wm, wc;
  explicit OrbitFilterWorkspace(int n)
      : x(n),
        xp(n),
        p(n, n),
        phi(n, n),
        q(n, n),
        tmp(n, n),
        ikh(n, n),
        pht(n, 2),
        k(n, 2),
        kr(n, 2),
        h(2, n),
        llt(n),
        consider_mask(VectorXd::Ones(n)),
        sig(n, 2 * n + 1),
        dx(n, 2 * n + 1),
        phi2(n, n),
        q2(n, n),
        z(2, 2 * n + 1),
        dz(2, 2 * n + 1),
        wm(2 * n + 1),
        wc(2 * n + 1) {}
};
}  // namespace detail

OrbitFilter::OrbitFilter(OrbitProcessModel process, OrbitMeasurementFunction measurement,
                         const OrbitFilterSettings& settings)
    : process_(std::move(process)), measurement_(std::move(measurement)), settings_(settings) {
  n_ = process_.dimension();
  core::require(measurement_.dimension() == n_, "measurement",
                "state dimension " + std::to_string(measurement_.dimension()) +
                    " differs from the process model's " + std::to_string(n_));
  settings_.validate(n_);
  gate1_ = chi2_quantile(1, settings_.gate_probability);
  gate2_ = chi2_quantile(2, settings_.gate_probability);
  ws_ = std::make_unique<detail::OrbitFilterWorkspace>(n_);
  for (int c : settings_.consider) ws_->consider_mask[c] = 0.0;
  const double a = settings_.ukf_alpha, nd = n_;
  lambda_ = a * a * (nd + settings_.ukf_kappa) - nd;
  ws_->wm.setConstant(0.5 / (nd + lambda_));
  ws_->wc = ws_->wm;
  ws_->wm[0] = lambda_ / (nd + lambda_);
  ws_->wc[0] = ws_->wm[0] + 1.0 - a * a + settings_.ukf_beta;
}

// Sigma points of (w.x, w.p) into w.sig; false when sqrt((n + lambda) P) fails (not positive definite).
bool OrbitFilter::draw_sigma_points() noexcept {
  auto& w = *ws_;
  const int n = n_;
  w.tmp = (n + lambda_) * w.p;
  w.llt.compute(w.tmp);
  if (w.llt.info() != Eigen::Success) return false;
  w.sig.col(0) = w.x;
  for (int i = 0; i < n; ++i) {
    w.sig.col(1 + i) = w.x;
    w.sig.col(1 + n + i) = w.x;
    for (int r = i; r < n; ++r) {
      const double l = w.llt.matrixLLT()(r, i);
      w.sig(r, 1 + i) += l;
      w.sig(r, 1 + n + i) -= l;
    }
  }
  return true;
}

OrbitFilter::~OrbitFilter() = default;
OrbitFilter::OrbitFilter(OrbitFilter&&) noexcept = default;
OrbitFilter& OrbitFilter::operator=(OrbitFilter&&) noexcept = default;

namespace {
template <class M>
void put(std::vector<double>& dst, std::size_t k, const M& m) {
  // Row-major copy of m into slot k of a time-major array.
  const std::size_t sz = static_cast<std::size_t>(m.size());
  double* d = dst.data() + k * sz;
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) *d++ = m(i, j);
}
}  // namespace

OrbitFilterResult OrbitFilter::run(double t0, const VectorXd& x0, const MatrixXd& p0,
                                   const std::vector<OrbitMeasurement>& meas) {
  const int n = n_;
  core::require_finite(t0, "t0");
  core::require(x0.size() == n, "x0",
                "must have " + std::to_string(n) + " entries, got " + std::to_string(x0.size()));
  core::require_finite(x0, "x0");
  core::require(p0.rows() == n && p0.cols() == n, "P0",
                "must be " + std::to_string(n) + " x " + std::to_string(n));
  core::require_finite(p0, "P0");
  core::require((p0 - p0.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * p0.cwiseAbs().maxCoeff(), "P0",
                "must be symmetric");
  core::require(Eigen::LLT<MatrixXd>(p0).info() == Eigen::Success, "P0",
                "must be positive definite (Cholesky failed)");
  double prev = t0;
  const int n_stations = static_cast<int>(measurement_.settings().stations.size());
  for (std::size_t i = 0; i < meas.size(); ++i) {
    const auto& m = meas[i];
    // Messages are built only on failure: validation allocates nothing per good measurement.
    const bool t_ok = std::isfinite(m.t) && m.t >= prev;
    const bool s_ok = m.station >= 0 && m.station < n_stations;
    const int sz = measurement_.size(m);
    const bool v_ok = sz > 0 && m.value.head(sz).allFinite();
    if (t_ok && s_ok && v_ok) {
      prev = m.t;
      continue;
    }
    const std::string name = "measurements[" + std::to_string(i) + "]";
    core::require(t_ok, name + ".t",
                  "tags must be finite, non-decreasing and >= t0 (sort the measurements), got " +
                      std::to_string(m.t) + " after " + std::to_string(prev));
    core::require(s_ok, name + ".station", "unknown station index " + std::to_string(m.station));
    core::require(sz > 0, name + ".observable",
                  "observable index " + std::to_string(m.observable) + " was not set up (the filter knows " +
                      std::to_string(measurement_.settings().observables.size()) + ")");
    core::require_finite(m.value.head(sz), name + ".value");
  }
  const std::size_t K = meas.size();
  const std::size_t nn = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  OrbitFilterResult r;
  r.n = n;
  r.t.resize(K);
  r.station.resize(K);
  r.observable.resize(K);
  r.size.resize(K);
  r.status.assign(K, OrbitStepStatus::not_run);
  r.state.assign(K * static_cast<std::size_t>(n), nan);
  r.covariance.assign(K * nn, nan);
  r.prefit.assign(2 * K, nan);
  r.postfit.assign(2 * K, nan);
  r.sigma.assign(2 * K, nan);
  r.nis.assign(K, nan);
  r.normalized_residual.assign(K, nan);
  r.gate.assign(K, 0.0);
  r.predicted_state.assign(K * static_cast<std::size_t>(n), nan);
  r.predicted_covariance.assign(K * nn, nan);
  r.transition.assign(K * nn, nan);
  r.t0 = t0;
  r.consider = settings_.consider;
  r.initial_state = x0;
  r.initial_covariance = p0;
  for (std::size_t k = 0; k < K; ++k) {
    r.t[k] = meas[k].t;
    r.station[k] = meas[k].station;
    r.observable[k] = meas[k].observable;
    r.size[k] = measurement_.size(meas[k]);
  }
  const auto start = std::chrono::steady_clock::now();
  {
    SATGNC_NO_MALLOC_SCOPE;
    auto& w = *ws_;
    w.x = x0;
    w.p = p0;
    const bool ukf = settings_.method == OrbitFilterMethod::ukf;
    const int ns = 2 * n + 1;
    double t = t0;
    for (std::size_t k = 0; k < K; ++k) {
      const OrbitMeasurement& m = meas[k];
      // --- predict
      if (!ukf) {
        const OrbitProcessInfo pi = process_.propagate(t, m.t, w.x, w.phi, w.q);
        r.propagation_steps += pi.steps;
        if (pi.status != propagation::Dop853Status::success) {
          r.status[k] = OrbitStepStatus::propagation_failed;
          break;
        }
        w.tmp.noalias() = w.phi * w.p;
        w.p.noalias() = w.tmp * w.phi.transpose();
        w.p += w.q;
      } else {
        if (!draw_sigma_points()) {
          r.status[k] = OrbitStepStatus::not_positive_definite;
          break;
        }
        bool ok = true;
        for (int j = 0; j < ns && ok; ++j) {
          auto col = w.sig.col(j);
          const OrbitProcessInfo pi = j == 0 ? process_.propagate(t, m.t, col, w.phi, w.q)
                                             : process_.propagate(t, m.t, col, w.phi2, w.q2);
          r.propagation_steps += pi.steps;
          ok = pi.status == propagation::Dop853Status::success;
        }
        if (!ok) {
          r.status[k] = OrbitStepStatus::propagation_failed;
          break;
        }
        w.x.noalias() = w.sig * w.wm;
        w.dx = w.sig.colwise() - w.x;
        w.p.noalias() = w.dx * w.wc.asDiagonal() * w.dx.transpose();
        w.p += w.q;
      }
      t = m.t;
      w.tmp = w.p.transpose();
      w.p = 0.5 * (w.p + w.tmp);
      put(r.predicted_state, k, w.x.transpose());
      put(r.predicted_covariance, k, w.p);
      put(r.transition, k, w.phi);
      r.steps_run = static_cast<int>(k) + 1;
      // --- measurement: predicted value zhat, innovation covariance s, gain pieces (pht = P H^T or Pxz)
      const int sz = r.size[k];
      Eigen::Vector2d zhat, sig;
      Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
      OrbitStepStatus st = OrbitStepStatus::updated;
      core::ObservationStatus os = core::ObservationStatus::success;
      if (!ukf) {
        w.h.setZero();
        os = measurement_.evaluate(m, w.x, zhat, w.h, sig);
        if (os == core::ObservationStatus::success) {
          w.pht.noalias() = w.p * w.h.transpose();
          s.noalias() = w.h * w.pht;
        }
      } else {
        if (!draw_sigma_points()) {
          r.status[k] = OrbitStepStatus::not_positive_definite;
          break;
        }
        for (int j = 0; j < ns && os == core::ObservationStatus::success; ++j) {
          Eigen::Vector2d zj, sj;
          os = measurement_.evaluate(m, w.sig.col(j), zj, w.h, sj);
          w.z.col(j) = zj;
          if (j == 0) sig = sj;
        }
        if (os == core::ObservationStatus::success) {
          // Differences from the central point (azimuth / right ascension wrapped), then the mean.
          for (int j = 0; j < ns; ++j) {
            OrbitMeasurement mj = m;
            mj.value = w.z.col(j);
            w.dz.col(j) = measurement_.residual(mj, w.z.col(0));
          }
          const Eigen::Vector2d mean_dz = w.dz * w.wm;
          zhat = w.z.col(0) + mean_dz;
          w.dz.colwise() -= mean_dz;
          w.dx = w.sig.colwise() - w.x;
          w.pht.noalias() = w.dx * w.wc.asDiagonal() * w.dz.transpose();
          s.noalias() = w.dz * w.wc.asDiagonal() * w.dz.transpose();
          if (sz == 1) {
            w.pht.col(1).setZero();
            s(0, 1) = s(1, 0) = s(1, 1) = 0.0;
          }
        }
      }
      if (os != core::ObservationStatus::success) {
        st = OrbitStepStatus::measurement_failed;
      } else {
        const Eigen::Vector2d y = measurement_.residual(m, zhat);
        const Eigen::Vector2d r2 = sig.cwiseProduct(sig);
        r.prefit[2 * k] = y[0];
        r.sigma[2 * k] = sig[0];
        if (sz == 2) {
          r.prefit[2 * k + 1] = y[1];
          r.sigma[2 * k + 1] = sig[1];
        }
        s(0, 0) += r2[0];
        s(1, 1) += r2[1];
        Eigen::Matrix2d si = Eigen::Matrix2d::Zero();
        double nis;
        if (sz == 1) {
          si(0, 0) = 1.0 / s(0, 0);
          nis = y[0] * y[0] * si(0, 0);
        } else {
          si = s.inverse();
          nis = y.dot(si * y);
        }
        r.nis[k] = nis;
        r.normalized_residual[k] = std::sqrt(nis);
        const bool warm = static_cast<int>(k) < settings_.warmup;
        const double gate = (settings_.gating && !warm) ? (sz == 2 ? gate2_ : gate1_) : 0.0;
        r.gate[k] = gate;
        if (!(s(0, 0) > 0.0) || !std::isfinite(nis)) {
          st = OrbitStepStatus::measurement_failed;
        } else if (gate > 0.0 && nis > gate) {
          st = OrbitStepStatus::rejected;
          ++r.rejected;
          r.postfit[2 * k] = y[0];
          if (sz == 2) r.postfit[2 * k + 1] = y[1];
        } else {
          // Gain; consider rows zeroed (Schmidt-Kalman).
          w.k.noalias() = w.pht * si;
          if (sz == 1) w.k.col(1).setZero();
          w.k.array().colwise() *= w.consider_mask.array();
          const Eigen::Vector2d yy = sz == 1 ? Eigen::Vector2d(y[0], 0.0) : y;
          w.x.noalias() += w.k * yy;
          if (!ukf) {
            // Joseph form: (I - K H) P (I - K H)^T + K R K^T.
            w.ikh.setIdentity();
            w.ikh.noalias() -= w.k * w.h;
            w.tmp.noalias() = w.ikh * w.p;
            w.p.noalias() = w.tmp * w.ikh.transpose();
            w.kr = w.k * r2.asDiagonal();
            w.p.noalias() += w.kr * w.k.transpose();
          } else {
            // General form for any gain: P - K Pxz^T - Pxz K^T + K S K^T.
            w.kr.noalias() = w.k * s;
            w.tmp.noalias() = w.k * w.pht.transpose();
            w.p -= w.tmp;
            w.p -= w.tmp.transpose();
            w.p.noalias() += w.kr * w.k.transpose();
          }
          w.tmp = w.p.transpose();
          w.p = 0.5 * (w.p + w.tmp);
          w.llt.compute(w.p);
          if (w.llt.info() != Eigen::Success) st = OrbitStepStatus::not_positive_definite;
          // Post-fit residual at the updated state.
          Eigen::Vector2d post, sig2;
          if (measurement_.evaluate(m, w.x, post, w.h, sig2) == core::ObservationStatus::success) {
            const Eigen::Vector2d yp = measurement_.residual(m, post);
            r.postfit[2 * k] = yp[0];
            if (sz == 2) r.postfit[2 * k + 1] = yp[1];
          }
        }
      }
      r.status[k] = st;
      put(r.state, k, w.x.transpose());
      put(r.covariance, k, w.p);
      if (st == OrbitStepStatus::not_positive_definite) break;
    }
  }
  r.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

OrbitSmootherResult OrbitFilter::smooth(const OrbitFilterResult& f) {
  const int n = f.n;
  core::require(n >= 6 && f.initial_state.size() == n, "result", "is not a filter result (state dimension)");
  const int K = f.steps_run;
  core::require(K >= 1, "result", "has no step to smooth (steps_run = 0)");
  const std::size_t nn = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  auto mat = [&](const std::vector<double>& v, int k) {
    return RowMat(Eigen::Map<const RowMat>(v.data() + static_cast<std::size_t>(k) * nn, n, n));
  };
  auto vec = [&](const std::vector<double>& v, int k) {
    return VectorXd(
        Eigen::Map<const VectorXd>(v.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(n), n));
  };
  OrbitSmootherResult s;
  s.n = n;
  s.t.assign(f.t.begin(), f.t.begin() + K);
  s.state.resize(static_cast<std::size_t>(K) * static_cast<std::size_t>(n));
  s.covariance.resize(static_cast<std::size_t>(K) * nn);
  VectorXd xs = vec(f.state, K - 1);
  MatrixXd ps = mat(f.covariance, K - 1);
  put(s.state, static_cast<std::size_t>(K - 1), xs.transpose());
  put(s.covariance, static_cast<std::size_t>(K - 1), ps);
  // Backward pass: C_k = P_k Phi_{k+1}^T Ppred_{k+1}^-1; index -1 is the initial epoch.
  for (int k = K - 2; k >= -1; --k) {
    const VectorXd xk = k >= 0 ? vec(f.state, k) : f.initial_state;
    const MatrixXd pk = k >= 0 ? MatrixXd(mat(f.covariance, k)) : f.initial_covariance;
    const MatrixXd phi = mat(f.transition, k + 1);
    const MatrixXd ppred = mat(f.predicted_covariance, k + 1);
    const VectorXd xpred = vec(f.predicted_state, k + 1);
    MatrixXd c = ppred.ldlt().solve(phi * pk).transpose();
    for (int ci : f.consider) c.row(ci).setZero();  // consider parameters keep their values
    xs = xk + c * (xs - xpred);
    ps = pk + c * (ps - ppred) * c.transpose();
    ps = 0.5 * (ps + ps.transpose()).eval();
    if (k >= 0) {
      put(s.state, static_cast<std::size_t>(k), xs.transpose());
      put(s.covariance, static_cast<std::size_t>(k), ps);
    }
  }
  s.initial_state = xs;
  s.initial_covariance = ps;
  return s;
}

}  // namespace satgnc::filter
