// Ensemble propagation: DOP853 per member (the arithmetic of propagate_dop853), members handed out to
// a fixed pool of std::threads started once by the EnsemblePropagator constructor.
#include "satgnc/propagation/ensemble.hpp"

#include <atomic>
#include <cmath>
#include <condition_variable>
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#endif
#include <cstdint>
#include <limits>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>

#include "detail/force_model_accel.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/propagation/dop853.hpp"

// The lane integrator, compiled twice: for the baseline instruction set and for AVX-512 (chosen at
// run time by the CPU's support; the library itself keeps baseline flags).
// -Wpsabi: a 64-byte vector passed by value in the baseline build is an ABI note, not a defect (these
// functions are internal to this file).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
namespace satgnc::propagation::detail {
namespace lanes_generic {
#include "detail/dop853_lanes.inc"
}  // namespace lanes_generic
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define SATGNC_LANES_AVX512 1
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")
#define SATGNC_LANES_AVX512_REGION 1
namespace lanes_avx512 {
#include "detail/dop853_lanes.inc"
}  // namespace lanes_avx512
#undef SATGNC_LANES_AVX512_REGION
#pragma GCC pop_options
#endif
}  // namespace satgnc::propagation::detail
#pragma GCC diagnostic pop

namespace satgnc::propagation {

void EnsembleSettings::validate() const {
  dop853_validate_settings(integrator);
  core::require(
      threads >= 1 && threads <= 256, "threads",
      "must lie in [1, 256] (threads used, including the caller's), got " + std::to_string(threads));
  core::require_nonnegative(surface_radius, "surface_radius");
}

std::size_t EnsembleResult::succeeded() const {
  std::size_t n = 0;
  for (PropagationStatus s : status) n += s == PropagationStatus::success ? 1 : 0;
  return n;
}

namespace {

// One propagate() call: what every thread needs to run members.
struct Job {
  // One copy of the force model per thread (index 0: the calling thread): a gravity field evaluates
  // into a workspace of its own, so two threads must never share one model.
  const dynamics::ForceModel* models = nullptr;
  const EnsembleSettings* settings = nullptr;
  const Vec6* x0 = nullptr;
  std::size_t members = 0;
  double t0 = 0.0;
  const std::vector<double>* times = nullptr;
  EnsembleResult* out = nullptr;
  std::atomic<std::size_t> next{0};
};

std::string member_prefix(std::size_t k) { return "member " + std::to_string(k) + ": "; }

// Propagate member k into its slots of job.out. Never throws (a failure becomes the member's status).
void run_member(Job& job, const dynamics::ForceModel& fm, std::size_t k) noexcept {
  EnsembleResult& out = *job.out;
  const std::vector<double>& ts = *job.times;
  const std::size_t n = ts.size();
  const EnsembleSettings& s = *job.settings;
  Vec6* states = out.states.data() + k * n;
  Mat6* stms = s.with_stm ? out.stms.data() + k * n : nullptr;
  const Vec6& x = job.x0[k];
  PropagationStatus status = PropagationStatus::success;
  Dop853Info info;
  info.t_reached = job.t0;
  try {
    const double r0 = x.head<3>().norm();
    if (!(r0 > 0.0)) {
      status = PropagationStatus::rhs_failure;
      out.messages[k] = member_prefix(k) + "|r0| = 0 (" + kGravitySingular + "); no output";
    } else if (s.surface_radius > 0.0 && !(r0 > s.surface_radius)) {
      status = PropagationStatus::impact;
      out.messages[k] = member_prefix(k) + "starts at or below the surface: |r0| = " + std::to_string(r0) +
                        " km <= surface_radius = " + std::to_string(s.surface_radius) + " km; no output";
    } else {
      detail::with_force_model_accel(fm, [&](const auto& accel, auto velocity_dependent) {
        constexpr bool vd = decltype(velocity_dependent)::value;
        if (s.with_stm)
          detail::run_arc<true, vd>(accel, x, job.t0, ts.data(), n, s.integrator, states, stms, info,
                                    s.surface_radius);
        else
          detail::run_arc<false, vd>(accel, x, job.t0, ts.data(), n, s.integrator, states, nullptr, info,
                                     s.surface_radius);
      });
      if (info.status == Dop853Status::event) {
        status = PropagationStatus::impact;
        out.messages[k] = member_prefix(k) + "impact at t = " + std::to_string(info.t_reached) +
                          " s: |r| reached surface_radius = " + std::to_string(s.surface_radius) + " km";
      } else if (info.status != Dop853Status::success) {
        status = dop853_to_propagation_status(info.status);
        out.messages[k] = member_prefix(k) + status_message(info.status) +
                          "; reached t = " + std::to_string(info.t_reached) + " s of " +
                          std::to_string(ts.back()) + " s after " + std::to_string(info.steps) + " steps";
      } else {
        out.messages[k].clear();
      }
    }
  } catch (...) {  // only std::bad_alloc from a message can land here
    status = PropagationStatus::solver_failure;
  }
  const std::size_t got = status == PropagationStatus::success ? n : std::min<std::size_t>(info.outputs, n);
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = got; i < n; ++i) {
    states[i].setConstant(nan);
    if (stms != nullptr) stms[i].setConstant(nan);
  }
  out.status[k] = status;
  out.outputs[k] = got;
  out.t_reached[k] = info.t_reached;
  PropagationStats& st = out.stats[k];
  st = PropagationStats();
  st.steps = info.steps;
  st.rhs_evals = info.rhs_evals;
  st.error_test_fails = info.rejected;
  st.last_step = info.steps > 0 ? info.h_last : 0.0;
}

// The member is valid for the lane path (else run_member gives its status).
bool lane_ready(const Job& job, std::size_t k) {
  const double r0 = job.x0[k].head<3>().norm();
  return r0 > 0.0 && (job.settings->surface_radius <= 0.0 || r0 > job.settings->surface_radius);
}

// Whether this CPU runs the AVX-512 build of the lane integrator.
bool cpu_has_avx512() {
#ifdef SATGNC_LANES_AVX512
  static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
  return has;
#else
  return false;
#endif
}

template <class NS_Lane, class LaneAccel, bool WithStm, bool Vd>
void run_lanes_with(Job& job, const dynamics::ForceModel& fm, std::size_t first, std::size_t count,
                    const LaneAccel& accel) {
  // NS_Lane is a tag carrying the lane namespace's types (see LanesOf below).
  using Integrator = typename NS_Lane::template Integrator<WithStm, Vd, LaneAccel>;
  using LaneOut = typename NS_Lane::LaneOut;
  using LaneInfo = typename NS_Lane::LaneInfo;
  constexpr int L = NS_Lane::kLanes;
  EnsembleResult& out = *job.out;
  const std::size_t n = job.times->size();
  Vec6 x0[L];
  bool active[L];
  LaneOut lo;
  for (int l = 0; l < L; ++l) {
    const std::size_t k = first + static_cast<std::size_t>(l);
    active[l] = static_cast<std::size_t>(l) < count && lane_ready(job, k);
    x0[l] = active[l] ? job.x0[k] : Vec6::Zero();
    lo.states[l] = active[l] ? out.states.data() + k * n : nullptr;
    lo.stms[l] = active[l] && WithStm ? out.stms.data() + k * n : nullptr;
  }
  LaneInfo info;
  Integrator integ(accel, job.settings->integrator);
  integ.run(x0, active, job.t0, job.times->data(), n, job.settings->surface_radius, lo, info);
  for (int l = 0; l < L; ++l) {
    if (static_cast<std::size_t>(l) >= count) break;
    const std::size_t k = first + static_cast<std::size_t>(l);
    if (!active[l] || !info.ok[l]) {
      run_member(job, fm, k);  // anything but a clean success: the scalar path, exactly as a single arc
      continue;
    }
    out.status[k] = PropagationStatus::success;
    out.outputs[k] = n;
    out.t_reached[k] = info.t_reached[l];
    out.messages[k].clear();
    PropagationStats& st = out.stats[k];
    st = PropagationStats();
    st.steps = info.steps[l];
    st.rhs_evals = info.rhs_evals[l];
    st.error_test_fails = info.rejected[l];
    st.last_step = info.h_last[l];
  }
}

// Type tags exposing each lane namespace to the templates above.
template <bool Avx512>
struct LanesOf;
template <>
struct LanesOf<false> {
  static constexpr int kLanes = detail::lanes_generic::kLanes;
  using LaneOut = detail::lanes_generic::LaneOut;
  using LaneInfo = detail::lanes_generic::LaneInfo;
  using PointMassJ2 = detail::lanes_generic::LanePointMassJ2;
  template <class A>
  using Scalar = detail::lanes_generic::LaneScalar<A>;
  template <bool S, bool V, class A>
  using Integrator = detail::lanes_generic::LaneDop853<S, V, A>;
};
#ifdef SATGNC_LANES_AVX512
template <>
struct LanesOf<true> {
  static constexpr int kLanes = detail::lanes_avx512::kLanes;
  using LaneOut = detail::lanes_avx512::LaneOut;
  using LaneInfo = detail::lanes_avx512::LaneInfo;
  using PointMassJ2 = detail::lanes_avx512::LanePointMassJ2;
  template <class A>
  using Scalar = detail::lanes_avx512::LaneScalar<A>;
  template <bool S, bool V, class A>
  using Integrator = detail::lanes_avx512::LaneDop853<S, V, A>;
};
#endif

// ForceModel as of this file: mu, optional J2, optional exponential drag, gravity field, third
// bodies, SRP, atmosphere drag, the epoch and the ephemeris (ERFA node cache, or a JPL DE file with its
// TDB nodes: only third bodies / SRP / drag read it, all refused below). A new term changes the
// size and stops the build here: the point-mass / J2 lane kernel below must then learn to refuse a model
// holding it (detail::point_mass_j2_only).
static_assert(sizeof(dynamics::ForceModel) == 768,
              "ForceModel gained a member: update the lane fast paths in ensemble.cpp and "
              "force_model_accel.hpp, then this size");

template <bool Avx512>
void run_lanes(Job& job, const dynamics::ForceModel& fm, std::size_t first, std::size_t count) {
  using NS = LanesOf<Avx512>;
  const bool stm = job.settings->with_stm;
  if (detail::point_mass_j2_only(fm)) {  // point mass, or point mass + J2: the vectorized kernel
    typename NS::PointMassJ2 acc{fm.mu, fm.j2.has_value(), 0.0};
    if (fm.j2) acc.j2_coef = -1.5 * fm.j2->j2 * fm.j2->mu * fm.j2->radius * fm.j2->radius;
    if (stm)
      run_lanes_with<NS, decltype(acc), true, false>(job, fm, first, count, acc);
    else
      run_lanes_with<NS, decltype(acc), false, false>(job, fm, first, count, acc);
    return;
  }
  detail::with_force_model_accel(fm, [&](const auto& accel, auto velocity_dependent) {
    constexpr bool vd = decltype(velocity_dependent)::value;
    const typename NS::template Scalar<std::decay_t<decltype(accel)>> acc{accel};
    if (stm)
      run_lanes_with<NS, decltype(acc), true, vd>(job, fm, first, count, acc);
    else
      run_lanes_with<NS, decltype(acc), false, vd>(job, fm, first, count, acc);
  });
}

void run_job(Job& job, std::size_t slot) noexcept {
  const dynamics::ForceModel& fm = job.models[slot];
  const bool lanes = job.settings->simd && job.times->back() != job.t0;
  if (!lanes) {
    for (;;) {
      const std::size_t k = job.next.fetch_add(1, std::memory_order_relaxed);
      if (k >= job.members) return;
      run_member(job, fm, k);
    }
  }
  constexpr std::size_t L = detail::lanes_generic::kLanes;
  const bool avx512 = !job.settings->simd_portable && cpu_has_avx512();
  for (;;) {
    const std::size_t b = job.next.fetch_add(1, std::memory_order_relaxed);
    const std::size_t first = b * L;
    if (first >= job.members) return;
    const std::size_t count = std::min(L, job.members - first);
#ifdef SATGNC_LANES_AVX512
    if (avx512) {
      run_lanes<true>(job, fm, first, count);
      continue;
    }
#endif
    (void)avx512;
    run_lanes<false>(job, fm, first, count);
  }
}

}  // namespace

