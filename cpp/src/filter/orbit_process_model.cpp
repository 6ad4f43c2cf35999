// Orbit process model of the filter room: DOP853 state + STM (+ DMC sensitivity) and the Gauss-Legendre
// discretization of SNC / DMC process noise (see satgnc/filter/orbit_process_model.hpp).
#include "satgnc/filter/orbit_process_model.hpp"

#include <Eigen/LU>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::filter {

using Mat11 = Eigen::Matrix<double, 11, 11>;  // r, v, w (DMC), Cd, Cr: the dynamic block
using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat113 = Eigen::Matrix<double, 11, 3>;

void OrbitProcessSettings::validate() const {
  integrator.validate();
  for (int i = 0; i < 3; ++i) {
    core::require_nonnegative(snc_psd_ric[i], "snc_psd_ric[" + std::to_string(i) + "]");
    core::require_positive(dmc_tau[i], "dmc_tau[" + std::to_string(i) + "]");
    core::require_nonnegative(dmc_sigma[i], "dmc_sigma[" + std::to_string(i) + "]");
  }
  core::require(parameters >= 0, "parameters", "must be >= 0, got " + std::to_string(parameters));
  core::require_positive(noise_step, "noise_step");
  core::require(quadrature_nodes >= 1 && quadrature_nodes <= 5, "quadrature_nodes",
                "must be in 1..5, got " + std::to_string(quadrature_nodes));
}

Mat3 OrbitProcessModel::ric_rows(const Vec3& r, const Vec3& v) noexcept {
  const Vec3 rr = r.normalized();
  const Vec3 cc = r.cross(v).normalized();
  const Vec3 ii = cc.cross(rr);
  Mat3 m;
  m.row(0) = rr.transpose();
  m.row(1) = ii.transpose();
  m.row(2) = cc.transpose();
  return m;
}

