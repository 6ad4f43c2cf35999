// One EKF update, 9 states, one scalar measurement (issue 15 bench, goal <= 1 us): Joseph
// (scalar-sequential) and UD forms, no gate and no PD check (the bare update), then with both.
// gtest-free and benchmark-free: `repeats` updates at the same epoch per sample (no propagation;
// P shrinks ~1/i, which does not change the work), best of `samples`; prints ns per update, by the
// wall clock and by this thread's CPU clock (the second is not inflated when a loaded machine
// preempts the process: the shared 2-core bench machine often runs at load 10-20).
#include <time.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>

#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/linear_models.hpp"

namespace f = satgnc::filter;

namespace {
double thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e9 * static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec);
}

// {best wall ns, best thread-CPU ns} per update.
std::pair<double, double> time_update(f::CovarianceForm form, bool checks, int repeats, int samples) {
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
  double best_cpu = best;
  for (int smp = 0; smp < samples; ++smp) {
    kf.initialize();
    const double c0 = thread_cpu_ns();
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < repeats; ++i) kf.update(rec);
    const auto t1 = std::chrono::steady_clock::now();
    const double c1 = thread_cpu_ns();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / repeats);
    best_cpu = std::min(best_cpu, (c1 - c0) / repeats);
  }
  return {best, best_cpu};
}
}  // namespace

int main() {
  const int repeats = 20000;
  const int samples = 25;
  std::printf(
      "EKF update, n = 9, one scalar measurement, best of %d x %d (ns per update: wall, thread CPU)\n",
      samples, repeats);
  {
    const auto [wall, cpu] = time_update(f::CovarianceForm::joseph, false, repeats, samples);
    std::printf("joseph, bare (no gate, no PD check): %8.1f %8.1f\n", wall, cpu);
  }
  {
    const auto [wall, cpu] = time_update(f::CovarianceForm::ud, false, repeats, samples);
    std::printf("ud,     bare (no gate, no PD check): %8.1f %8.1f\n", wall, cpu);
  }
  {
    const auto [wall, cpu] = time_update(f::CovarianceForm::joseph, true, repeats, samples);
    std::printf("joseph, gate + Cholesky PD check:    %8.1f %8.1f\n", wall, cpu);
  }
  {
    const auto [wall, cpu] = time_update(f::CovarianceForm::ud, true, repeats, samples);
    std::printf("ud,     gate + D > 0 check:          %8.1f %8.1f\n", wall, cpu);
  }
  return 0;
}
