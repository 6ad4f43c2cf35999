// ADMM with a Riccati step for L1 / group-L2 / box-constrained LTV guidance (see admm.hpp): status
// messages, settings validation and the public AdmmSolver, which forwards to detail::AdmmWorkspace.
#include "satgnc/guidance/admm.hpp"

#include <cmath>
#include <limits>
#include <memory>

#include "detail/admm_workspace.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::guidance {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void AdmmSettings::validate() const {
  using core::require;
  core::require_positive(rho, "rho");
  require(max_iterations >= 1, "max_iterations", "must be >= 1");
  core::require_nonnegative(eps_abs, "eps_abs");
  core::require_nonnegative(eps_rel, "eps_rel");
  require(stopping == StoppingRule::kPaper || eps_abs > 0.0 || eps_rel > 0.0, "eps_abs/eps_rel",
          "at least one must be > 0 with the residual stopping rule");
  core::require_positive(paper_eps, "paper_eps");
  require(std::isfinite(relaxation) && relaxation > 0.0 && relaxation < 2.0, "relaxation",
          "must be in (0, 2)", "1.6 is a good default, 1 disables over-relaxation");
  require(adaptive_rho_interval >= 1, "adaptive_rho_interval", "must be >= 1");
  require(std::isfinite(adaptive_rho_tolerance) && adaptive_rho_tolerance >= 1.0, "adaptive_rho_tolerance",
          "must be >= 1");
  core::require_positive(rho_min, "rho_min");
  core::require_positive(rho_max, "rho_max");
  require(rho_min <= rho_max, "rho_min", "must be <= rho_max");
  require(polish_interval >= 1, "polish_interval", "must be >= 1");
  require(polish_max_free >= 0, "polish_max_free", "must be >= 0");
  require(polish_swaps >= 0, "polish_swaps", "must be >= 0");
  core::require_positive(polish_tolerance, "polish_tolerance");
  require(paper_global_rescale_iterations >= 0, "paper_global_rescale_iterations", "must be >= 0");
  core::require_nonnegative(eps_gap, "eps_gap");
  core::require_nonnegative(gap_floor, "gap_floor");
  core::require_nonnegative(terminal_tolerance, "terminal_tolerance");
  require(gap_check_interval >= 1, "gap_check_interval", "must be >= 1");
  require(std::isfinite(inaccurate_factor) && inaccurate_factor >= 1.0, "inaccurate_factor", "must be >= 1");
  core::require_nonnegative(time_limit, "time_limit");
  core::require_positive(max_workspace_bytes, "max_workspace_bytes");
  require(infeasibility_check_interval >= 1, "infeasibility_check_interval", "must be >= 1");
  require(method == AdmmMethod::kAdmm || method == AdmmMethod::kAdmmIpm || method == AdmmMethod::kIpm,
          "method", "must be admm, admm_ipm or ipm");
  require(ipm_after >= 0, "ipm_after", "must be >= 0");
  require(ipm_max_iterations >= 1, "ipm_max_iterations", "must be >= 1");
  core::require_positive(ipm_tolerance, "ipm_tolerance");
}

// ---- AdmmSolver: the public face; every datum and step lives in detail::AdmmWorkspace.

AdmmSolver::AdmmSolver(const LtvProblem& problem, const AdmmSettings& settings)
    : ws_(std::make_unique<detail::AdmmWorkspace>(problem, settings)) {}

AdmmSolver::~AdmmSolver() = default;
AdmmSolver::AdmmSolver(AdmmSolver&&) noexcept = default;
AdmmSolver& AdmmSolver::operator=(AdmmSolver&&) noexcept = default;

const AdmmResult& AdmmSolver::solve() noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  return ws_->solve();
}

void AdmmSolver::warm_start(const Eigen::Ref<const MatrixXd>& Y, const Eigen::Ref<const MatrixXd>& Lambda) {
  ws_->warm_start(Y, Lambda);
}

void AdmmSolver::cold_start() noexcept { ws_->warm_ = false; }

void AdmmSolver::set_x0(const Eigen::Ref<const VectorXd>& x0) { ws_->set_x0(x0); }

void AdmmSolver::set_xf(const Eigen::Ref<const VectorXd>& xf) { ws_->set_xf(xf); }

void AdmmSolver::update_settings(const AdmmSettings& settings) { ws_->update_settings(settings); }

bool AdmmSolver::set_time_limit(double seconds) noexcept {
  if (!(seconds >= 0.0 && seconds < std::numeric_limits<double>::infinity())) return false;
  ws_->set_.time_limit = seconds;
  return true;
}

const AdmmResult& AdmmSolver::result() const { return ws_->res_; }
const AdmmSettings& AdmmSolver::settings() const { return ws_->set_; }
const LtvProblem& AdmmSolver::problem() const { return ws_->orig_; }
const Eigen::VectorXd& AdmmSolver::control_scaling() const { return ws_->du_; }
double AdmmSolver::cost_scaling() const { return ws_->cscale_; }
const RiccatiSolver& AdmmSolver::riccati() const { return *ws_->ric_; }
const Eigen::MatrixXd& AdmmSolver::dual_estimate() const { return ws_->Gd_; }
int AdmmSolver::nx() const { return ws_->nx_; }
int AdmmSolver::nu() const { return ws_->nu_; }
int AdmmSolver::horizon() const { return ws_->N_; }

double AdmmSolver::objective_of(const Eigen::Ref<const MatrixXd>& U) const { return ws_->objective_of(U); }

bool AdmmSolver::update_dynamics(const std::vector<MatrixXd>& A, const std::vector<MatrixXd>& B,
                                 const std::vector<VectorXd>& c) noexcept {
  return ws_->update_dynamics(A, B, c);
}

}  // namespace satgnc::guidance
