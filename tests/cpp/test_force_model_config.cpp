// The force-model TOML read from C++ (issue 14 item 8): a file equals the hand-built ForceModel
// (acceleration and Jacobians at 5 states bit-identical), errors name the file, the line, the
// section and the key, and the two-satellite truth parameters come from the same file.
// (The battery of >= 15 bad files, EGM2008 and EOP are in tests/python/test_force_model_config.py.)
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "satgnc/dynamics/force_model_config.hpp"
#include "satgnc/dynamics/nrlmsise00.hpp"
#include "satgnc/frames/earth_rotation.hpp"

namespace {
using satgnc::Mat3;
using satgnc::Vec3;
namespace dy = satgnc::dynamics;
namespace core = satgnc::core;

constexpr const char* kFile = R"(# test
[central_body]
radius = 6378.1363

[epoch]
time = "2024-03-20T12:00:00"
scale = "utc"

[gravity]
model = "j2"

[third_body]
sun = true
moon = true

[srp]
area = 2.0
mass = 500.0
cr = 1.4
shadow = "conical"

[drag]
area = 3.0
mass = 500.0
cd = 2.1
atmosphere = "harris_priester"
hp_n = 4
)";

dy::ForceModel hand_built() {
  dy::ForceModel fm;
  fm.j2 = dy::J2Gravity{core::earth::mu, core::earth::j2, 6378.1363};
  fm.third_body = dy::ThirdBodies{};
  dy::SolarRadiationPressure s;
  s.area = 2.0;
  s.mass = 500.0;
  s.cr = 1.4;
  fm.srp = s;
  dy::AtmosphereDrag a;
  a.atmosphere = std::make_shared<dy::HarrisPriester>(4.0, 30.0 * M_PI / 180.0);
  a.earth_rotation = std::make_shared<satgnc::frames::UniformRotation>(0.0, core::earth::omega);
  a.cd = 2.1;
  a.area = 3.0;
  a.mass = 500.0;
  fm.atmosphere_drag = a;
  fm.set_epoch(core::Epoch::parse("2024-03-20T12:00:00", core::TimeScale::utc));
  return fm;
}

TEST(ForceModelConfig, FileEqualsTheHandBuiltModelAtFiveStates) {
  const dy::ForceModelConfig cfg = dy::parse_force_model_config(kFile, "test.toml");
  const dy::ForceModel ref = hand_built();
  ASSERT_TRUE(cfg.epoch.has_value());
  EXPECT_EQ(cfg.model.epoch_jd1, ref.epoch_jd1);
  EXPECT_EQ(cfg.model.epoch_jd2, ref.epoch_jd2);
  EXPECT_EQ(cfg.atmosphere, "harris_priester");
  const Vec3 rs[5] = {Vec3(6778.0, 0.0, 0.0), Vec3(0.0, 6900.0, 100.0), Vec3(-4000.0, 4000.0, 3500.0),
                      Vec3(3000.0, -5000.0, -3000.0), Vec3(-6700.0, -500.0, 800.0)};
  const Vec3 vs[5] = {Vec3(0.0, 7.6, 1.0), Vec3(-7.5, 0.0, 1.2), Vec3(-4.0, -4.0, 4.0), Vec3(5.0, 4.0, -3.0),
                      Vec3(0.5, -7.4, 1.0)};
  for (int i = 0; i < 5; ++i) {
    const double t = 600.0 * i;
    // Bit-identical: the same terms with the same numbers (EXPECT_EQ on every component).
    EXPECT_TRUE(cfg.model.acceleration(t, rs[i], vs[i]) == ref.acceleration(t, rs[i], vs[i])) << i;
    Vec3 a1, a2;
    Mat3 g1, g2, h1, h2;
    cfg.model.acceleration_jacobians(t, rs[i], vs[i], a1, g1, h1);
    ref.acceleration_jacobians(t, rs[i], vs[i], a2, g2, h2);
    EXPECT_TRUE(g1 == g2 && h1 == h2) << i;
    EXPECT_GT(a1.norm(), 7e-3);  // a real LEO acceleration (km/s^2), not a zero model
  }
}

