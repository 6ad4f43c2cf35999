#pragma once
/// @file dop853.hpp
/// Embedded-friendly explicit Runge-Kutta integrator: Dormand-Prince 8(5,3) with Hairer's DOP853
/// tableau, error estimator (5th and 3rd order embedded solutions), step-size control and 7th-order
/// dense output (Hairer, Norsett, Wanner, "Solving Ordinary Differential Equations I", 2nd ed., 1993,
/// sec. II.5 and II.10; coefficients as published with DOP853). Fixed-size Eigen state (size N a
/// template parameter), no heap allocation: every work vector lives inside the integrator object.
/// Units are the caller's (orbital wrapper: km, km/s, s).
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/solver.hpp"
#include "satgnc/core/status.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::propagation {

/// Default relative tolerance of satgnc's orbit propagation (Dop853Settings, satgnc.propagate, ensembles),
/// chosen by measurement (bench/propagation_defaults.py, docs/propagation.md "Defaults"): with
/// kDefaultOrbitAtol it meets 1 mm per day on LEO orbits (e <= 0.02), with and without J2 and the
/// STM, at the lowest cost of the methods measured (CVODES Adams and BDF meet it at no tolerance swept).
inline constexpr double kDefaultOrbitRtol = 3e-12;
/// Default absolute tolerance (km, km/s; STM entries dimensionless), rtol / 100 (see kDefaultOrbitRtol).
inline constexpr double kDefaultOrbitAtol = 3e-14;

/// Integrator settings (plain struct; defaults as in Hairer's DOP853 unless noted).
struct Dop853Settings {
  double rtol = kDefaultOrbitRtol;  ///< relative tolerance (> 10 machine epsilons, as in Hairer's code)
  double atol = kDefaultOrbitAtol;  ///< absolute tolerance (>= 0), units of the state
  long max_steps = 100000;          ///< step budget (accepted + rejected), > 0
  double h0 = 0.0;                  ///< initial |step|; 0 selects it automatically (Hairer's HINIT)
  double h_max = 0.0;               ///< largest |step|; 0 means |t_end - t0|
  double safety = 0.9;              ///< safety factor of the step-size controller, in (1e-4, 1)
  double fac_min = 0.333;           ///< smallest step-size ratio h_new / h per step, in (0, 1]
  double fac_max = 6.0;             ///< largest step-size ratio h_new / h per step, >= 1
  double beta = 0.0;                ///< PI-control (Lund) stabilisation, in [0, 0.2]
  /// Throws std::invalid_argument("field: rule") unless every field is in its documented range.
  void validate() const;
};

/// Outcome of Dop853::solve (core/status.hpp): success, invalid_settings (kept for its number; the
/// constructor validates the settings), invalid_input (non-finite t0/y0/output time, or output times
/// not monotone away from t0), max_steps, step_size_too_small (tolerance too tight or singularity),
/// rhs_failure (non-finite derivative at an accepted point), event (the event function reached zero,
/// Dop853Info::t_reached = its time); unsolved before the first solve.
using core::Dop853Status;

/// The default event of Dop853::solve: none.
struct Dop853NoEvent {
  template <class Vec>
  double operator()(double, const Vec&) const {
    return 1.0;
  }
};

/// Human-readable message for a Dop853Status.
[[deprecated("use status_message")]] inline const char* dop853_status_message(Dop853Status s) {
  return core::status_message(s);
}

/// Statistics and status of one solve. From core::InfoBase: status (unsolved before a solve),
/// iterations (= steps, mirrored), solve_time (wall time of solve(), s); the residuals are unused (0).
struct Dop853Info : core::InfoBase<Dop853Status> {
  long steps = 0;           ///< accepted steps
  long rejected = 0;        ///< rejected steps
  long rhs_evals = 0;       ///< right-hand-side evaluations
  double t_reached = 0.0;   ///< last accepted time
  double h_last = 0.0;      ///< last step size attempted
  std::size_t outputs = 0;  ///< number of output times delivered
};

/// Check a Settings struct; returns Dop853Status::success or invalid_settings.
inline Dop853Status dop853_check_settings(const Dop853Settings& s) {
  const bool ok = std::isfinite(s.rtol) && s.rtol > 10.0 * std::numeric_limits<double>::epsilon() &&
                  std::isfinite(s.atol) && s.atol >= 0.0 && s.max_steps > 0 && std::isfinite(s.h0) &&
                  s.h0 >= 0.0 && std::isfinite(s.h_max) && s.h_max >= 0.0 && s.safety > 1e-4 &&
                  s.safety < 1.0 && s.fac_min > 0.0 && s.fac_min <= 1.0 && std::isfinite(s.fac_max) &&
                  s.fac_max >= 1.0 && s.beta >= 0.0 && s.beta <= 0.2;
  return ok ? Dop853Status::success : Dop853Status::invalid_settings;
}

