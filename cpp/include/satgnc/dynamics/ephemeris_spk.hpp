#pragma once
/// @file ephemeris_spk.hpp
/// A reader of NAIF SPK files (the binary `.bsp` form of the JPL DE ephemerides): the DAF container
/// (file record, summary and name records, segment descriptors) and the Chebyshev segment types 2
/// (position coefficients; velocity by differentiation) and 3 (position and velocity coefficients).
/// Written from NAIF's "DAF Required Reading" and "SPK Required Reading"; no SPICE code is used.
///
/// Bodies are NAIF integer codes (0 solar-system barycentre, 3 Earth-Moon barycentre, 10 Sun,
/// 301 Moon, 399 Earth). A position of a target with respect to a center is chained through the
/// file's segments: the Moon from the Earth is (EMB -> Moon) - (EMB -> Earth), the Sun from the Earth
/// is (SSB -> Sun) - (SSB -> EMB) - (EMB -> Earth). Epochs are TDB seconds past J2000 (the SPK "ET").
/// Units: km, km/s. Axes: the segments' frame, which must be J2000 (code 1; for the DE files the
/// ICRF axes, taken as GCRF).
///
/// Open validates: a DAF of type SPK, the host's byte order, descriptors inside the file, and for
/// every segment on a requested chain its type (2 or 3) and its record layout. Errors are
/// std::invalid_argument naming the file and what is wrong. All segment data on the requested chains
/// are read into memory at open; an evaluation allocates nothing and the object is immutable, so one
/// instance may be shared by threads (`std::shared_ptr<const SpkEphemeris>`).
#include <string>
#include <utility>
#include <vector>

#include "satgnc/core/types.hpp"

namespace satgnc::dynamics {

/// NAIF body codes used by the force model.
namespace naif {
inline constexpr int ssb = 0;      ///< solar-system barycentre
inline constexpr int emb = 3;      ///< Earth-Moon barycentre
inline constexpr int sun = 10;     ///< Sun
inline constexpr int moon = 301;   ///< Moon
inline constexpr int earth = 399;  ///< Earth
}  // namespace naif

/// One segment descriptor of an SPK file (as stored; nothing evaluated).
struct SpkSegmentInfo {
  int target = 0;         ///< NAIF code of the body whose position the segment gives
  int center = 0;         ///< NAIF code of the body it is relative to
  int frame = 0;          ///< NAIF frame code (1: J2000)
  int type = 0;           ///< SPK data type (2, 3 supported)
  double start_et = 0.0;  ///< coverage start, TDB s past J2000
  double end_et = 0.0;    ///< coverage end, TDB s past J2000
  int begin_address = 0;  ///< first double-precision word (1-based DAF address)
  int end_address = 0;    ///< last double-precision word
  std::string name;       ///< segment name from the name record (trailing blanks removed)
};

/// A JPL DE (or any SPK type 2 / 3) ephemeris opened for a set of (target, center) pairs.
class SpkEphemeris {
 public:
  /// Geocentric Sun and Moon: the pairs the third-body model needs.
  static std::vector<std::pair<int, int>> geocentric_sun_moon() {
    return {{naif::sun, naif::earth}, {naif::moon, naif::earth}};
  }

  /// Open `path`, validate the DAF and every segment on the chains of `pairs` (target, center), and
  /// read those segments' data. Throws std::invalid_argument "<path>: <what is wrong>".
  explicit SpkEphemeris(const std::string& path,
                        const std::vector<std::pair<int, int>>& pairs = geocentric_sun_moon());

  const std::string& path() const { return path_; }  ///< the file opened
  /// The internal file name of the DAF file record (trailing blanks removed).
  const std::string& internal_name() const { return internal_name_; }
  /// Every segment descriptor of the file, in file order (those not on a chain included).
  const std::vector<SpkSegmentInfo>& segments() const { return segments_; }
  /// The (target, center) pairs prepared at open.
  const std::vector<std::pair<int, int>>& pairs() const { return pairs_; }
  /// Span (TDB s past J2000) where every prepared pair can be evaluated: the intersection of the
  /// coverage of all the chains' segments (gaps inside it are reported by the evaluation).
  double start_et() const { return start_et_; }
  double end_et() const { return end_et_; }  ///< see start_et(), TDB s past J2000
  /// True when et (TDB s past J2000) is in [start_et(), end_et()].
  bool covers(double et) const { return et >= start_et_ && et <= end_et_; }

  /// Position (km) of target relative to center at et (TDB s past J2000); the pair must have been
  /// prepared. Throws std::out_of_range naming the epoch and the coverage when et lies outside it,
  /// std::invalid_argument for a pair not prepared. Allocates nothing on success.
  Vec3 position(int target, int center, double et) const;
  /// Position (km) and velocity (km/s) of target relative to center at et; as position().
  void state(int target, int center, double et, Vec3& r, Vec3& v) const;

  /// TDB seconds past J2000 of the two-part TT Julian date jd1 + jd2 (ERFA eraDtdb at the geocentre,
  /// TDB - TT < 1.7 ms).
  static double tdb_seconds_from_tt(double jd1, double jd2);

 private:
  struct Segment {          // the loaded data of one type 2 / 3 segment
    int info = 0;           // index into segments_
    int type = 2;           // 2 or 3
    double start_et = 0.0;  // coverage, TDB s past J2000
    double end_et = 0.0;
    double init = 0.0;         // start of the first record's interval, TDB s
    double intlen = 0.0;       // record interval length, s
    int rsize = 0;             // doubles per record: 2 + components * ncoef
    int n = 0;                 // number of records
    int ncoef = 0;             // Chebyshev coefficients per component (degree + 1)
    std::vector<double> data;  // n * rsize doubles: MID, RADIUS, coefficients
  };
  struct Edge {  // one link body -> parent: a list of segments (later ones take precedence)
    int body = 0;
    int parent = 0;
    std::vector<int> segments;  // indices into loaded_
  };
  struct Chain {  // target - center = sum(sign * edge)
    int target = 0;
    int center = 0;
    std::vector<std::pair<int, double>> terms;  // (edge index, +1 or -1)
  };
  void eval_edge(const Edge& e, double et, bool with_velocity, Vec3& r, Vec3& v) const;
  const Chain& chain(int target, int center) const;
  [[noreturn]] void throw_outside(const Edge& e, double et) const;

  std::string path_;
  std::string internal_name_;
  std::vector<SpkSegmentInfo> segments_;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<Segment> loaded_;
  std::vector<Edge> edges_;
  std::vector<Chain> chains_;
  double start_et_ = 0.0;
  double end_et_ = 0.0;
};

/// Format a TDB-seconds-past-J2000 epoch as an ISO 8601 TDB calendar string (for error messages).
std::string format_tdb_seconds(double et);

}  // namespace satgnc::dynamics
