// C++ cost of each precise force-model term per evaluation (google-benchmark): gravity field
// acceleration and acceleration + gradient at degree/order 8, 20, 70; Sun and Moon ephemerides and
// accelerations; SRP with conical shadow; and a 2 h LEO DOP853 arc with the STM and 20x20 + Sun + Moon
// + SRP. Coefficients: the shipped EGM2008 file (SATGNC_GFC_PATH, set by bench/cpp/CMakeLists.txt).
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/frames/earth_rotation.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace {
namespace dy = satgnc::dynamics;
using satgnc::Mat3;
using satgnc::Vec3;

std::shared_ptr<const dy::GravityCoefficients> coefficients() {
  static const auto c = std::make_shared<const dy::GravityCoefficients>(dy::load_gfc(SATGNC_GFC_PATH));
  return c;
}

dy::GravityField field(int n) {
  return dy::GravityField(coefficients(), n, n, std::make_shared<const satgnc::frames::UniformRotation>());
}

void BM_GravityAcceleration(benchmark::State& state) {
  const dy::GravityField f = field(static_cast<int>(state.range(0)));
  Vec3 r(5000.0, -3000.0, 3500.0);
  for (auto _ : state) {
    r.x() += 1e-9;
    Vec3 a = f.acceleration(10.0, r);
    benchmark::DoNotOptimize(a.data());
  }
}
BENCHMARK(BM_GravityAcceleration)->Arg(8)->Arg(20)->Arg(70)->Unit(benchmark::kMicrosecond);

void BM_GravityGradient(benchmark::State& state) {
  const dy::GravityField f = field(static_cast<int>(state.range(0)));
  Vec3 r(5000.0, -3000.0, 3500.0), a;
  Mat3 g;
  for (auto _ : state) {
    r.x() += 1e-9;
    f.jacobian(10.0, r, a, g);
    benchmark::DoNotOptimize(g.data());
  }
}
BENCHMARK(BM_GravityGradient)->Arg(8)->Arg(20)->Arg(70)->Unit(benchmark::kMicrosecond);

void BM_SunPosition(benchmark::State& state) {
  double t = 0.0;
  for (auto _ : state) {
    t += 1e-6;
    Vec3 s = dy::sun_position(2451545.0, t);
    benchmark::DoNotOptimize(s.data());
  }
}
BENCHMARK(BM_SunPosition)->Unit(benchmark::kMicrosecond);

void BM_MoonPosition(benchmark::State& state) {
  double t = 0.0;
  for (auto _ : state) {
    t += 1e-6;
    Vec3 s = dy::moon_position(2451545.0, t);
    benchmark::DoNotOptimize(s.data());
  }
}
BENCHMARK(BM_MoonPosition)->Unit(benchmark::kMicrosecond);

void BM_SrpConicalJacobian(benchmark::State& state) {
  const dy::SolarRadiationPressure p;
  const Vec3 s = dy::sun_position(2451545.0, 0.0);
  Vec3 r(7000.0, 10.0, 20.0), a;
  Mat3 g;
  for (auto _ : state) {
    r.y() += 1e-9;
    dy::srp_jacobian(p, s, r, a, g);
    benchmark::DoNotOptimize(g.data());
  }
}
BENCHMARK(BM_SrpConicalJacobian)->Unit(benchmark::kMicrosecond);

void BM_Dop853FullModelStm(benchmark::State& state) {
  dy::ForceModel fm;
  fm.mu = coefficients()->mu;
  fm.gravity.emplace(field(20));
  fm.third_body = dy::ThirdBodies{};
  fm.srp = dy::SolarRadiationPressure{};
  const satgnc::Vec6 x0 = (satgnc::Vec6() << 7000.0, 0.0, 0.0, 0.0, 5.3, 5.3).finished();
  satgnc::propagation::Dop853Settings settings;
  settings.rtol = 1e-10;
  settings.atol = 1e-12;
  const std::vector<double> times{7200.0};
  for (auto _ : state) {
    auto traj = satgnc::propagation::propagate_dop853(fm, x0, 0.0, times, settings, true);
    benchmark::DoNotOptimize(traj.stms.data());
  }
}
BENCHMARK(BM_Dop853FullModelStm)->Unit(benchmark::kMillisecond);

}  // namespace