/// DOP853 tableau (Hairer's published coefficients).
namespace dop853_tableau {
// Nodes c_i (stage i = 1..16; stage 13 is f(t + h, y_new), stages 14-16 serve dense output).
inline constexpr double c1 = 0.0;
inline constexpr double c2 = 0.526001519587677318785587544488e-01;
inline constexpr double c3 = 0.789002279381515978178381316732e-01;
inline constexpr double c4 = 0.118350341907227396726757197510;
inline constexpr double c5 = 0.281649658092772603273242802490;
inline constexpr double c6 = 0.333333333333333333333333333333;
inline constexpr double c7 = 0.25;
inline constexpr double c8 = 0.307692307692307692307692307692;
inline constexpr double c9 = 0.651282051282051282051282051282;
inline constexpr double c10 = 0.6;
inline constexpr double c11 = 0.857142857142857142857142857142;
inline constexpr double c12 = 1.0;
inline constexpr double c13 = 1.0;
inline constexpr double c14 = 0.1;
inline constexpr double c15 = 0.2;
inline constexpr double c16 = 0.777777777777777777777777777778;
// Runge-Kutta matrix a_ij (1-based stage indices; zero entries omitted). Row 13 holds the weights b_j.
inline constexpr double a2_1 = 5.26001519587677318785587544488e-2;
inline constexpr double a3_1 = 1.97250569845378994544595329183e-2;
inline constexpr double a3_2 = 5.91751709536136983633785987549e-2;
inline constexpr double a4_1 = 2.95875854768068491816892993775e-2;
inline constexpr double a4_3 = 8.87627564304205475450678981324e-2;
inline constexpr double a5_1 = 2.41365134159266685502369798665e-1;
inline constexpr double a5_3 = -8.84549479328286085344864962717e-1;
inline constexpr double a5_4 = 9.24834003261792003115737966543e-1;
inline constexpr double a6_1 = 3.7037037037037037037037037037e-2;
inline constexpr double a6_4 = 1.70828608729473871279604482173e-1;
inline constexpr double a6_5 = 1.25467687566822425016691814123e-1;
inline constexpr double a7_1 = 3.7109375e-2;
inline constexpr double a7_4 = 1.70252211019544039314978060272e-1;
inline constexpr double a7_5 = 6.02165389804559606850219397283e-2;
inline constexpr double a7_6 = -1.7578125e-2;
inline constexpr double a8_1 = 3.70920001185047927108779319836e-2;
inline constexpr double a8_4 = 1.70383925712239993810214054705e-1;
inline constexpr double a8_5 = 1.07262030446373284651809199168e-1;
inline constexpr double a8_6 = -1.53194377486244017527936158236e-2;
inline constexpr double a8_7 = 8.27378916381402288758473766002e-3;
inline constexpr double a9_1 = 6.24110958716075717114429577812e-1;
inline constexpr double a9_4 = -3.36089262944694129406857109825;
inline constexpr double a9_5 = -8.68219346841726006818189891453e-1;
inline constexpr double a9_6 = 2.75920996994467083049415600797e1;
inline constexpr double a9_7 = 2.01540675504778934086186788979e1;
inline constexpr double a9_8 = -4.34898841810699588477366255144e1;
inline constexpr double a10_1 = 4.77662536438264365890433908527e-1;
inline constexpr double a10_4 = -2.48811461997166764192642586468;
inline constexpr double a10_5 = -5.90290826836842996371446475743e-1;
inline constexpr double a10_6 = 2.12300514481811942347288949897e1;
inline constexpr double a10_7 = 1.52792336328824235832596922938e1;
inline constexpr double a10_8 = -3.32882109689848629194453265587e1;
inline constexpr double a10_9 = -2.03312017085086261358222928593e-2;
inline constexpr double a11_1 = -9.3714243008598732571704021658e-1;
inline constexpr double a11_4 = 5.18637242884406370830023853209;
inline constexpr double a11_5 = 1.09143734899672957818500254654;
inline constexpr double a11_6 = -8.14978701074692612513997267357;
inline constexpr double a11_7 = -1.85200656599969598641566180701e1;
inline constexpr double a11_8 = 2.27394870993505042818970056734e1;
inline constexpr double a11_9 = 2.49360555267965238987089396762;
inline constexpr double a11_10 = -3.0467644718982195003823669022;
inline constexpr double a12_1 = 2.27331014751653820792359768449;
inline constexpr double a12_4 = -1.05344954667372501984066689879e1;
inline constexpr double a12_5 = -2.00087205822486249909675718444;
inline constexpr double a12_6 = -1.79589318631187989172765950534e1;
inline constexpr double a12_7 = 2.79488845294199600508499808837e1;
inline constexpr double a12_8 = -2.85899827713502369474065508674;
inline constexpr double a12_9 = -8.87285693353062954433549289258;
inline constexpr double a12_10 = 1.23605671757943030647266201528e1;
inline constexpr double a12_11 = 6.43392746015763530355970484046e-1;
inline constexpr double a13_1 = 5.42937341165687622380535766363e-2;
inline constexpr double a13_6 = 4.45031289275240888144113950566;
inline constexpr double a13_7 = 1.89151789931450038304281599044;
inline constexpr double a13_8 = -5.8012039600105847814672114227;
inline constexpr double a13_9 = 3.1116436695781989440891606237e-1;
inline constexpr double a13_10 = -1.52160949662516078556178806805e-1;
inline constexpr double a13_11 = 2.01365400804030348374776537501e-1;
inline constexpr double a13_12 = 4.47106157277725905176885569043e-2;
inline constexpr double a14_1 = 5.61675022830479523392909219681e-2;
inline constexpr double a14_7 = 2.53500210216624811088794765333e-1;
inline constexpr double a14_8 = -2.46239037470802489917441475441e-1;
inline constexpr double a14_9 = -1.24191423263816360469010140626e-1;
inline constexpr double a14_10 = 1.5329179827876569731206322685e-1;
inline constexpr double a14_11 = 8.20105229563468988491666602057e-3;
inline constexpr double a14_12 = 7.56789766054569976138603589584e-3;
inline constexpr double a14_13 = -8.298e-3;
inline constexpr double a15_1 = 3.18346481635021405060768473261e-2;
inline constexpr double a15_6 = 2.83009096723667755288322961402e-2;
inline constexpr double a15_7 = 5.35419883074385676223797384372e-2;
inline constexpr double a15_8 = -5.49237485713909884646569340306e-2;
inline constexpr double a15_11 = -1.08347328697249322858509316994e-4;
inline constexpr double a15_12 = 3.82571090835658412954920192323e-4;
inline constexpr double a15_13 = -3.40465008687404560802977114492e-4;
inline constexpr double a15_14 = 1.41312443674632500278074618366e-1;
inline constexpr double a16_1 = -4.28896301583791923408573538692e-1;
inline constexpr double a16_6 = -4.69762141536116384314449447206;
inline constexpr double a16_7 = 7.68342119606259904184240953878;
inline constexpr double a16_8 = 4.06898981839711007970213554331;
inline constexpr double a16_9 = 3.56727187455281109270669543021e-1;
inline constexpr double a16_13 = -1.39902416515901462129418009734e-3;
inline constexpr double a16_14 = 2.9475147891527723389556272149;
inline constexpr double a16_15 = -9.15095847217987001081870187138;
// Weights of the embedded 3rd-order solution: bhat_j = b_j - e3_j, nonzero at j = 1, 9, 12.
inline constexpr double bhh1 = 0.244094488188976377952755905512;
inline constexpr double bhh9 = 0.733846688281611857341361741547;
inline constexpr double bhh12 = 0.220588235294117647058823529412e-1;
// 5th-order error estimator weights e_j.
inline constexpr double e1 = 0.1312004499419488073250102996e-1;
inline constexpr double e6 = -0.1225156446376204440720569753e+1;
inline constexpr double e7 = -0.4957589496572501915214079952;
inline constexpr double e8 = 0.1664377182454986536961530415e+1;
inline constexpr double e9 = -0.3503288487499736816886487290;
inline constexpr double e10 = 0.3341791187130174790297318841;
inline constexpr double e11 = 0.8192320648511571246570742613e-1;
inline constexpr double e12 = -0.2235530786388629525884427845e-1;
// Dense-output coefficients d_{k,j}, k = 4..7 (contd8 polynomial terms 4..7).
inline constexpr double d4_1 = -0.84289382761090128651353491142e+1;
inline constexpr double d4_6 = 0.56671495351937776962531783590;
inline constexpr double d4_7 = -0.30689499459498916912797304727e+1;
inline constexpr double d4_8 = 0.23846676565120698287728149680e+1;
inline constexpr double d4_9 = 0.21170345824450282767155149946e+1;
inline constexpr double d4_10 = -0.87139158377797299206789907490;
inline constexpr double d4_11 = 0.22404374302607882758541771650e+1;
inline constexpr double d4_12 = 0.63157877876946881815570249290;
inline constexpr double d4_13 = -0.88990336451333310820698117400e-1;
inline constexpr double d4_14 = 0.18148505520854727256656404962e+2;
inline constexpr double d4_15 = -0.91946323924783554000451984436e+1;
inline constexpr double d4_16 = -0.44360363875948939664310572000e+1;
inline constexpr double d5_1 = 0.10427508642579134603413151009e+2;
inline constexpr double d5_6 = 0.24228349177525818288430175319e+3;
inline constexpr double d5_7 = 0.16520045171727028198505394887e+3;
inline constexpr double d5_8 = -0.37454675472269020279518312152e+3;
inline constexpr double d5_9 = -0.22113666853125306036270938578e+2;
inline constexpr double d5_10 = 0.77334326684722638389603898808e+1;
inline constexpr double d5_11 = -0.30674084731089398182061213626e+2;
inline constexpr double d5_12 = -0.93321305264302278729567221706e+1;
inline constexpr double d5_13 = 0.15697238121770843886131091075e+2;
inline constexpr double d5_14 = -0.31139403219565177677282850411e+2;
inline constexpr double d5_15 = -0.93529243588444783865713862664e+1;
inline constexpr double d5_16 = 0.35816841486394083752465898540e+2;
inline constexpr double d6_1 = 0.19985053242002433820987653617e+2;
inline constexpr double d6_6 = -0.38703730874935176555105901742e+3;
inline constexpr double d6_7 = -0.18917813819516756882830838328e+3;
inline constexpr double d6_8 = 0.52780815920542364900561016686e+3;
inline constexpr double d6_9 = -0.11573902539959630126141871134e+2;
inline constexpr double d6_10 = 0.68812326946963000169666922661e+1;
inline constexpr double d6_11 = -0.10006050966910838403183860980e+1;
inline constexpr double d6_12 = 0.77771377980534432092869265740;
inline constexpr double d6_13 = -0.27782057523535084065932004339e+1;
inline constexpr double d6_14 = -0.60196695231264120758267380846e+2;
inline constexpr double d6_15 = 0.84320405506677161018159903784e+2;
inline constexpr double d6_16 = 0.11992291136182789328035130030e+2;
inline constexpr double d7_1 = -0.25693933462703749003312586129e+2;
inline constexpr double d7_6 = -0.15418974869023643374053993627e+3;
inline constexpr double d7_7 = -0.23152937917604549567536039109e+3;
inline constexpr double d7_8 = 0.35763911791061412378285349910e+3;
inline constexpr double d7_9 = 0.93405324183624310003907691704e+2;
inline constexpr double d7_10 = -0.37458323136451633156875139351e+2;
inline constexpr double d7_11 = 0.10409964950896230045147246184e+3;
inline constexpr double d7_12 = 0.29840293426660503123344363579e+2;
inline constexpr double d7_13 = -0.43533456590011143754432175058e+2;
inline constexpr double d7_14 = 0.96324553959188282948394950600e+2;
inline constexpr double d7_15 = -0.39177261675615439165231486172e+2;
inline constexpr double d7_16 = -0.14972683625798562581422125276e+3;
}  // namespace dop853_tableau

