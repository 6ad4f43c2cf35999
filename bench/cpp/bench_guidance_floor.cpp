// Latency and throughput floors of the cached-gain ADMM iteration's 6x6 recursions (google-benchmark),
// and the Riccati affine sweep itself, for docs/guidance.md: the backward costate and the rollout are
// each a chain of N = 99 dependent 6x6 matrix-vector products; no implementation of one iteration can
// beat two such chains, nor the rate of independent fixed-size products of the same build.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <vector>

#include "satgnc/guidance/riccati.hpp"

namespace {

using M6 = Eigen::Matrix<double, 6, 6>;
using V6 = Eigen::Matrix<double, 6, 1>;
constexpr int kN = 99;

std::vector<M6, Eigen::aligned_allocator<M6>> stages() {
  std::vector<M6, Eigen::aligned_allocator<M6>> A(kN);
  for (auto& a : A) a = M6::Random() * 0.4;  // contractive: the chain stays finite
  return A;
}

V6 tree(const M6& M, const V6& x) {
  return ((M.col(0) * x(0) + M.col(1) * x(1)) + (M.col(2) * x(2) + M.col(3) * x(3))) +
         (M.col(4) * x(4) + M.col(5) * x(5));
}

// x_{k+1} = A_k x_k, products summed as in the solver (tree of column pairs)
void BM_Chain99Tree(benchmark::State& state) {
  const auto A = stages();
  V6 x = V6::Ones();
  for (auto _ : state) {
    for (int k = 0; k < kN; ++k) x = tree(A[static_cast<std::size_t>(k)], x);
    x(0) += 1.0;
    benchmark::DoNotOptimize(x.data());
  }
}

// the same chain with Eigen's plain product
void BM_Chain99Plain(benchmark::State& state) {
  const auto A = stages();
  V6 x = V6::Ones();
  for (auto _ : state) {
    for (int k = 0; k < kN; ++k) {
      const V6 y = A[static_cast<std::size_t>(k)] * x;
      x = y;
    }
    x(0) += 1.0;
    benchmark::DoNotOptimize(x.data());
  }
}

// 99 independent products (throughput of this build for fixed-size 6x6 matvecs)
void BM_Independent99(benchmark::State& state) {
  const auto A = stages();
  std::vector<V6, Eigen::aligned_allocator<V6>> y(kN);
  V6 x = V6::Ones();
  for (auto _ : state) {
    for (int k = 0; k < kN; ++k) y[static_cast<std::size_t>(k)] = tree(A[static_cast<std::size_t>(k)], x);
    benchmark::DoNotOptimize(y.data());
    x(0) += 1e-30;
  }
}

// the cached-gain affine sweep + rollout (nx = 6, nu = 3, N = 99, no terminal constraint)
void BM_RiccatiSolve63(benchmark::State& state) {
  satgnc::guidance::LtvDynamics dyn;
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(6, 6);
  A.topRightCorner(3, 3) = 0.01 * Eigen::MatrixXd::Identity(3, 3);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, 3);
  B.bottomRows(3) = 0.01 * Eigen::MatrixXd::Identity(3, 3);
  dyn.A = {A};
  dyn.B = {B};
  dyn.horizon = kN;
  satgnc::guidance::RiccatiSolver ric;
  ric.setup(dyn, Eigen::MatrixXd(), Eigen::MatrixXd(), 1e3 * Eigen::MatrixXd::Identity(6, 6), false);
  ric.factor(0.2);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(6), xf = Eigen::VectorXd::Zero(6);
  const Eigen::MatrixXd q = Eigen::MatrixXd::Zero(6, kN + 1), r = Eigen::MatrixXd::Random(3, kN);
  Eigen::MatrixXd X(6, kN + 1), U(3, kN);
  for (auto _ : state) {
    benchmark::DoNotOptimize(ric.solve(x0, q, r, xf, X, U));
    benchmark::DoNotOptimize(X.data());
  }
}

}  // namespace

BENCHMARK(BM_Chain99Tree);
BENCHMARK(BM_Chain99Plain);
BENCHMARK(BM_Independent99);
BENCHMARK(BM_RiccatiSolve63);