namespace detail {

namespace {

// Gauss-Legendre nodes on [-1, 1] and weights, 1..5 nodes (Abramowitz & Stegun 25.4.29).
struct GaussRule {
  std::array<double, 5> x{};
  std::array<double, 5> w{};
};
constexpr GaussRule gauss_rule(int n) {
  GaussRule g{};
  switch (n) {
    case 1:
      g.x = {0.0};
      g.w = {2.0};
      break;
    case 2:
      g.x = {-0.57735026918962576, 0.57735026918962576};
      g.w = {1.0, 1.0};
      break;
    case 3:
      g.x = {-0.77459666924148338, 0.0, 0.77459666924148338};
      g.w = {0.55555555555555556, 0.88888888888888889, 0.55555555555555556};
      break;
    case 4:
      g.x = {-0.86113631159405258, -0.33998104358485626, 0.33998104358485626, 0.86113631159405258};
      g.w = {0.34785484513745386, 0.65214515486254614, 0.65214515486254614, 0.34785484513745386};
      break;
    default:
      g.x = {-0.90617984593866399, -0.53846931010339377, 0.0, 0.53846931010339377, 0.90617984593866399};
      g.w = {0.23692688505618909, 0.47862867049936647, 0.56888888888888889, 0.47862867049936647,
             0.23692688505618909};
      break;
  }
  return g;
}

// dy/dt of [r, v, Phi (6x6 column-major), S (6x3 column-major, DMC only), Sp (6x2: d/dCd, d/dCr; Par
// only)].
template <bool Dmc, bool Par>
struct ProcessRhs {
  static constexpr int kSp = Dmc ? 60 : 42;  // offset of Sp
  static constexpr int N = kSp + (Par ? 12 : 0);
  using Vec = Eigen::Matrix<double, N, 1>;
  const dynamics::ForceModel* fm = nullptr;
  double t_a = 0.0;             // start of the sub-interval, s
  Vec3 w_a = Vec3::Zero();      // DMC acceleration at t_a, km/s^2
  Vec3 inv_tau = Vec3::Zero();  // 1/s
  bool cd = false, cr = false;  // which parameter partials are non-zero
  void operator()(double t, const Vec& y, Vec& dy) const {
    const Vec3 r = y.template head<3>();
    const Vec3 v = y.template segment<3>(3);
    Vec3 a;
    Mat3 da_dr, da_dv;
    fm->acceleration_jacobians(t, r, v, a, da_dr, da_dv);
    dy.template head<3>() = v;
    Vec3 decay = Vec3::Ones();
    if constexpr (Dmc) {
      decay = (-(t - t_a) * inv_tau).array().exp().matrix();
      a += w_a.cwiseProduct(decay);
    }
    dy.template segment<3>(3) = a;
    const Eigen::Map<const Mat6> phi(y.data() + 6);
    Eigen::Map<Mat6> dphi(dy.data() + 6);
    dphi.template topRows<3>() = phi.template bottomRows<3>();
    dphi.template bottomRows<3>().noalias() = da_dr * phi.template topRows<3>();
    dphi.template bottomRows<3>().noalias() += da_dv * phi.template bottomRows<3>();
    if constexpr (Dmc) {
      const Eigen::Map<const Mat63> s(y.data() + 42);
      Eigen::Map<Mat63> ds(dy.data() + 42);
      ds.template topRows<3>() = s.template bottomRows<3>();
      ds.template bottomRows<3>().noalias() = da_dr * s.template topRows<3>();
      ds.template bottomRows<3>().noalias() += da_dv * s.template bottomRows<3>();
      ds.template bottomRows<3>().diagonal() += decay;
    }
    if constexpr (Par) {
      using Mat62 = Eigen::Matrix<double, 6, 2>;
      const Eigen::Map<const Mat62> s(y.data() + kSp);
      Eigen::Map<Mat62> ds(dy.data() + kSp);
      ds.template topRows<3>() = s.template bottomRows<3>();
      ds.template bottomRows<3>().noalias() = da_dr * s.template topRows<3>();
      ds.template bottomRows<3>().noalias() += da_dv * s.template bottomRows<3>();
      // Partials validated at setup (the model holds the terms they scale): no throw here.
      if (cd)
        ds.template block<3, 1>(3, 0) += fm->acceleration_partial(dynamics::ForceParameter::cd, t, r, v);
      if (cr)
        ds.template block<3, 1>(3, 1) += fm->acceleration_partial(dynamics::ForceParameter::cr, t, r, v);
    }
  }
};

}  // namespace

struct OrbitProcessWorkspace {
  ProcessRhs<false, false> rhs6;
  ProcessRhs<true, false> rhs9;
  ProcessRhs<false, true> rhs6p;
  ProcessRhs<true, true> rhs9p;
  propagation::Dop853<42, ProcessRhs<false, false>> integ6;
  propagation::Dop853<60, ProcessRhs<true, false>> integ9;
  propagation::Dop853<54, ProcessRhs<false, true>> integ6p;
  propagation::Dop853<72, ProcessRhs<true, true>> integ9p;
  // Outputs of one sub-interval: the nodes, then its end (index nodes).
  std::array<double, 6> t_out{};
  std::array<Vec6, 6> x{};
  std::array<Mat6, 6> phi{};
  std::array<Mat63, 6> sens{};
  std::array<Eigen::Matrix<double, 6, 2>, 6> sensp{};
  Mat11 phi_tot = Mat11::Identity();
  Mat11 q_tot = Mat11::Zero();
  Mat11 tmp = Mat11::Zero();