struct EnsemblePropagator::Impl {
  dynamics::ForceModel model;
  std::vector<dynamics::ForceModel> models;  // one copy per thread, made at setup
  EnsembleSettings settings;
  std::vector<std::thread> workers;
  std::mutex mu;
  std::condition_variable start_cv, done_cv;
  std::uint64_t generation = 0;  // incremented per job; a worker runs each generation once
  std::size_t active = 0;        // workers still inside the current job
  bool stop = false;
  Job* job = nullptr;

  void worker_loop(std::size_t slot) {
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mu);
    for (;;) {
      start_cv.wait(lock, [&] { return stop || generation != seen; });
      if (stop) return;
      seen = generation;
      Job* j = job;
      lock.unlock();
      run_job(*j, slot);
      lock.lock();
      if (--active == 0) done_cv.notify_one();
    }
  }

  void run(Job& j) {
    if (workers.empty()) {
      run_job(j, 0);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mu);
      job = &j;
      active = workers.size();
      ++generation;
    }
    start_cv.notify_all();
    run_job(j, 0);
    std::unique_lock<std::mutex> lock(mu);
    done_cv.wait(lock, [&] { return active == 0; });
    job = nullptr;
  }

  void shutdown() {
    {
      std::lock_guard<std::mutex> lock(mu);
      stop = true;
    }
    start_cv.notify_all();
    for (std::thread& t : workers)
      if (t.joinable()) t.join();
    workers.clear();
  }
};

