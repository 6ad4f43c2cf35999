// One EKF update, 9 states, one scalar measurement (issue 15 bench, goal <= 1 us): Joseph
// (scalar-sequential) and UD forms, no gate and no PD check (the bare update), then with both.
// gtest-free and benchmark-free: `repeats` updates at the same epoch per sample (no propagation;
// P shrinks ~1/i, which does not change the work), best of `samples`; prints ns per update.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <random>

#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/linear_models.hpp"

namespace f = satgnc::filter;

namespace {
double time_update(f::CovarianceForm form, bool checks, int repeats, int samples) {
  const int n = 9;
  std::mt19937 gen(1);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd a(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a(i, j) = g(gen);
  Eigen::MatrixXd p0 = a * a.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd h(1, n);
  for (int j = 0; j < n; ++j) h(0, j) = g(gen);
  f::LinearProcessModel proc(Eigen::MatrixXd::Identity(n, n), Eigen::MatrixXd::Zero(n, n));
  f::LinearMeasurementFunction meas({h});
  f::FilterProblem p;
  p.x0 = Eigen::VectorXd::Zero(n);
  p.p0 = p0;
  f::FilterSettings s;
  s.form = form;
  s.gating = checks;
  s.check_covariance = checks;
  f::KalmanFilter kf(proc, meas, p, s);
  f::MeasurementRecord rec;
  rec.value[0] = 1.0;
  rec.sigma[0] = 1.0;
  double best = std::numeric_limits<double>::infinity();
  for (int smp = 0; smp < samples; ++smp) {
    kf.initialize();
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < repeats; ++i) kf.update(rec);
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / repeats);
  }
  return best;
}
}  // namespace

int main() {
  const int repeats = 20000;
  const int samples = 25;
  std::printf("EKF update, n = 9, one scalar measurement, best of %d x %d (ns per update)\n", samples,
              repeats);
  std::printf("joseph, bare (no gate, no PD check): %8.1f\n",
              time_update(f::CovarianceForm::joseph, false, repeats, samples));
  std::printf("ud,     bare (no gate, no PD check): %8.1f\n",
              time_update(f::CovarianceForm::ud, false, repeats, samples));
  std::printf("joseph, gate + Cholesky PD check:    %8.1f\n",
              time_update(f::CovarianceForm::joseph, true, repeats, samples));
  std::printf("ud,     gate + D > 0 check:          %8.1f\n",
              time_update(f::CovarianceForm::ud, true, repeats, samples));
  return 0;
}
