#pragma once
// Private to the od room (not installed): Householder QR in place on storage sized at setup.
//
// Eigen's HouseholderQR::compute() allocates when the matrix has fewer rows than columns (the
// six-point problem: [J | r] is 6 x 7): its blocked algorithm then updates the trailing column by
// apply_block_householder_on_the_left, whose triangular factor T and product temporaries are
// dynamic-size matrices created on every call (15 / 15 / 42 mallocs per OD solve for newton /
// gauss_newton / LM, measured on branch dedupe). householder_qr_inplace below is the same algorithm
// with those matrices in a workspace: the unblocked loop on the leading min(rows, cols) columns,
// then, when rows < cols, the block reflector applied to the trailing columns. It uses Eigen's own
// expression types and its internal make_block_householder_triangular_factor, so the result is
// bit-identical to HouseholderQR::compute() of the Eigen it is compiled with (test_od_solver.cpp,
// OdQr.BitIdenticalToEigenHouseholderQr, checks every shape 1..40 x 6..7), and no allocation
// happens after HouseholderQrWorkspace::resize.
#include <Eigen/Core>
#include <Eigen/Householder>
#include <algorithm>

namespace satgnc::od::detail {

/// Storage of householder_qr_inplace for one rows x cols shape.
struct HouseholderQrWorkspace {
  Eigen::VectorXd tau;   ///< reflector coefficients (min(rows, cols)): HouseholderQR::hCoeffs()
  Eigen::VectorXd temp;  ///< cols: work vector of the reflector applications
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> T;  ///< block reflector factor
  Eigen::MatrixXd tmp, tmp2;  ///< min(rows, cols) x (cols - min(rows, cols)): V^T A and T^T V^T A

  /// Size for a rows x cols matrix (allocates).
  void resize(Eigen::Index rows, Eigen::Index cols) {
    const Eigen::Index size = std::min(rows, cols);
    tau.setZero(size);
    temp.setZero(cols);
    T.setZero(size, size);
    tmp.setZero(size, cols - size);
    tmp2.setZero(size, cols - size);
  }
};

/// QR of a (rows x cols as given to w.resize) in place, in Eigen's HouseholderQR storage: R on and
/// above the diagonal, the essential parts of the reflectors below, their coefficients in w.tau.
/// No allocation.
inline void householder_qr_inplace(Eigen::MatrixXd& a, HouseholderQrWorkspace& w) {
  const Eigen::Index rows = a.rows(), cols = a.cols(), size = std::min(rows, cols);
  // HouseholderQR's one block (its block size is 48; here size <= 7): unblocked on the leading columns
  Eigen::Block<Eigen::MatrixXd> v = a.block(0, 0, rows, size);
  Eigen::Block<Eigen::VectorXd, Eigen::Dynamic, 1> h = w.tau.segment(0, size);
  double* temp = w.temp.data();
  for (Eigen::Index k = 0; k < size; ++k) {
    const Eigen::Index remaining_rows = rows - k;
    const Eigen::Index remaining_cols = size - k - 1;
    double beta = 0.0;
    v.col(k).tail(remaining_rows).makeHouseholderInPlace(h.coeffRef(k), beta);
    v.coeffRef(k, k) = beta;
    v.bottomRightCorner(remaining_rows, remaining_cols)
        .applyHouseholderOnTheLeft(v.col(k).tail(remaining_rows - 1), h.coeffRef(k), temp + k + 1);
  }
  if (cols == size) return;
  // Trailing columns: A -= V T^T V^T A (Eigen's apply_block_householder_on_the_left, backward),
  // with T and the temporaries in the workspace.
  Eigen::Block<Eigen::MatrixXd> trail = a.block(0, size, rows, cols - size);
  Eigen::internal::make_block_householder_triangular_factor(w.T, v, h.conjugate());
  const Eigen::TriangularView<const Eigen::Block<Eigen::MatrixXd>, Eigen::UnitLower> V(v);
  w.tmp.noalias() = V.adjoint() * trail;
  w.tmp2.noalias() = w.T.triangularView<Eigen::Upper>().adjoint() * w.tmp;
  w.tmp = w.tmp2;
  trail.noalias() -= V * w.tmp;
}

}  // namespace satgnc::od::detail