EnsemblePropagator::EnsemblePropagator(const dynamics::ForceModel& model, const EnsembleSettings& settings)
    : impl_(std::make_unique<Impl>()) {
  model.validate();
  settings.validate();
  impl_->model = model;
  impl_->settings = settings;
  impl_->models.assign(static_cast<std::size_t>(settings.threads), model);
  try {
    impl_->workers.reserve(static_cast<std::size_t>(settings.threads - 1));
    for (int i = 1; i < settings.threads; ++i)
      impl_->workers.emplace_back([this, i] { impl_->worker_loop(static_cast<std::size_t>(i)); });
  } catch (...) {
    impl_->shutdown();
    throw;
  }
}

EnsemblePropagator::~EnsemblePropagator() {
  if (impl_) impl_->shutdown();
}

const dynamics::ForceModel& EnsemblePropagator::model() const { return impl_->model; }
const EnsembleSettings& EnsemblePropagator::settings() const { return impl_->settings; }
int EnsemblePropagator::threads() const { return static_cast<int>(impl_->workers.size()) + 1; }

EnsembleResult EnsemblePropagator::propagate(const std::vector<Vec6>& x0, double t0,
                                             const std::vector<double>& times) {
  EnsembleResult out;
  propagate(x0.data(), x0.size(), t0, times, out);
  return out;
}

