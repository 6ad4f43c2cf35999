#pragma once
/// @file ensemble.hpp
/// Ensemble propagation: many initial states x0_k = [r km, v km/s] (inertial frame of the force
/// model, e.g. GCRF) propagated with the same force model, epoch t0 (s) and output times (s), with
/// DOP853 (dop853.hpp) and optionally the 6x6 STMs. For Monte Carlo runs, convergence maps and
/// campaigns.
///
/// Settings / workspace / result: EnsemblePropagator validates its settings and starts a fixed pool
/// of `threads - 1` worker threads (std::thread) once; every propagate() call hands the members out
/// to the pool and the calling thread (dynamic scheduling over member indices) and waits for them.
/// Each member has its own step-size control and its own status: one failing member (impact,
/// step budget, |r| = 0) never stops or alters the others. With settings.simd (default) 8 members
/// share the SIMD lanes of one integrator, each lane with its own step control; without it each
/// member runs exactly the arithmetic of propagate_dop853 (bitwise equal). Either way a member's
/// result does not depend on the number of threads or on the other members.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::propagation {

/// Settings of an ensemble propagation.
struct EnsembleSettings {
  /// Per-member DOP853 settings (rtol, atol km and km/s, max_steps per member, ...). The defaults
  /// are those of Dop853Settings (kDefaultOrbitRtol, kDefaultOrbitAtol).
  Dop853Settings integrator;
  bool with_stm = true;  ///< also integrate the 36 variational equations (6x6 STM per output)
  int threads = 1;       ///< threads used by propagate(), including the caller's: >= 1 (at most 256)
  /// Radius of the body's surface, km (>= 0): a member starting at or below it gets the status
  /// impact with no output; a member reaching it stops with impact at t_reached. 0: no surface.
  double surface_radius = 0.0;
  /// Integrate 8 members at once, one per SIMD lane (AVX-512 when the CPU has it, else the baseline
  /// instruction set), each lane with its own step-size control. Results then agree with
  /// propagate_dop853 to rounding (sums in another order, fused multiply-adds), not bitwise; they still
  /// do not depend on the number of threads or on the other members. A lane that fails is re-run alone
  /// by the scalar path, so statuses and messages are those of the single-arc call. false: one member
  /// at a time, bitwise equal to propagate_dop853.
  bool simd = true;
  /// With simd: use the baseline (SSE2) build of the lane integrator even on a CPU with AVX-512. The
  /// AVX-512 build fuses multiply-adds, so its last bits differ from the baseline build's: set this
  /// for results that are the same on every x86-64 machine (and to test the baseline kernel).
  bool simd_portable = false;
  /// Throw std::invalid_argument("field: rule") on any invalid value (integrator fields by name).
  void validate() const;
};

/// Result of an ensemble propagation: K members times n output times.
struct EnsembleResult {
  std::size_t members = 0;    ///< K
  std::vector<double> times;  ///< the n requested output times, s
  /// States [r km, v km/s], member-major: states[k * n + i] is member k at times[i]. Entries past a
  /// failed member's outputs[k] are NaN.
  std::vector<Vec6> states;
  /// STMs d x_k(t_i) / d x_k(t0), same layout as states; empty without the STM.
  std::vector<Mat6> stms;
  std::vector<PropagationStatus> status;  ///< per member: success or why it stopped
  std::vector<std::size_t> outputs;       ///< per member: number of outputs delivered (n on success)
  std::vector<double> t_reached;          ///< per member: last time reached (impact time on impact), s
  std::vector<PropagationStats> stats;    ///< per member: steps, rhs_evals, rejected steps
  std::vector<std::string> messages;      ///< per member: empty on success, else why it stopped

  /// Number of members whose status is success.
  std::size_t succeeded() const;
};

/// Ensemble propagator bound to one force model, with its thread pool started once.
class EnsemblePropagator {
 public:
  /// Validate the force model and settings (std::invalid_argument naming the field) and start the
  /// `threads - 1` worker threads (std::system_error if the system refuses a thread).
  explicit EnsemblePropagator(const dynamics::ForceModel& model, const EnsembleSettings& settings = {});
  ~EnsemblePropagator();
  EnsemblePropagator(const EnsemblePropagator&) = delete;
  EnsemblePropagator& operator=(const EnsemblePropagator&) = delete;

  /// Propagate every x0[k] (km, km/s) from t0 (s) to every time in `times` (s). Throws
  /// std::invalid_argument naming the argument: x0 empty ("x0: must hold at least one state"), a
  /// non-finite or too large component ("x0[k]: ..."), t0 non-finite, times empty, non-finite, not
  /// strictly monotone or on both sides of t0. Physical failures of one member (|r0| = 0, start
  /// below the surface, impact, step budget) are that member's status, not an exception.
  EnsembleResult propagate(const std::vector<Vec6>& x0, double t0, const std::vector<double>& times);

  /// Same, writing into `out` (its vectors keep their capacity: no allocation once it has the
  /// capacity, except the message of a failed member). x0 points to `members` states.
  void propagate(const Vec6* x0, std::size_t members, double t0, const std::vector<double>& times,
                 EnsembleResult& out);

  const dynamics::ForceModel& model() const;  ///< the force model (a copy)
  const EnsembleSettings& settings() const;   ///< the validated settings
  int threads() const;                        ///< threads used, including the caller's

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience: build an EnsemblePropagator and propagate once.
EnsembleResult propagate_ensemble(const dynamics::ForceModel& model, const std::vector<Vec6>& x0, double t0,
                                  const std::vector<double>& times, const EnsembleSettings& settings = {});

}  // namespace satgnc::propagation