  OrbitProcessWorkspace(const dynamics::ForceModel& fm, const OrbitProcessSettings& s)
      : integ6(rhs6, s.integrator),
        integ9(rhs9, s.integrator),
        integ6p(rhs6p, s.integrator),
        integ9p(rhs9p, s.integrator) {
    point_at(fm);
    rhs9.inv_tau = rhs9p.inv_tau = s.dmc_tau.cwiseInverse();
    rhs6p.cd = rhs9p.cd = s.cd_state >= 0;
    rhs6p.cr = rhs9p.cr = s.cr_state >= 0;
  }
  void point_at(const dynamics::ForceModel& fm) { rhs6.fm = rhs9.fm = rhs6p.fm = rhs9p.fm = &fm; }
};

// One sub-interval of the variational integration from (a, xa[, wa]) for one fixed-size system: the
// state, the STM [, the DMC sensitivity][, the Cd / Cr sensitivity] at the output times into w.
template <bool Dmc, bool Par, int N>
propagation::Dop853Info integrate_segment(OrbitProcessWorkspace& w,
                                          propagation::Dop853<N, ProcessRhs<Dmc, Par>>& integ,
                                          ProcessRhs<Dmc, Par>& rhs, double a, const Vec6& xa, const Vec3& wa,
                                          std::size_t n_out) {
  using VecN = Eigen::Matrix<double, N, 1>;
  if constexpr (Dmc) {
    rhs.t_a = a;
    rhs.w_a = wa;
  }
  VecN y0 = VecN::Zero();
  y0.template head<6>() = xa;
  Eigen::Map<Mat6>(y0.data() + 6).setIdentity();
  return integ.solve(a, y0, w.t_out.data(), n_out, [&w](std::size_t i, double, const VecN& y) {
    w.x[i] = y.template head<6>();
    w.phi[i] = Eigen::Map<const Mat6>(y.data() + 6);
    if constexpr (Dmc) w.sens[i] = Eigen::Map<const Mat63>(y.data() + 42);
    if constexpr (Par) w.sensp[i] = Eigen::Map<const Eigen::Matrix<double, 6, 2>>(y.data() + (Dmc ? 60 : 42));
  });
}

}  // namespace detail

OrbitProcessModel::OrbitProcessModel(const dynamics::ForceModel& force_model,
                                     const OrbitProcessSettings& settings)
    : force_model_(force_model), settings_(settings) {
  force_model_.validate();
  settings_.validate();
  n_ = 6 + (settings_.dmc ? 3 : 0) + settings_.parameters;
  const int off = settings_.dmc ? 9 : 6;
  for (const auto& [idx, name] : {std::pair<int, const char*>{settings_.cd_state, "cd_state"},
                                  std::pair<int, const char*>{settings_.cr_state, "cr_state"}}) {
    core::require(idx == -1 || (idx >= off && idx < n_), name,
                  "must be -1 or a parameter index in [" + std::to_string(off) + ", " + std::to_string(n_) +
                      "), got " + std::to_string(idx));
  }
  core::require(settings_.cd_state < 0 || settings_.cd_state != settings_.cr_state, "cr_state",
                "must differ from cd_state");
  // The partials throw std::invalid_argument here (setup) when the model has no drag / SRP term.
  const Vec3 r0(7000.0, 0.0, 0.0), v0(0.0, 7.5, 0.0);
  if (settings_.cd_state >= 0) {
    core::require(force_model_.drag.has_value() || force_model_.atmosphere_drag.has_value(), "cd_state",
                  "the force model has no drag term to scale");
    static_cast<void>(force_model_.acceleration_partial(dynamics::ForceParameter::cd, 0.0, r0, v0));
  }
  if (settings_.cr_state >= 0) {
    core::require(force_model_.srp.has_value(), "cr_state", "the force model has no SRP term to scale");
    static_cast<void>(force_model_.acceleration_partial(dynamics::ForceParameter::cr, 0.0, r0, v0));
  }
  ws_ = std::make_unique<detail::OrbitProcessWorkspace>(force_model_, settings_);
}

OrbitProcessModel::~OrbitProcessModel() = default;

// The workspace points at force_model_: re-point it after a move.
OrbitProcessModel::OrbitProcessModel(OrbitProcessModel&& o) noexcept
    : force_model_(std::move(o.force_model_)),
      settings_(o.settings_),
      n_(o.n_),
      total_steps_(o.total_steps_),
      ws_(std::move(o.ws_)) {
  if (ws_) ws_->point_at(force_model_);
}

