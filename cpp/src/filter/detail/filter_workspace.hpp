#pragma once
// Private: every buffer of filter::KalmanFilter, sized once in the constructor (pimpl), and the
// step kernels shared by kalman_filter.cpp (EKF, Joseph / conventional / iterated), ud.cpp (Bierman
// and Thornton) and ukf.cpp (sigma points).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <array>

#include "satgnc/filter/kalman_filter.hpp"

namespace satgnc::filter::detail {

constexpr int kM = kMaxMeasurementDim;
/// m x m (m <= kM) matrices without heap storage.
using SmallMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kM, kM>;
/// m vectors without heap storage.
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kM, 1>;

struct FilterWorkspace {
  ProcessModel* process = nullptr;
  MeasurementFunction* measurement = nullptr;
  FilterSettings settings;
  FilterProblem problem;
  int n = 0;
  int nc = 0;
  bool has_consider = false;  // any consider state (consider_count or consider_states)
  Eigen::VectorXd cmask;      // n: 1 estimated, 0 consider (gain rows multiplied by it)
  int seen = 0;               // update() calls since initialize() (warm_up_records)
  std::array<double, kM> gate{};

  // on-board state
  Eigen::VectorXd x;
  Eigen::MatrixXd P;  // joseph / conventional / ukf: the covariance; ud: formed by covariance()
  Eigen::MatrixXd U;  // ud: unit upper triangular factor
  Eigen::VectorXd d;  // ud: diagonal factor
  double t = 0.0;
  bool have_first = false;
  double t_first = 0.0;
  StepRecord last;
  Eigen::MatrixXd last_phi;

  // predict scratch
  Eigen::VectorXd x1;
  Eigen::MatrixXd phi, qd, T, T2;
  Eigen::MatrixXd W;   // ud: n x 2n MWGS array
  Eigen::VectorXd dw;  // ud: 2n weights
  Eigen::MatrixXd G;   // ud: unit upper factor of Qd
  Eigen::VectorXd dq;  // ud: diagonal factor of Qd
  Eigen::MatrixXd qc;  // ud: copy of Qd factorized in place

  // update scratch
  Eigen::VectorXd z;  // kM
  Eigen::MatrixXd H;  // kM x n
  Eigen::VectorXd xbar, xi, xn, ph, kv, wv, f, v, b;
  Eigen::MatrixXd PHt, K, TH;  // n x kM
  SmallMat S, Sinv;
  SmallVec y, r;
  Eigen::LLT<SmallMat> sllt;
  Eigen::LLT<Eigen::MatrixXd> llt;

  // ukf
  Eigen::MatrixXd X, Xp;  // n x (2n + 1)
  Eigen::MatrixXd Z;      // kM x (2n + 1)
  Eigen::VectorXd wm, wc;
  double ukf_c = 0.0;  // sqrt(n + lambda)

  FilterResult result;

  void allocate();
  void symmetrize() noexcept;
  bool covariance_pd() noexcept;
  void form_covariance() noexcept;  // ud: P = U D U'
  void ud_factor(const Eigen::MatrixXd& a, Eigen::MatrixXd& u, Eigen::VectorXd& dd,
                 Eigen::MatrixXd& work) noexcept;
  FilterStatus thornton() noexcept;  // ud time update with phi, qd
  FilterStatus bierman(int j, double variance, double residual) noexcept;
  FilterStatus ukf_predict(double t1) noexcept;
  FilterStatus ukf_update(const MeasurementRecord& rec, int m, StepRecord& out) noexcept;
  FilterStatus innovation(const MeasurementRecord& rec, int m, StepRecord& out) noexcept;  // S, y, nis
  // From S (R on its diagonal) and y: the LLT of S, the NIS and the per-component statistics (EKF, UKF).
  FilterStatus innovation_statistics(int m, StepRecord& out) noexcept;
  EditFlag gate_decision(const MeasurementRecord& rec, int m, StepRecord& out) noexcept;
  void postfit(const MeasurementRecord& rec, int m, StepRecord& out) noexcept;
};

}  // namespace satgnc::filter::detail