namespace detail {
/// Finite check at the cost of one reduction (a sum is non-finite iff some term is, barring overflow,
/// which the full check then settles).
template <class V>
bool all_finite(const V& v) {
  return std::isfinite(v.sum()) || v.allFinite();
}
}  // namespace detail

/// The workspace of Dop853<N, Rhs>: every work vector (16 stages, trial states, the 7th-order
/// dense-output coefficients) and the evaluation count, held by value in the integrator (sized by N at
/// compile time: no allocation, no indirection in the stepping loop). Set up with the integrator,
/// reused by every solve().
template <int N>
struct Dop853Workspace {
  using Vec = Eigen::Matrix<double, N, 1>;
  Vec k[16];        ///< stage derivatives k1..k16 (state units per s)
  Vec y, yt, ynew;  ///< state at the step start, stage argument, state at the step end
  Vec bsum;         ///< the 8th-order increment sum (error estimate)
  Vec cont[8];      ///< dense-output coefficients of the last accepted step
  long nfev = 0;    ///< right-hand-side evaluations of the current solve()
};

/// Dormand-Prince 8(5,3) integrator on a fixed-size state of dimension N.
/// Rhs is a callable `void(double t, const Eigen::Matrix<double, N, 1>& y, Eigen::Matrix<double, N, 1>& dy)`.
/// Settings -> workspace -> solve: the object validates its Dop853Settings and owns its
/// Dop853Workspace<N> (16 stages, dense-output coefficients): construct it once (on the stack or
/// statically) and call solve() as often as needed; solve() never allocates and returns a Dop853Info.
template <int N, class Rhs>
class Dop853 {
 public:
  using Vec = Eigen::Matrix<double, N, 1>;