OrbitProcessModel& OrbitProcessModel::operator=(OrbitProcessModel&& o) noexcept {
  force_model_ = std::move(o.force_model_);
  settings_ = o.settings_;
  n_ = o.n_;
  total_steps_ = o.total_steps_;
  ws_ = std::move(o.ws_);
  if (ws_) ws_->point_at(force_model_);
  return *this;
}

OrbitProcessInfo OrbitProcessModel::propagate(double t0, double t1, Eigen::Ref<Eigen::VectorXd> x,
                                              Eigen::Ref<Eigen::MatrixXd> phi,
                                              Eigen::Ref<Eigen::MatrixXd> q) noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  using propagation::Dop853Status;
  OrbitProcessInfo info;
  auto& w = *ws_;
  const bool dmc = settings_.dmc;
  const int m = dmc ? 9 : 6;
  if (x.size() != n_ || phi.rows() != n_ || phi.cols() != n_ || q.rows() != n_ || q.cols() != n_ ||
      !std::isfinite(t0) || !std::isfinite(t1) || !x.allFinite()) {
    info.status = Dop853Status::invalid_input;
    return info;
  }
  phi.setIdentity();
  q.setZero();
  w.phi_tot.setIdentity();
  w.q_tot.setZero();
  Vec6 xa = x.head<6>();
  Vec3 wa = dmc ? Vec3(x.segment<3>(6)) : Vec3::Zero();
  const int cd_i = settings_.cd_state, cr_i = settings_.cr_state;
  const bool par = cd_i >= 0 || cr_i >= 0;
  // Estimated Cd / Cr: the force model flies the state's current values (constant over the interval).
  if (cd_i >= 0) {
    if (force_model_.drag) force_model_.drag->cd = x[cd_i];
    if (force_model_.atmosphere_drag) force_model_.atmosphere_drag->cd = x[cd_i];
  }
  if (cr_i >= 0 && force_model_.srp) force_model_.srp->cr = x[cr_i];
  const double span = t1 - t0;
  const int segments = span == 0.0 ? 0 : static_cast<int>(std::ceil(std::abs(span) / settings_.noise_step));
  const detail::GaussRule g = detail::gauss_rule(settings_.quadrature_nodes);
  const int nn = settings_.quadrature_nodes;
  const Vec3 psd = settings_.snc_psd_ric;
  const bool snc = psd.maxCoeff() > 0.0;
  const Vec3 inv_tau = settings_.dmc_tau.cwiseInverse();
  const Vec3 q_dmc = (2.0 * settings_.dmc_sigma.array().square() * inv_tau.array()).matrix();  // km^2/s^5
  info.status = Dop853Status::success;
  for (int k = 0; k < segments; ++k) {
    const double a = t0 + span * k / segments;
    const double b = (k + 1 == segments) ? t1 : t0 + span * (k + 1) / segments;
    const double h = b - a;
    for (int i = 0; i < nn; ++i) w.t_out[i] = a + 0.5 * h * (1.0 + g.x[i]);
    w.t_out[nn] = b;
    const std::size_t n_out = static_cast<std::size_t>(nn + 1);
    propagation::Dop853Info di;
    if (par && dmc) {
      di = detail::integrate_segment(w, w.integ9p, w.rhs9p, a, xa, wa, n_out);
    } else if (par) {
      di = detail::integrate_segment(w, w.integ6p, w.rhs6p, a, xa, wa, n_out);
    } else if (dmc) {
      di = detail::integrate_segment(w, w.integ9, w.rhs9, a, xa, wa, n_out);
    } else {
      di = detail::integrate_segment(w, w.integ6, w.rhs6, a, xa, wa, n_out);
    }
    info.steps += di.steps;
    info.rhs_evals += di.rhs_evals;
    if (di.status != Dop853Status::success || di.outputs != n_out) {
      info.status = di.status == Dop853Status::success ? Dop853Status::rhs_failure : di.status;
      return info;
    }
    // Segment transition matrix and noise in the 11 x 11 storage (r, v | w | Cd, Cr).
    const Mat6& pb = w.phi[nn];
    Mat11 phis = Mat11::Identity();
    phis.topLeftCorner<6, 6>() = pb;
    Vec3 eb = Vec3::Ones();
    if (dmc) {
      eb = (-h * inv_tau).array().exp().matrix();
      phis.block<6, 3>(0, 6) = w.sens[nn];
      phis.block<3, 3>(6, 6) = eb.asDiagonal();
    }
    if (par) phis.block<6, 2>(0, 9) = w.sensp[nn];
    Mat11 qs = Mat11::Zero();
    for (int i = 0; i < nn; ++i) {
      const double wk = 0.5 * h * g.w[i];
      // Phi(b, s_i) = Phi(b, a) Phi(s_i, a)^-1.
      const Mat6 pbs = w.phi[i].transpose().partialPivLu().solve(pb.transpose()).transpose();
      if (snc) {
        const Mat3 ric = OrbitProcessModel::ric_rows(w.x[i].head<3>(), w.x[i].tail<3>());
        const Mat3 qg = ric.transpose() * psd.asDiagonal() * ric;  // GCRF PSD, km^2/s^3
        const Mat63 nb = pbs.rightCols<3>();
        qs.topLeftCorner<6, 6>().noalias() += wk * (nb * qg * nb.transpose());
      }
      if (dmc) {
        const double s = w.t_out[i];
        const Vec3 grow = ((s - a) * inv_tau).array().exp().matrix();
        const Vec3 ebs = (-(b - s) * inv_tau).array().exp().matrix();
        Mat113 mk = Mat113::Zero();
        mk.topRows<6>() = (w.sens[nn] - pbs * w.sens[i]) * grow.asDiagonal();
        mk.block<3, 3>(6, 0) = ebs.asDiagonal();
        qs.noalias() += wk * (mk * q_dmc.asDiagonal() * mk.transpose());
      }
    }
    if (dmc) {
      // The w block exactly: sigma^2 (1 - exp(-2 |h| / tau)), signed like h.
      const double sgn = h >= 0.0 ? 1.0 : -1.0;
      const Vec3 ew2 = (-2.0 * std::abs(h) * inv_tau).array().exp().matrix();
      qs.block<3, 3>(6, 6) =
          (sgn * settings_.dmc_sigma.array().square() * (1.0 - ew2.array())).matrix().asDiagonal();
    }
    w.tmp.noalias() = phis * w.q_tot;
    w.q_tot.noalias() = w.tmp * phis.transpose();
    w.q_tot += qs;
    w.tmp.noalias() = phis * w.phi_tot;
    w.phi_tot = w.tmp;
    xa = w.x[nn];
    wa = wa.cwiseProduct(eb);
  }
  x.head<6>() = xa;
  if (dmc) x.segment<3>(6) = wa;
  phi.topLeftCorner(m, m) = w.phi_tot.topLeftCorner(m, m);
  if (cd_i >= 0) phi.col(cd_i).head(m) = w.phi_tot.col(9).head(m);
  if (cr_i >= 0) phi.col(cr_i).head(m) = w.phi_tot.col(10).head(m);
  q.topLeftCorner(m, m) = 0.5 * (w.q_tot.topLeftCorner(m, m) + w.q_tot.topLeftCorner(m, m).transpose());
  return info;
}

ModelStatus OrbitProcessModel::propagate(const Eigen::Ref<const Eigen::VectorXd>& x0, double t0, double t1,
                                         Eigen::Ref<Eigen::VectorXd> x1, Eigen::Ref<Eigen::MatrixXd> phi,
                                         Eigen::Ref<Eigen::MatrixXd> qd, bool /*with_jacobian*/) noexcept {
  if (x0.size() != n_ || x1.size() != n_) return ModelStatus::failed;
  x1 = x0;
  const OrbitProcessInfo info = propagate(t0, t1, x1, phi, qd);
  total_steps_ += info.steps;
  return info.status == propagation::Dop853Status::success ? ModelStatus::success : ModelStatus::failed;
}

}  // namespace satgnc::filter