void EnsemblePropagator::propagate(const Vec6* x0, std::size_t members, double t0,
                                   const std::vector<double>& times, EnsembleResult& out) {
  if (members == 0 || x0 == nullptr) core::require(false, "x0", "must hold at least one state (K >= 1)");
  for (std::size_t k = 0; k < members; ++k) {  // names are built only on failure (no allocation)
    if (!x0[k].allFinite())
      core::require(false, "x0[" + std::to_string(k) + "]", "must be finite (no NaN or Inf)");
    if (!(x0[k].cwiseAbs().maxCoeff() < kMaxStateComponent))
      core::require(false, "x0[" + std::to_string(k) + "]",
                    "every component must be below 1e100 (km, km/s): |r|^3 overflows double precision");
  }
  // Times: the CVODES rules (non-empty, finite, strictly monotone, one side of t0), checked with a
  // valid stand-in state (the members were checked above; |r0| = 0 is a member's status).
  validate_orbit_arc_input(Vec6(1.0, 0.0, 0.0, 0.0, 0.0, 0.0), t0, times, kOneSidedArc, kGravitySingular);
  const std::size_t n = times.size();
  const bool stm = impl_->settings.with_stm;
  out.members = members;
  out.times.assign(times.begin(), times.end());
  out.states.resize(members * n);
  out.stms.resize(stm ? members * n : 0);
  out.status.assign(members, PropagationStatus::unsolved);
  out.outputs.assign(members, 0);
  out.t_reached.assign(members, t0);
  out.stats.resize(members);
  out.messages.resize(members);
  Job job;
  job.models = impl_->models.data();
  job.settings = &impl_->settings;
  job.x0 = x0;
  job.members = members;
  job.t0 = t0;
  job.times = &times;
  job.out = &out;
  // The whole job runs inside one no-allocation scope of the calling thread (Eigen's switch is one
  // process-wide flag: set here once, the workers' own scopes in Dop853::solve save and restore the
  // same value, so no thread can leave it changed).
  SATGNC_NO_MALLOC_SCOPE;
  impl_->run(job);
}

EnsembleResult propagate_ensemble(const dynamics::ForceModel& model, const std::vector<Vec6>& x0, double t0,
                                  const std::vector<double>& times, const EnsembleSettings& settings) {
  EnsemblePropagator p(model, settings);
  return p.propagate(x0, t0, times);
}

}  // namespace satgnc::propagation