  /// @param rhs right-hand side (referenced, must outlive the integrator)
  /// @param settings tolerances and controller parameters
  /// @throws std::invalid_argument naming the field when a setting is out of range (Settings::validate)
  Dop853(Rhs& rhs, const Dop853Settings& settings) : rhs_(rhs), s_(settings) { s_.validate(); }

  /// Integrate from (t0, y0) through the output times t_out[0..n_out), which must be finite and
  /// monotone away from t0 (all >= t0 or all <= t0; values equal to t0 are allowed), calling
  /// out(i, t_out[i], y) for each. Steps are not shortened to hit output times (7th-order dense
  /// output); only the last step lands exactly on t_out[n_out - 1].
  /// event(t, y) -> double (optional, > 0 at t0): the integration stops at the first accepted step
  /// whose end has event <= 0, at the zero located on the 7th-order dense output by bisection
  /// (status event, t_reached = its time, only the outputs before it delivered). Checked at step
  /// ends: an excursion below zero and back within one step is not seen.
  template <class Output, class Event = Dop853NoEvent>
  Dop853Info solve(double t0, const Vec& y0, const double* t_out, std::size_t n_out, Output&& out,
                   const Event& event = Event()) {
    SATGNC_NO_MALLOC_SCOPE;
    const auto start = std::chrono::steady_clock::now();
    Dop853Info info = run<Output, Event>(t0, y0, t_out, n_out, std::forward<Output>(out), event);
    info.iterations = static_cast<int>(info.steps);  // core::InfoBase mirror
    info.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return info;
  }

  /// The integrator's workspace (read-only; after a solve() it holds that run's last step).
  const Dop853Workspace<N>& workspace() const noexcept { return w_; }

 private:
  template <class Output, class Event>
  Dop853Info run(double t0, const Vec& y0, const double* t_out, std::size_t n_out, Output&& out,
                 const Event& event);
  double error_norm(double h) const;
  double initial_step(double t, double dir, double h_max);
  void prepare_dense(double t, double h);
  void interpolate(double s, Vec& y) const;

  Rhs& rhs_;
  Dop853Settings s_;
  Dop853Workspace<N> w_;
};

template <int N, class Rhs>
double Dop853<N, Rhs>::error_norm(double h) const {
  namespace tb = dop853_tableau;
  const Vec* k = w_.k;
  // One division per component; the 3rd- and 5th-order estimates are formed component by component.
  const auto inv_sk = (s_.atol + s_.rtol * w_.y.cwiseAbs().cwiseMax(w_.ynew.cwiseAbs()).array())
                          .max(std::numeric_limits<double>::min())
                          .inverse()
                          .eval();
  const double err3 =
      ((w_.bsum - tb::bhh1 * k[0] - tb::bhh9 * k[8] - tb::bhh12 * k[11]).array() * inv_sk).square().sum();
  const double err5 = ((tb::e1 * k[0] + tb::e6 * k[5] + tb::e7 * k[6] + tb::e8 * k[7] + tb::e9 * k[8] +
                        tb::e10 * k[9] + tb::e11 * k[10] + tb::e12 * k[11])
                           .array() *
                       inv_sk)
                          .square()
                          .sum();
  double deno = err5 + 0.01 * err3;
  if (deno <= 0.0) deno = 1.0;
  return std::abs(h) * err5 * std::sqrt(1.0 / (N * deno));
}

template <int N, class Rhs>
double Dop853<N, Rhs>::initial_step(double t, double dir, double h_max) {
  // Hairer's HINIT: an explicit Euler step probes the second derivative.
  Vec* k = w_.k;
  const auto sk = s_.atol + s_.rtol * w_.y.array().abs();
  const double dnf = (k[0].array() / sk).square().sum();
  const double dny = (w_.y.array() / sk).square().sum();
  double h = (dnf <= 1e-10 || dny <= 1e-10) ? 1e-6 : std::sqrt(dny / dnf) * 0.01;
  h = std::min(h, h_max) * dir;
  w_.yt.noalias() = w_.y + h * k[0];
  rhs_(t + h, w_.yt, k[1]);
  ++w_.nfev;
  const double der2 = std::sqrt(((k[1] - k[0]).array() / sk).square().sum()) / std::abs(h);
  const double der12 = std::max(der2, std::sqrt(dnf));
  const double h1 = der12 <= 1e-15 ? std::max(1e-6, std::abs(h) * 1e-3) : std::pow(0.01 / der12, 1.0 / 8.0);
  return std::min({100.0 * std::abs(h), h1, h_max});
}

