#pragma once
/// @file dop853_arc.hpp
/// Allocation-free single DOP853 arc on a dynamics::ForceModel, writing into caller-owned buffers:
/// the stepping of propagate_dop853 (the same acceleration dispatch and the same detail::run_arc, so
/// the same arithmetic bit for bit) without its Trajectory output, for solvers that propagate inside
/// an allocation-free solve() (od::Dop853StmPropagator under od::BatchEstimator::solve()).
#include <cstddef>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace satgnc::propagation {

/// Integrate x0 = [r km, v km/s] given at t0 (s) through the n output times (s), which must be finite
/// and monotone away from t0 (all >= t0 ascending, or all <= t0 descending), writing states[i] and,
/// when stms is not null, stms[i] = d x(times[i]) / d x0 (the variational equations ride along).
/// No validation and no heap allocation: the caller validates the force model (ForceModel::validate),
/// the settings (dop853_validate_settings) and the input (validate_orbit_arc_input) at setup, and owns
/// the force model's evaluation workspace (do not share one ForceModel between threads here; the
/// Trajectory-returning propagate_dop853 copies it instead). No surface (impact) event.
/// Exceptions of the force model propagate (the stepping itself throws nothing).
/// Returns the integrator's statistics; outputs [0, info.outputs) are written; status success when
/// all n were reached.
Dop853Info propagate_dop853_arc(const dynamics::ForceModel& force_model, const Vec6& x0, double t0,
                                const double* times, std::size_t n, const Dop853Settings& settings,
                                Vec6* states, Mat6* stms);

}  // namespace satgnc::propagation
