#pragma once
// Private helpers of the guidance room (not installed).
#include <Eigen/Core>

namespace satgnc::guidance::detail {

/// 1/2 (x - t)' W (x - t) by loops: W * (x - t) inside an expression would allocate a temporary,
/// and the solvers call this inside their allocation-free solve().
inline double half_weighted_error(const Eigen::MatrixXd& W, const Eigen::Ref<const Eigen::VectorXd>& x,
                                  const Eigen::VectorXd& t) noexcept {
  const Eigen::Index n = x.size();
  double c = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double ej = x(j) - t(j);
    if (ej == 0.0) continue;
    double row = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) row += W(i, j) * (x(i) - t(i));
    c += ej * row;
  }
  return 0.5 * c;
}

}  // namespace satgnc::guidance::detail