template <int N, class Rhs>
void Dop853<N, Rhs>::prepare_dense(double t, double h) {
  namespace tb = dop853_tableau;
  Vec* k = w_.k;
  w_.yt.noalias() =
      w_.y + h * (tb::a14_1 * k[0] + tb::a14_7 * k[6] + tb::a14_8 * k[7] + tb::a14_9 * k[8] +
                  tb::a14_10 * k[9] + tb::a14_11 * k[10] + tb::a14_12 * k[11] + tb::a14_13 * k[12]);
  rhs_(t + tb::c14 * h, w_.yt, k[13]);
  w_.yt.noalias() =
      w_.y + h * (tb::a15_1 * k[0] + tb::a15_6 * k[5] + tb::a15_7 * k[6] + tb::a15_8 * k[7] +
                  tb::a15_11 * k[10] + tb::a15_12 * k[11] + tb::a15_13 * k[12] + tb::a15_14 * k[13]);
  rhs_(t + tb::c15 * h, w_.yt, k[14]);
  w_.yt.noalias() =
      w_.y + h * (tb::a16_1 * k[0] + tb::a16_6 * k[5] + tb::a16_7 * k[6] + tb::a16_8 * k[7] +
                  tb::a16_9 * k[8] + tb::a16_13 * k[12] + tb::a16_14 * k[13] + tb::a16_15 * k[14]);
  rhs_(t + tb::c16 * h, w_.yt, k[15]);
  w_.cont[4].noalias() = h * (tb::d4_1 * k[0] + tb::d4_6 * k[5] + tb::d4_7 * k[6] + tb::d4_8 * k[7] +
                              tb::d4_9 * k[8] + tb::d4_10 * k[9] + tb::d4_11 * k[10] + tb::d4_12 * k[11] +
                              tb::d4_13 * k[12] + tb::d4_14 * k[13] + tb::d4_15 * k[14] + tb::d4_16 * k[15]);
  w_.cont[5].noalias() = h * (tb::d5_1 * k[0] + tb::d5_6 * k[5] + tb::d5_7 * k[6] + tb::d5_8 * k[7] +
                              tb::d5_9 * k[8] + tb::d5_10 * k[9] + tb::d5_11 * k[10] + tb::d5_12 * k[11] +
                              tb::d5_13 * k[12] + tb::d5_14 * k[13] + tb::d5_15 * k[14] + tb::d5_16 * k[15]);
  w_.cont[6].noalias() = h * (tb::d6_1 * k[0] + tb::d6_6 * k[5] + tb::d6_7 * k[6] + tb::d6_8 * k[7] +
                              tb::d6_9 * k[8] + tb::d6_10 * k[9] + tb::d6_11 * k[10] + tb::d6_12 * k[11] +
                              tb::d6_13 * k[12] + tb::d6_14 * k[13] + tb::d6_15 * k[14] + tb::d6_16 * k[15]);
  w_.cont[7].noalias() = h * (tb::d7_1 * k[0] + tb::d7_6 * k[5] + tb::d7_7 * k[6] + tb::d7_8 * k[7] +
                              tb::d7_9 * k[8] + tb::d7_10 * k[9] + tb::d7_11 * k[10] + tb::d7_12 * k[11] +
                              tb::d7_13 * k[12] + tb::d7_14 * k[13] + tb::d7_15 * k[14] + tb::d7_16 * k[15]);

  w_.nfev += 3;
  w_.cont[0] = w_.y;
  w_.cont[1] = w_.ynew - w_.y;
  w_.cont[2] = h * k[0] - w_.cont[1];
  w_.cont[3] = w_.cont[1] - h * k[12] - w_.cont[2];
}

template <int N, class Rhs>
void Dop853<N, Rhs>::interpolate(double s, Vec& y) const {
  const double s1 = 1.0 - s;
  y.noalias() = w_.cont[0] +
                s * (w_.cont[1] +
                     s1 * (w_.cont[2] +
                           s * (w_.cont[3] +
                                s1 * (w_.cont[4] + s * (w_.cont[5] + s1 * (w_.cont[6] + s * w_.cont[7]))))));
}

