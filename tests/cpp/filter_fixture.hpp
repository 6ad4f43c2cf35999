#pragma once
// Seeded random linear systems for the filter tests, and the batch least-squares solution in
// information form that a zero-process-noise Kalman filter must reproduce.
#include <Eigen/Dense>
#include <random>
#include <vector>

#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/linear_models.hpp"

namespace satgnc::testing {

struct LinearCase {
  int n = 0;
  Eigen::MatrixXd phi;             // one step
  std::vector<Eigen::MatrixXd> h;  // by type (1, 2, 3 rows)
  filter::FilterProblem problem;
  std::vector<int> step_of;  // number of Phi steps from t0 to each record
  int steps = 0;             // Phi steps to the last record
};

/// n states; records at t = 1..epochs (one Phi step each), one or two records per epoch (types 0..2),
/// sigmas in [0.5, 2]; truth x_true; P0 = diag(1..10) (units of the state), x0 = truth + offset.
inline LinearCase make_linear_case(int n, int epochs, unsigned seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  std::uniform_int_distribution<int> type(0, 2);
  LinearCase c;
  c.n = n;
  Eigen::MatrixXd a(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a(i, j) = g(gen);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  Eigen::MatrixXd q = qr.householderQ();
  Eigen::VectorXd scale(n);
  for (int i = 0; i < n; ++i) scale(i) = 0.98 + 0.04 * (i + 0.5) / n;  // near-orthogonal, mildly (un)stable
  c.phi = q * scale.asDiagonal();
  for (int m = 1; m <= 3; ++m) {
    Eigen::MatrixXd h(m, n);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < n; ++j) h(i, j) = g(gen);
    c.h.push_back(h);
  }
  Eigen::VectorXd xt(n);
  for (int i = 0; i < n; ++i) xt(i) = 10.0 * g(gen);
  Eigen::VectorXd p0d(n);
  for (int i = 0; i < n; ++i) p0d(i) = 1.0 + 9.0 * i / std::max(n - 1, 1);
  c.problem.p0 = p0d.asDiagonal();
  c.problem.x0 = xt;
  for (int i = 0; i < n; ++i) c.problem.x0(i) += std::sqrt(p0d(i)) * g(gen);
  c.problem.t0 = 0.0;
  Eigen::VectorXd x = xt;
  for (int k = 1; k <= epochs; ++k) {
    x = c.phi * x;
    const int per = 1 + (k % 2);
    for (int j = 0; j < per; ++j) {
      filter::MeasurementRecord r;
      r.t = k;
      r.type = type(gen);
      r.station = j;
      const Eigen::MatrixXd& h = c.h[static_cast<std::size_t>(r.type)];
      for (int i = 0; i < h.rows(); ++i) {
        r.sigma[static_cast<std::size_t>(i)] = u(gen);
        r.value[static_cast<std::size_t>(i)] =
            h.row(i).dot(x) + r.sigma[static_cast<std::size_t>(i)] * g(gen);
      }
      c.problem.records.push_back(r);
      c.step_of.push_back(k);
    }
  }
  c.steps = epochs;
  return c;
}

/// Batch least squares in information form at t0: returns {x0_hat, P0_hat}.
inline std::pair<Eigen::VectorXd, Eigen::MatrixXd> batch_information(const LinearCase& c) {
  const int n = c.n;
  Eigen::MatrixXd p0inv = c.problem.p0.inverse();
  Eigen::MatrixXd lambda = p0inv;
  Eigen::VectorXd b = p0inv * c.problem.x0;
  std::vector<Eigen::MatrixXd> phik(1, Eigen::MatrixXd::Identity(n, n));
  for (int k = 1; k <= c.steps; ++k) phik.push_back(c.phi * phik.back());
  for (std::size_t i = 0; i < c.problem.records.size(); ++i) {
    const auto& r = c.problem.records[i];
    const Eigen::MatrixXd a =
        c.h[static_cast<std::size_t>(r.type)] * phik[static_cast<std::size_t>(c.step_of[i])];
    for (int j = 0; j < a.rows(); ++j) {
      const double w = 1.0 / (r.sigma[static_cast<std::size_t>(j)] * r.sigma[static_cast<std::size_t>(j)]);
      lambda += w * a.row(j).transpose() * a.row(j);
      b += w * a.row(j).transpose() * r.value[static_cast<std::size_t>(j)];
    }
  }
  Eigen::LLT<Eigen::MatrixXd> llt(lambda);
  return {llt.solve(b), llt.solve(Eigen::MatrixXd::Identity(n, n))};
}

/// Phi^k
inline Eigen::MatrixXd phi_power(const LinearCase& c, int k) {
  Eigen::MatrixXd p = Eigen::MatrixXd::Identity(c.n, c.n);
  for (int i = 0; i < k; ++i) p = c.phi * p;
  return p;
}

}  // namespace satgnc::testing