TEST(ForceModelConfig, ErrorsNameFileLineSectionAndKey) {
  auto message = [](const std::string& text) -> std::string {
    try {
      dy::parse_force_model_config(text, "bad.toml");
    } catch (const dy::ForceModelConfigError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message("[srp]\narea = 1.0\nmass = 10.0\naera = 2.0\n"),
            "bad.toml:4: [srp] aera: unknown key (known in [srp]: area, mass, cr, shadow)");
  EXPECT_EQ(message("[drag]\narea = -1.0\nmass = 10.0\n"),
            "bad.toml:2: [drag] area: must be >= 0 m^2, got -1");
  EXPECT_EQ(message("[space_weather]\nf107 = 900\n"),
            "bad.toml:2: [space_weather] f107: must be in [0, 400] sfu, got 900");
  EXPECT_EQ(message("[drag]\narea = 1.0\nmass = 10.0\natmosphere = \"nrlmsise00\"\nhp_n = 3\n"),
            "bad.toml:5: [drag] hp_n: only with atmosphere = \"harris_priester\"");
  EXPECT_EQ(dy::ForceModelConfigError("f.toml", 0, "[gravity]", "x").line(), 0);
}

TEST(ForceModelConfig, TwoSatelliteTruthParametersFromTheSameFile) {
  const std::string text =
      "[central_body]\nmu = 398600.4418\n[gravity]\nmodel = \"j2\"\n[drag]\narea = 0.01\nmass = 4.6\n"
      "cd = 1.0\natmosphere = \"exponential\"\nrho0 = 3.725e-12\nh0 = 400.0\nscale_height = 58.515\n";
  const dy::ForceModelConfig cfg = dy::parse_force_model_config(text, "truth.toml");
  const dy::TwoSatelliteParams p = dy::two_satellite_params(cfg);
  EXPECT_EQ(p.mu, 398600.4418e9);  // km^3/s^2 -> m^3/s^2 (exact: 1e9 scaling of this value)
  EXPECT_TRUE(p.j2_on);
  EXPECT_TRUE(p.drag_on);
  // The density at 400 km altitude equals the file's rho0 (1e-15 relative: exp / log round-off).
  const double h = 400.0e3 + 6378.1363e3 - p.density_radius;
  EXPECT_NEAR(p.rho0 * std::exp(-p.density_decay * h), 3.725e-12, 3.725e-12 * 1e-15);
  EXPECT_EQ(p.area_chaser, 0.01);
  EXPECT_EQ(p.mass_target, 4.6);
  // A term the two-satellite model does not have is refused, naming the section.
  const dy::ForceModelConfig srp = dy::parse_force_model_config("[srp]\narea = 1\nmass = 2\n", "srp.toml");
  try {
    dy::two_satellite_params(srp);
    FAIL() << "no throw";
  } catch (const dy::ForceModelConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("srp.toml: [srp]: the two-satellite truth model has no"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace

// NRLMSISE-00 from the file: the model takes the file's [epoch] (as TT) and [space_weather]; the
// acceleration equals a hand-built AtmosphereDrag on Nrlmsise00 with the same settings, bit for bit.
TEST(ForceModelConfig, Nrlmsise00FromTheFileEqualsTheHandBuiltModel) {
  const char* text =
      "[epoch]\ntime = \"2024-03-20T12:00:00\"\nscale = \"utc\"\n[drag]\narea = 3.0\nmass = 500.0\n"
      "cd = 2.1\natmosphere = \"nrlmsise00\"\n[space_weather]\nf107 = 180\nf107a = 160\nap = 15\n";
  const dy::ForceModelConfig cfg = dy::parse_force_model_config(text, "msis.toml");
  EXPECT_EQ(cfg.atmosphere, "nrlmsise00");
  ASSERT_TRUE(cfg.model.atmosphere_drag.has_value());
  const core::Epoch ep = core::Epoch::parse("2024-03-20T12:00:00", core::TimeScale::utc);
  dy::Nrlmsise00Settings ms;
  const core::JulianDate jd = ep.jd(core::TimeScale::tt);
  ms.epoch_jd1 = jd.jd1;
  ms.epoch_jd2 = jd.jd2;
  ms.space_weather.f107 = 180.0;
  ms.space_weather.f107a = 160.0;
  ms.space_weather.ap = 15.0;
  dy::ForceModel ref;
  dy::AtmosphereDrag a;
  a.atmosphere = std::make_shared<dy::Nrlmsise00>(ms);
  a.earth_rotation = std::make_shared<satgnc::frames::UniformRotation>(0.0, core::earth::omega);
  a.cd = 2.1;
  a.area = 3.0;
  a.mass = 500.0;
  ref.atmosphere_drag = a;
  ref.set_epoch(ep);
  const Vec3 r(6778.0, 100.0, 200.0), v(0.0, 7.6, 1.0);
  for (int i = 0; i < 3; ++i) {
    const double t = 1800.0 * i;
    const Vec3 a1 = cfg.model.acceleration(t, r, v), a2 = ref.acceleration(t, r, v);
    EXPECT_TRUE(a1 == a2) << i;  // bit-identical: the same terms with the same numbers
    // Drag at 400 km: |a_drag| ~ 0.5 rho v^2 Cd A / m with rho ~ 1e-12..1e-11 kg/m^3 -> 1e-10..1e-8 km/s^2.
    const Vec3 two_body = -core::earth::mu * r / std::pow(r.norm(), 3);
    const double drag = (a1 - two_body).norm();
    EXPECT_GT(drag, 1e-11);
    EXPECT_LT(drag, 1e-7);
  }
}