template <int N, class Rhs>
template <class Output, class Event>
Dop853Info Dop853<N, Rhs>::run(double t0, const Vec& y0, const double* t_out, std::size_t n_out, Output&& out,
                               const Event& event) {
  namespace tb = dop853_tableau;
  Dop853Info info;
  info.status = Dop853Status::success;
  info.t_reached = t0;
  w_.nfev = 0;
  if (dop853_check_settings(s_) != Dop853Status::success) {
    info.status = Dop853Status::invalid_settings;
    return info;
  }
  if (!std::isfinite(t0) || !y0.allFinite()) {
    info.status = Dop853Status::invalid_input;
    return info;
  }
  if (n_out == 0) return info;
  const double t_end = t_out[n_out - 1];
  const double dir = t_end >= t0 ? 1.0 : -1.0;
  double prev = t0;
  for (std::size_t i = 0; i < n_out; ++i) {
    if (!std::isfinite(t_out[i]) || (t_out[i] - prev) * dir < 0.0) {
      info.status = Dop853Status::invalid_input;
      return info;
    }
    prev = t_out[i];
  }
  std::size_t io = 0;
  w_.y = y0;
  while (io < n_out && t_out[io] == t0) out(io++, t0, static_cast<const Vec&>(w_.y));
  info.outputs = io;
  if (io == n_out) return info;

  Vec* k = w_.k;
  double t = t0;
  rhs_(t, w_.y, k[0]);
  ++w_.nfev;
  if (!detail::all_finite(k[0])) {
    info.status = Dop853Status::rhs_failure;
    info.rhs_evals = w_.nfev;
    return info;
  }
  const double h_max = s_.h_max > 0.0 ? std::min(s_.h_max, std::abs(t_end - t0)) : std::abs(t_end - t0);
  double h = (s_.h0 > 0.0 ? std::min(s_.h0, h_max) : initial_step(t, dir, h_max)) * dir;
  const double expo1 = 1.0 / 8.0 - s_.beta * 0.2;
  const double facc1 = 1.0 / s_.fac_min, facc2 = 1.0 / s_.fac_max;
  double facold = 1e-4;
  bool reject = false;
  long nstep = 0;
  constexpr double uround = std::numeric_limits<double>::epsilon();
  for (;;) {
    if (nstep >= s_.max_steps) {
      info.status = Dop853Status::max_steps;
      break;
    }
    if (0.1 * std::abs(h) <= std::abs(t) * uround || !(std::abs(h) > 0.0)) {
      info.status = Dop853Status::step_size_too_small;
      break;
    }
    bool last = false;
    if ((t + 1.01 * h - t_end) * dir > 0.0) {
      h = t_end - t;
      last = true;
    }
    ++nstep;
    info.h_last = h;
    w_.yt.noalias() = w_.y + h * (tb::a2_1 * k[0]);
    rhs_(t + tb::c2 * h, w_.yt, k[1]);
    w_.yt.noalias() = w_.y + h * (tb::a3_1 * k[0] + tb::a3_2 * k[1]);
    rhs_(t + tb::c3 * h, w_.yt, k[2]);
    w_.yt.noalias() = w_.y + h * (tb::a4_1 * k[0] + tb::a4_3 * k[2]);
    rhs_(t + tb::c4 * h, w_.yt, k[3]);
    w_.yt.noalias() = w_.y + h * (tb::a5_1 * k[0] + tb::a5_3 * k[2] + tb::a5_4 * k[3]);
    rhs_(t + tb::c5 * h, w_.yt, k[4]);
    w_.yt.noalias() = w_.y + h * (tb::a6_1 * k[0] + tb::a6_4 * k[3] + tb::a6_5 * k[4]);
    rhs_(t + tb::c6 * h, w_.yt, k[5]);
    w_.yt.noalias() = w_.y + h * (tb::a7_1 * k[0] + tb::a7_4 * k[3] + tb::a7_5 * k[4] + tb::a7_6 * k[5]);
    rhs_(t + tb::c7 * h, w_.yt, k[6]);
    w_.yt.noalias() =
        w_.y + h * (tb::a8_1 * k[0] + tb::a8_4 * k[3] + tb::a8_5 * k[4] + tb::a8_6 * k[5] + tb::a8_7 * k[6]);
    rhs_(t + tb::c8 * h, w_.yt, k[7]);
    w_.yt.noalias() = w_.y + h * (tb::a9_1 * k[0] + tb::a9_4 * k[3] + tb::a9_5 * k[4] + tb::a9_6 * k[5] +
                                  tb::a9_7 * k[6] + tb::a9_8 * k[7]);
    rhs_(t + tb::c9 * h, w_.yt, k[8]);
    w_.yt.noalias() = w_.y + h * (tb::a10_1 * k[0] + tb::a10_4 * k[3] + tb::a10_5 * k[4] + tb::a10_6 * k[5] +
                                  tb::a10_7 * k[6] + tb::a10_8 * k[7] + tb::a10_9 * k[8]);
    rhs_(t + tb::c10 * h, w_.yt, k[9]);
    w_.yt.noalias() = w_.y + h * (tb::a11_1 * k[0] + tb::a11_4 * k[3] + tb::a11_5 * k[4] + tb::a11_6 * k[5] +
                                  tb::a11_7 * k[6] + tb::a11_8 * k[7] + tb::a11_9 * k[8] + tb::a11_10 * k[9]);
    rhs_(t + tb::c11 * h, w_.yt, k[10]);
    w_.yt.noalias() = w_.y + h * (tb::a12_1 * k[0] + tb::a12_4 * k[3] + tb::a12_5 * k[4] + tb::a12_6 * k[5] +
                                  tb::a12_7 * k[6] + tb::a12_8 * k[7] + tb::a12_9 * k[8] + tb::a12_10 * k[9] +
                                  tb::a12_11 * k[10]);
    rhs_(t + tb::c12 * h, w_.yt, k[11]);
    w_.bsum.noalias() = tb::a13_1 * k[0] + tb::a13_6 * k[5] + tb::a13_7 * k[6] + tb::a13_8 * k[7] +
                        tb::a13_9 * k[8] + tb::a13_10 * k[9] + tb::a13_11 * k[10] + tb::a13_12 * k[11];

    w_.ynew.noalias() = w_.y + h * w_.bsum;
    w_.nfev += 11;
    const double err = error_norm(h);
    const double fac11 = std::pow(err, expo1);
    double hnew;
    if (err <= 1.0) {
      // Accepted step (Lund stabilisation with beta; Hairer's defaults make it a plain I-controller).
      double fac = s_.beta > 0.0 ? fac11 / std::pow(facold, s_.beta) : fac11;
      fac = std::max(facc2, std::min(facc1, fac / s_.safety));
      hnew = h / fac;
      facold = std::max(err, 1e-4);
      rhs_(t + h, w_.ynew, k[12]);
      ++w_.nfev;
      if (!detail::all_finite(k[12])) {
        info.status = Dop853Status::rhs_failure;
        break;
      }
      ++info.steps;
      double tnew = last ? t_end : t + h;
      bool dense_ready = false;
      bool hit = false;
      if constexpr (!std::is_same_v<Event, Dop853NoEvent>) {
        if (!(event(tnew, static_cast<const Vec&>(w_.ynew)) > 0.0)) {
          // Bracket [0, 1] of s = (t' - t) / h: event > 0 at s = 0 (the previous step end), <= 0 at 1.
          prepare_dense(t, h);
          dense_ready = true;
          double lo = 0.0, hi = 1.0;
          for (int it = 0; it < 60 && hi - lo > 4.0 * uround; ++it) {
            const double mid = 0.5 * (lo + hi);
            interpolate(mid, w_.yt);
            (event(t + mid * h, static_cast<const Vec&>(w_.yt)) > 0.0 ? lo : hi) = mid;
          }
          tnew = t + hi * h;
          hit = true;
        }
      }
      while (io < n_out && (t_out[io] - tnew) * dir <= 0.0 && !(hit && t_out[io] == tnew)) {
        if (t_out[io] == tnew) {
          out(io, tnew, static_cast<const Vec&>(w_.ynew));
        } else {
          if (!dense_ready) {
            prepare_dense(t, h);
            dense_ready = true;
          }
          interpolate((t_out[io] - t) / h, w_.yt);
          out(io, t_out[io], static_cast<const Vec&>(w_.yt));
        }
        ++io;
      }
      info.outputs = io;
      if (hit) {
        info.status = Dop853Status::event;
        info.t_reached = tnew;
        break;
      }
      k[0] = k[12];
      w_.y = w_.ynew;
      t = tnew;
      info.t_reached = t;
      if (last || io == n_out) break;
      if (std::abs(hnew) > h_max) hnew = dir * h_max;
      if (reject) hnew = dir * std::min(std::abs(hnew), std::abs(h));
      reject = false;
    } else {
      // Rejected (a NaN error also lands here: min(facc1, NaN) = facc1 shrinks the step).
      hnew = h / std::min(facc1, fac11 / s_.safety);
      reject = true;
      if (info.steps >= 1) ++info.rejected;
    }
    h = hnew;
  }
  info.rhs_evals = w_.nfev;
  return info;
}

