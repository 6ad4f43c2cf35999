// Flight-style sequential orbit determination over a CCSDS TDM (issue 15): read two-way range and
// range-rate of two stations (tests/data/filter/two_station.tdm, or the path given as argv[1]), run the
// orbit EKF (DOP853 + STM between records, SNC process noise, chi-square gate) from a 1.5 km initial
// error, print the final state and its 1-sigma. Links only the installed static satgnc library.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "satgnc/core/epoch.hpp"
#include "satgnc/dynamics/station.hpp"
#include "satgnc/filter/orbit_filter.hpp"
#include "satgnc/io/tdm.hpp"

int main(int argc, char** argv) {
  using namespace satgnc;
  // The data file: argv[1], else the repository copy (run from the repository root, as `make example`
  // does; or found next to this source when __FILE__ is absolute).
  std::string path = "tests/data/filter/two_station.tdm";
  if (FILE* f = std::fopen(path.c_str(), "r")) {
    std::fclose(f);
  } else {
    const std::string src = __FILE__;
    path = src.substr(0, src.rfind('/')) + "/../../tests/data/filter/two_station.tdm";
  }
  if (argc > 1) path = argv[1];
  try {
    // --- setup (allocation allowed): stations, models, records
    const double jd_epoch = 2460000.5;  // 2023-02-25T00:00:00 UTC, t = 0
    const core::Epoch epoch = core::Epoch::from_calendar(2023, 2, 25, 0, 0, 0.0, core::TimeScale::utc);
    const io::Tdm tdm = io::read_tdm(path);
    filter::OrbitMeasurementSettings ms;
    observation::MeasurementSettings range, rate;
    range.type = observation::ObservableType::two_way_range;
    rate.type = observation::ObservableType::two_way_range_rate;
    ms.observables = {range, rate};
    const struct {
      const char* name;
      double lat, lon, h;
    } sites[2] = {{"STN_A", 40.0, -105.0, 1.6}, {"STN_B", -35.0, 149.0, 0.7}};
    std::vector<filter::OrbitMeasurement> meas;
    for (const auto& seg : tdm.segments) {
      int station = -1;
      for (int s = 0; s < 2; ++s)
        if (seg.metadata.participants.at(0) == sites[s].name) station = s;
      if (station < 0) {
        std::fprintf(stderr, "unknown participant %s\n", seg.metadata.participants.at(0).c_str());
        return 2;
      }
      for (const auto& o : seg.observations) {
        const int type = o.keyword == "RANGE" ? 0 : o.keyword == "DOPPLER_INSTANTANEOUS" ? 1 : -1;
        if (type < 0) continue;
        meas.push_back({o.time - epoch, station, type, Eigen::Vector2d(o.value, 0.0)});
      }
    }
    std::stable_sort(meas.begin(), meas.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
    for (const auto& s : sites) {
      filter::OrbitStation st;
      st.ephemeris = std::make_shared<observation::RotatingStationEphemeris>(
          dynamics::Station::from_geodetic(s.lat, s.lon, s.h, jd_epoch));
      st.sigma = {0.005, 1e-6};  // km, km/s
      ms.stations.push_back(st);
    }
    dynamics::ForceModel fm;
    fm.j2 = dynamics::J2Gravity{};
    filter::OrbitProcessSettings ps;
    ps.snc_psd_ric = Vec3::Constant(1e-15);  // km^2/s^3
    filter::OrbitProcessModel pm(fm, ps);
    filter::OrbitMeasurementFunction mf(ms, pm.dimension());
    filter::OrbitFilter kf(std::move(pm), std::move(mf), filter::OrbitFilterSettings{});
    Eigen::VectorXd x0(6);
    x0 << 6878.8, -1.2, 0.5, 0.0004, 4.7364, 5.9872;  // truth + (0.8, -1.2, 0.5) km, (0.4, -0.6, 0.2) m/s
    Eigen::MatrixXd p0 = Eigen::MatrixXd::Zero(6, 6);
    p0.diagonal() << 1.0, 1.0, 1.0, 1e-6, 1e-6, 1e-6;

    // --- the run (no allocation per step; a failure is a step status)
    const filter::OrbitFilterResult r = kf.run(0.0, x0, p0, meas);
    const std::size_t k = static_cast<std::size_t>(r.steps_run) - 1;
    std::printf("orbit EKF over %s: %zu records, %d steps run, %d rejected, %.1f ms\n", path.c_str(),
                meas.size(), r.steps_run, r.rejected, r.solve_time * 1e3);
    std::printf("final state at t = %.0f s (GCRF km, km/s):", r.t[k]);
    for (int i = 0; i < 6; ++i) std::printf(" %.6f", r.state[k * 6 + static_cast<std::size_t>(i)]);
    double var = 0.0;
    for (int i = 0; i < 3; ++i) var += r.covariance[k * 36 + static_cast<std::size_t>(i) * 7];
    std::printf("\nposition 1-sigma %.3f m; last status %s\n", std::sqrt(var) * 1e3,
                filter::status_name(r.status[k]));
    return r.steps_run == static_cast<int>(meas.size()) && std::sqrt(var) < 0.01 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "filter_tdm: %s\n", e.what());
    return 2;
  }
}
