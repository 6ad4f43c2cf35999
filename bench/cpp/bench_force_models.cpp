// C++ cost of each precise force-model term per evaluation (google-benchmark): gravity field
// acceleration and acceleration + gradient at degree/order 8, 20, 70; Sun and Moon ephemerides and
// accelerations; SRP with conical shadow; and a 2 h LEO DOP853 arc with the STM and 20x20 + Sun + Moon
// + SRP. Coefficients: the shipped EGM2008 file (SATGNC_GFC_PATH, set by bench/cpp/CMakeLists.txt).
// NRLMSISE-00: one density and one density + gradient (7 evaluations), the library's phase-table form
// against the direct cos(w (x - p[k])) form (the private reference), before / after in one run.
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "../../cpp/src/dynamics/detail/nrlmsise00_reference.hpp"  // private: the direct form
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/nrlmsise00.hpp"
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

// A LEO point (about 400 km) with the Sun off the meridian, as bench/force_models.py uses.
dy::AtmospherePoint msis_point(double dx) {
  return dy::atmosphere_point(0.0, Vec3(6778.0 + dx, 100.0, 200.0), Vec3(0.3, 0.9, 0.1));
}

// range(0): 0 = direct cos per term (before), 1 = phase tables (the library, after).
void BM_Nrlmsise00Density(benchmark::State& state) {
  const dy::Nrlmsise00 model;
  const bool tables = state.range(0) == 1;
  double dx = 0.0;
  for (auto _ : state) {
    dx += 1e-9;
    const dy::AtmospherePoint p = msis_point(dx);
    const dy::Nrlmsise00Input in = model.input(p);
    const double rho =
        tables ? dy::nrlmsise00(in, model.settings().switches, true).mass_density
               : dy::detail::msis::nrlmsise00_direct(in, model.settings().switches, true).mass_density;
    benchmark::DoNotOptimize(rho);
  }
}
BENCHMARK(BM_Nrlmsise00Density)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The central-difference gradient (Nrlmsise00::density_gradient: 6 + 1 evaluations), both forms.
void BM_Nrlmsise00Gradient(benchmark::State& state) {
  const dy::Nrlmsise00 model;
  const bool tables = state.range(0) == 1;
  const double h = model.gradient_step();
  auto rho = [&](const dy::AtmospherePoint& p) {
    const dy::Nrlmsise00Input in = model.input(p);
    return tables ? dy::nrlmsise00(in, model.settings().switches, true).mass_density
                  : dy::detail::msis::nrlmsise00_direct(in, model.settings().switches, true).mass_density;
  };
  double dx = 0.0;
  for (auto _ : state) {
    dx += 1e-9;
    const dy::AtmospherePoint p = msis_point(dx);
    Vec3 g;
    for (int i = 0; i < 3; ++i) {
      Vec3 rp = p.r_itrf, rm = p.r_itrf;
      rp[i] += h;
      rm[i] -= h;
      g[i] =
          (rho(dy::atmosphere_point(p.t, rp, p.sun_itrf)) - rho(dy::atmosphere_point(p.t, rm, p.sun_itrf))) /
          (2.0 * h);
    }
    const double r0 = rho(p);
    benchmark::DoNotOptimize(g.data());
    benchmark::DoNotOptimize(r0);
  }
}
BENCHMARK(BM_Nrlmsise00Gradient)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The library's own gradient call (the AtmosphereModel interface; phase tables).
void BM_Nrlmsise00GradientModel(benchmark::State& state) {
  const dy::Nrlmsise00 model;
  double dx = 0.0;
  for (auto _ : state) {
    dx += 1e-9;
    Vec3 g;
    const double r0 = model.density_gradient(msis_point(dx), g);
    benchmark::DoNotOptimize(g.data());
    benchmark::DoNotOptimize(r0);
  }
}
BENCHMARK(BM_Nrlmsise00GradientModel)->Unit(benchmark::kMicrosecond);

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