/// Integrate the orbital state (and, with_stm, the variational equations dPhi/dt = A(t) Phi with
/// A = [0 I; da/dr da/dv]) through `times` with DOP853. Accel provides two call forms:
/// accel(t, r, v, a) fills the acceleration (km/s^2) and accel(t, r, v, a, da_dr, da_dv) also its
/// Jacobians (1/s^2, 1/s); VelocityDependent = false skips the da/dv products.
/// times: monotone (non-decreasing or non-increasing), either side of t0 (two arcs from t0).
/// surface_radius (km, >= 0): with R > 0, |r0| must exceed R and an arc reaching |r| = R stops with
/// PropagationStatus::impact, t_reached = the impact time, and the outputs before it; 0: no surface.
/// Throws std::invalid_argument naming the argument on bad input; solver failures are reported in
/// Trajectory::status / message with the states reached so far.
template <bool VelocityDependent = true, class Accel>
Trajectory propagate_dop853_with(const Accel& accel, const Vec6& x0, double t0,
                                 const std::vector<double>& times, const Dop853Settings& settings,
                                 bool with_stm, double surface_radius = 0.0);

/// DOP853 propagation with a ForceModel (see propagate_dop853_with). Units km, km/s, s.
/// @throws std::invalid_argument naming the argument: non-finite x0/t0/times, |r0| = 0 or
///   |r0| <= surface_radius, decreasing times, invalid settings (rtol <= 0, ...), invalid force model.
Trajectory propagate_dop853(const dynamics::ForceModel& force_model, const Vec6& x0, double t0,
                            const std::vector<double>& times, const Dop853Settings& settings, bool with_stm,
                            double surface_radius = 0.0);

/// Throw std::invalid_argument naming the first invalid field of a Dop853Settings.
void dop853_validate_settings(const Dop853Settings& settings);
/// Throw std::invalid_argument naming x0, t0 or times when invalid: validate_orbit_arc_input with
/// kTwoSidedArc (DOP853's rules), kept for existing callers.
inline void dop853_validate_orbit_input(const Vec6& x0, double t0, const std::vector<double>& times) {
  validate_orbit_arc_input(x0, t0, times, kTwoSidedArc, kGravitySingular);
}
/// Throw std::invalid_argument naming surface_radius (< 0 or non-finite) or x0 (|r0| <= surface_radius).
void dop853_validate_surface(const Vec6& x0, double surface_radius);
/// Map a Dop853Status to the Trajectory status set (event -> impact: the orbital wrappers' only event).
PropagationStatus dop853_to_propagation_status(Dop853Status s);

namespace detail {

/// One 6-column c = [p; q] of a variational system: dc/dt = [q; G p (+ H q) (+ source)], with
/// G = da/dr and H = da/dv column-major 3 x 3 (H used when VelocityDependent), source (3) null or
/// the parameter term da/dp. Scalar code on purpose: Eigen's small-product dispatch costs more than
/// the 9 FMAs per column. Shared by the STM (OrbitRhs) and the sensitivity right-hand sides.
template <bool VelocityDependent>
inline void variational_column(const double* G, const double* H, const double* pc, double* dc,
                               const double* source = nullptr) noexcept {
  const double p0 = pc[0], p1 = pc[1], p2 = pc[2], q0 = pc[3], q1 = pc[4], q2 = pc[5];
  double a0 = G[0] * p0 + G[3] * p1 + G[6] * p2;
  double a1 = G[1] * p0 + G[4] * p1 + G[7] * p2;
  double a2 = G[2] * p0 + G[5] * p1 + G[8] * p2;
  if constexpr (VelocityDependent) {
    a0 += H[0] * q0 + H[3] * q1 + H[6] * q2;
    a1 += H[1] * q0 + H[4] * q1 + H[7] * q2;
    a2 += H[2] * q0 + H[5] * q1 + H[8] * q2;
  }
  if (source != nullptr) {
    a0 += source[0];
    a1 += source[1];
    a2 += source[2];
  }
  dc[0] = q0;
  dc[1] = q1;
  dc[2] = q2;
  dc[3] = a0;
  dc[4] = a1;
  dc[5] = a2;
}

template <bool WithStm, bool VelocityDependent, class Accel>
struct OrbitRhs {
  static constexpr int N = WithStm ? 42 : 6;
  using Vec = Eigen::Matrix<double, N, 1>;
  const Accel& accel;
  void operator()(double t, const Vec& y, Vec& dy) const {
    const Vec3 r = y.template head<3>();
    const Vec3 v = y.template segment<3>(3);
    Vec3 a;
    dy.template head<3>() = v;
    if constexpr (!WithStm) {
      accel(t, r, v, a);  // no Jacobians needed without the STM
      dy.template segment<3>(3) = a;
    } else {
      Mat3 da_dr, da_dv;
      accel(t, r, v, a, da_dr, da_dv);
      dy.template segment<3>(3) = a;
      // Phi is stored column-major after the state: per column j, rows 0-2 are d r / d x0_j and rows
      // 3-5 d v / d x0_j, so column j of dPhi/dt is [Phi_v,j; da_dr Phi_r,j (+ da_dv Phi_v,j)].
      for (int j = 0; j < 6; ++j)
        variational_column<VelocityDependent>(da_dr.data(), da_dv.data(), y.data() + 6 + 6 * j,
                                              dy.data() + 6 + 6 * j);
    }
  }
};

template <bool WithStm, bool VelocityDependent, class Accel>
void run_arc(const Accel& accel, const Vec6& x0, double t0, const double* ts, std::size_t n,
             const Dop853Settings& settings, Vec6* states, Mat6* stms, Dop853Info& info,
             double surface_radius) {
  using R = OrbitRhs<WithStm, VelocityDependent, Accel>;
  using Vec = typename R::Vec;
  R rhs{accel};
  Dop853<R::N, R> integ(rhs, settings);
  Vec y0;
  y0.template head<6>() = x0;
  if constexpr (WithStm) {
    Eigen::Map<Mat6>(y0.data() + 6).setIdentity();
  }
  auto out = [&](std::size_t i, double, const Vec& y) {
    states[i] = y.template head<6>();
    if constexpr (WithStm) stms[i] = Eigen::Map<const Mat6>(y.data() + 6);
  };
  if (surface_radius > 0.0) {
    const double r2 = surface_radius * surface_radius;
    info = integ.solve(t0, y0, ts, n, out,
                       [r2](double, const Vec& y) { return y.template head<3>().squaredNorm() - r2; });
  } else {
    info = integ.solve(t0, y0, ts, n, out);
  }
}

}  // namespace detail

