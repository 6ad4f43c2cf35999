// C++ timings of one 2 h LEO arc with the 6x6 STM for each satgnc propagator (google-benchmark).
#include <benchmark/benchmark.h>

#include <vector>

#include "satgnc/propagation/cvodes.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace {

const satgnc::Vec6 kX0 = (satgnc::Vec6() << 7000.0, 0.0, 0.0, 0.0, 5.3, 5.3).finished();  // km, km/s
const std::vector<double> kTimes{7200.0};                                                 // s

void BM_Kepler(benchmark::State& state) {
  satgnc::Vec6 x;
  satgnc::Mat6 stm;
  for (auto _ : state) {
    auto status = satgnc::propagation::kepler_step(kX0, 7200.0, satgnc::dynamics::earth::mu, x, &stm);
    benchmark::DoNotOptimize(status);
    benchmark::DoNotOptimize(stm.data());
  }
}

void BM_Dop853(benchmark::State& state) {
  satgnc::dynamics::ForceModel model;
  if (state.range(0)) model.j2 = satgnc::dynamics::J2Gravity{};
  satgnc::propagation::Dop853Settings settings;
  settings.rtol = 1e-10;
  settings.atol = 1e-12;
  for (auto _ : state) {
    auto traj = satgnc::propagation::propagate_dop853(model, kX0, 0.0, kTimes, settings, true);
    benchmark::DoNotOptimize(traj.stms.data());
  }
}

void BM_CvodesAdams(benchmark::State& state) {
  satgnc::dynamics::ForceModel model;
  if (state.range(0)) model.j2 = satgnc::dynamics::J2Gravity{};
  satgnc::propagation::CvodesSettings settings;
  settings.rtol = 1e-10;
  satgnc::propagation::CvodesPropagator propagator(model, settings);
  satgnc::propagation::Trajectory traj;
  for (auto _ : state) {
    propagator.propagate(kX0, 0.0, kTimes, traj);
    benchmark::DoNotOptimize(traj.stms.data());
  }
}

}  // namespace

BENCHMARK(BM_Kepler)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Dop853)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CvodesAdams)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
