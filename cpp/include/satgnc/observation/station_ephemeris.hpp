#pragma once
/// @file station_ephemeris.hpp
/// Where a tracking station is, in GCRF, when a measurement model asks. A model calls it at the
/// reception time and (two-way) at the transmit time, so an implementation must be cheap,
/// allocation-free and must not throw.
///
/// Time axis: t is in seconds after the ephemeris's own reference epoch (as for
/// frames::EarthRotationModel); measurement tags given to observation::MeasurementModel are on the
/// same axis. A double t within 1e7 s (115 days) of the reference resolves 2e-9 s, i.e. < 1e-9 km
/// of station motion.
#include <memory>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/station.hpp"
#include "satgnc/frames/earth_rotation.hpp"
#include "satgnc/frames/ground_station.hpp"

namespace satgnc::observation {

/// State of a station at one instant, in GCRF.
struct StationState {
  Vec3 r = Vec3::Zero();        ///< position, km (GCRF)
  Vec3 v = Vec3::Zero();        ///< velocity, km/s (GCRF)
  Vec3 a = Vec3::Zero();        ///< acceleration, km/s^2 (GCRF)
  Mat3 enu = Mat3::Identity();  ///< rows: local east, north, up (geodetic) unit vectors in GCRF
};

/// A station's GCRF ephemeris: the interface the measurement models see (Orekit's "GroundStation"
/// role). Implementations are immutable; state() is const, thread-safe, allocation-free, noexcept.
class StationEphemeris {
 public:
  virtual ~StationEphemeris() = default;
  /// GCRF state at t (s after the reference epoch of this ephemeris).
  virtual void state(double t, StationState& out) const noexcept = 0;
  /// Geodetic latitude of the station (rad), for the troposphere model.
  virtual double latitude() const noexcept = 0;
  /// Height above the ellipsoid (km), for the troposphere model.
  virtual double height() const noexcept = 0;
};

/// The paper's rotating station (dynamics::Station: inertial position at t = 0 rotating about the
/// inertial +z axis at omega) seen through StationEphemeris: t is the Station's own time (s after
/// its epoch). Its acceleration is omega x (omega x R); the topocentric axes are the geodetic ones
/// of the rotated position on the given ellipsoid (a rotation about z leaves the geodetic latitude
/// unchanged, so it is computed once, with ERFA's eraGc2gde).
class RotatingStationEphemeris final : public StationEphemeris {
 public:
  /// Throws std::invalid_argument (station.validate(), "ellipsoid" for a non-finite or non-positive
  /// a or f outside [0, 1)).
  explicit RotatingStationEphemeris(const dynamics::Station& station,
                                    const dynamics::Ellipsoid& ellipsoid = dynamics::ellipsoids::wgs84);
  void state(double t, StationState& out) const noexcept override;
  double latitude() const noexcept override { return latitude_; }         ///< rad (geodetic)
  double height() const noexcept override { return height_; }             ///< km
  const dynamics::Station& station() const noexcept { return station_; }  ///< the wrapped station

 private:
  dynamics::Station station_;
  double latitude_ = 0.0;
  double height_ = 0.0;
};

/// Lowest accepted station height above the ellipsoid (km): the Dead Sea shore is at -0.43 km.
inline constexpr double kMinStationHeight = -0.5;

/// A station fixed in the Earth frame (ITRF) at WGS-84 geodetic coordinates (ERFA eraGd2gc), carried
/// to GCRF by an frames::EarthRotationModel: frames::UniformRotation (GMST-only) or the IAU 2006/2000A
/// chain with EOP (frames::IauEarthRotation, whose epoch is then the epoch of t = 0). State:
/// r = M^T r_itrf, v = omega x r, a = omega x v (M = gcrf_to_itrf, omega its rate in GCRF; the rate of
/// omega is left out); the ENU axes are the geodetic ones of the ITRF position rotated with M.
class EarthFixedStationEphemeris final : public StationEphemeris {
 public:
  /// latitude, longitude (rad), height (km) in [kMinStationHeight, 100]. Throws
  /// std::invalid_argument naming the argument; `rotation` must be non-null.
  EarthFixedStationEphemeris(double latitude_rad, double longitude_rad, double height_km,
                             std::shared_ptr<const frames::EarthRotationModel> rotation);
  /// The same station from a frames::GroundStation (its WGS-84 latitude, longitude and height).
  static EarthFixedStationEphemeris from_ground_station(
      const frames::GroundStation& station, std::shared_ptr<const frames::EarthRotationModel> rotation);
  void state(double t, StationState& out) const noexcept override;
  double latitude() const noexcept override { return latitude_; }  ///< rad (geodetic)
  double height() const noexcept override { return height_; }      ///< km
  double longitude() const noexcept { return longitude_; }         ///< rad (east)
  const Vec3& position_itrf() const noexcept { return r_itrf_; }   ///< km

 private:
  double latitude_, longitude_, height_;
  Vec3 r_itrf_;
  Mat3 enu_itrf_;
  std::shared_ptr<const frames::EarthRotationModel> rotation_;
};

}  // namespace satgnc::observation