namespace detail {

/// The arcs of an orbit propagation from t0 to the requested `times` (any order, either side of t0),
/// shared by propagate_dop853 and propagate_dop853_sensitivity: times >= t0 forward in increasing
/// order, times < t0 backward in decreasing order, the arc holding the first requested time first (so
/// a failure keeps a prefix where possible), the second skipped after a failure.
/// `run_arc(idx, ts) -> Dop853Info` integrates one arc from t0 through ts (ts[j] = times[idx[j]]) and
/// stores its outputs j < info.outputs at idx[j]. Fills tr's status, message ("<who> (<arc> arc):
/// ..."), t_reached and statistics; returns done[i] = 1 for the times reached. Setup-time
/// allocations only (index lists, per-arc times); the stepping loop allocates nothing.
template <class RunArc>
std::vector<char> dop853_two_arcs(const char* who, double t0, const std::vector<double>& times,
                                  double surface_radius, Trajectory& tr, RunArc&& run_arc) {
  const std::size_t n = times.size();
  std::vector<std::size_t> fwd, bwd;
  for (std::size_t i = 0; i < n; ++i) (times[i] >= t0 ? fwd : bwd).push_back(i);
  const bool ascending = n < 2 || times.front() <= times.back();
  if (!ascending) std::reverse(fwd.begin(), fwd.end());
  if (ascending) std::reverse(bwd.begin(), bwd.end());
  std::vector<char> done(n, 0);
  tr.status = PropagationStatus::success;
  tr.t_reached = t0;
  bool failed = false;
  auto arc = [&](const std::vector<std::size_t>& idx, const char* name) {
    if (idx.empty() || failed) return;
    const std::size_t m = idx.size();
    std::vector<double> ts(m);
    for (std::size_t j = 0; j < m; ++j) ts[j] = times[idx[j]];
    const Dop853Info info = run_arc(idx, ts);
    for (std::size_t j = 0; j < info.outputs; ++j) done[idx[j]] = 1;
    tr.stats.steps += info.steps;
    tr.stats.rhs_evals += info.rhs_evals;
    tr.stats.error_test_fails += info.rejected;
    if (info.steps > 0) tr.stats.last_step = info.h_last;
    tr.t_reached = info.t_reached;
    if (info.status == Dop853Status::event) {
      failed = true;
      tr.status = PropagationStatus::impact;
      tr.message = std::string(who) + " (" + name + " arc): impact at t = " + std::to_string(info.t_reached) +
                   " s: |r| reached surface_radius = " + std::to_string(surface_radius) +
                   " km before t = " + std::to_string(ts.back()) + " s";
    } else if (info.status != Dop853Status::success) {
      failed = true;
      tr.status = dop853_to_propagation_status(info.status);
      tr.message = std::string(who) + " (" + name + " arc): " + status_message(info.status) +
                   "; reached t = " + std::to_string(info.t_reached) + " s of " + std::to_string(ts.back()) +
                   " s after " + std::to_string(info.steps) + " steps";
    }
  };
  if (!bwd.empty() && times.front() < t0) {
    arc(bwd, "backward");
    arc(fwd, "forward");
  } else {
    arc(fwd, "forward");
    arc(bwd, "backward");
  }
  return done;
}

}  // namespace detail

template <bool VelocityDependent, class Accel>
Trajectory propagate_dop853_with(const Accel& accel, const Vec6& x0, double t0,
                                 const std::vector<double>& times, const Dop853Settings& settings,
                                 bool with_stm, double surface_radius) {
  validate_orbit_arc_input(x0, t0, times, kTwoSidedArc, kGravitySingular);
  dop853_validate_settings(settings);
  dop853_validate_surface(x0, surface_radius);
  const std::size_t n = times.size();
  std::vector<Vec6> states(n);
  std::vector<Mat6> stms(with_stm ? n : 0);
  Trajectory tr;
  const std::vector<char> done = detail::dop853_two_arcs(
      "propagate_dop853", t0, times, surface_radius, tr,
      [&](const std::vector<std::size_t>& idx, const std::vector<double>& ts) {
        const std::size_t m = idx.size();
        std::vector<Vec6> xs(m);
        std::vector<Mat6> ps(with_stm ? m : 0);
        Dop853Info info;
        if (with_stm)
          detail::run_arc<true, VelocityDependent>(accel, x0, t0, ts.data(), m, settings, xs.data(),
                                                   ps.data(), info, surface_radius);
        else
          detail::run_arc<false, VelocityDependent>(accel, x0, t0, ts.data(), m, settings, xs.data(), nullptr,
                                                    info, surface_radius);
        for (std::size_t j = 0; j < info.outputs; ++j) {
          states[idx[j]] = xs[j];
          if (with_stm) stms[idx[j]] = ps[j];
        }
        return info;
      });
  for (std::size_t i = 0; i < n; ++i) {
    if (!done[i]) continue;
    tr.times.push_back(times[i]);
    tr.states.push_back(states[i]);
    if (with_stm) tr.stms.push_back(stms[i]);
  }
  return tr;
}

}  // namespace satgnc::propagation
