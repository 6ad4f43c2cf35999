#pragma once
/// @file eop.hpp
/// Earth orientation parameters (EOP): polar motion, UT1-UTC, length of day and the celestial pole
/// offsets dX, dY, read from the IERS files in use and interpolated at an Epoch.
///
/// Files: IERS Rapid Service / Prediction Center `finals2000A.all` / `.data` / `.daily` (fixed
/// columns; Bulletin B values where present, else Bulletin A; the row's `source` says which) and the
/// IERS EOP 20 C04 series (`eopc04_20.1962-now`, `eopc04.1962-now`: whitespace-separated columns
/// YR MM DD HH MJD x y UT1-UTC dX dY xrt yrt LOD ...). Rows are at 0h UTC of each day.
///
/// Interpolation: 4-point Lagrange (cubic) on the two rows before and the two after the epoch, as
/// the IERS Conventions' interp.f does for daily series (linear on the first and last interval,
/// where only one row exists on a side). UT1 is interpolated as UT1-TAI, which is continuous across
/// a leap second (UT1-UTC jumps by 1 s there), and returned as UT1-UTC at the epoch. Diurnal and
/// semidiurnal ocean-tide and libration terms (IERS Conventions 5.5.1, 5.5.3: ~0.1 mas in polar
/// motion, ~0.05 ms in UT1) are not added. Interpolation allocates nothing.
#include <cstdint>
#include <string>
#include <vector>

#include "satgnc/core/epoch.hpp"

namespace satgnc::frames {

/// Where the values of an EOP row come from.
enum class EopSource : std::uint8_t {
  bulletin_b,             ///< finals2000A: IERS Bulletin B columns (final values)
  bulletin_a,             ///< finals2000A: Bulletin A, flag 'I' (IERS rapid values)
  bulletin_a_prediction,  ///< finals2000A: Bulletin A, flag 'P' (prediction)
  c04,                    ///< IERS EOP 20 C04 series
  user                    ///< built by the caller
};

/// The name of a source: "bulletin_b", "bulletin_a", "bulletin_a_prediction", "c04", "user".
const char* eop_source_name(EopSource source) noexcept;

/// What EopTable::at does with an epoch outside the table.
enum class OutOfRangePolicy : std::uint8_t {
  error,      ///< throw std::invalid_argument naming the epoch and the table span (default)
  hold_last,  ///< use the first (before) or last (after) row's values, UT1-UTC held constant
  zero        ///< all parameters zero: UT1 = UTC, no polar motion, no pole offsets
};

/// The name of a policy: "error", "hold_last", "zero".
const char* out_of_range_policy_name(OutOfRangePolicy policy) noexcept;
/// The policy named by name ("error", "hold_last", "zero"); throws std::invalid_argument naming
/// "policy" and the choices.
OutOfRangePolicy out_of_range_policy_from_name(const std::string& name);

/// One day of EOP at 0h UTC.
struct EopRow {
  double mjd = 0.0;                    ///< MJD (UTC) of the row, days (a whole day)
  double xp = 0.0;                     ///< polar motion x, arcsec
  double yp = 0.0;                     ///< polar motion y, arcsec
  double ut1_utc = 0.0;                ///< UT1-UTC, s
  double lod = 0.0;                    ///< excess length of day, s (0 where the file leaves it blank)
  double dx = 0.0;                     ///< celestial pole offset dX w.r.t. IAU 2006/2000A, arcsec
  double dy = 0.0;                     ///< celestial pole offset dY w.r.t. IAU 2006/2000A, arcsec
  EopSource source = EopSource::user;  ///< where the values come from
};

/// EOP interpolated at an epoch.
struct EopValues {
  double xp = 0.0;       ///< arcsec
  double yp = 0.0;       ///< arcsec
  double ut1_utc = 0.0;  ///< s
  double ut1_tai = 0.0;  ///< UT1-TAI, s
  double lod = 0.0;      ///< s
  double dx = 0.0;       ///< arcsec
  double dy = 0.0;       ///< arcsec
};

/// A table of daily EOP rows with 4-point Lagrange interpolation (see the file comment).
/// Immutable after construction; at() is const, thread-safe and allocates nothing (except when it
/// throws).
class EopTable {
 public:
  /// From rows with strictly increasing whole-day MJDs (>= 1960-01-01, MJD 36934), finite values,
  /// at least 2 rows. Throws std::invalid_argument naming "rows[i]" and the rule.
  explicit EopTable(std::vector<EopRow> rows, OutOfRangePolicy policy = OutOfRangePolicy::error);

  /// Read an IERS finals2000A file (.all, .data, .daily). Rows with no values (the dates after the
  /// prediction horizon) and lines starting with '#' are skipped. Throws std::invalid_argument
  /// "<path>:<line>: <column>: <rule>" on a malformed line, and naming the path if it cannot be opened or
  /// holds no rows.
  static EopTable read_finals2000a(const std::string& path,
                                   OutOfRangePolicy policy = OutOfRangePolicy::error);
  /// Read an IERS EOP 20 C04 file. Lines starting with '#' are comments. Errors as above.
  static EopTable read_c04(const std::string& path, OutOfRangePolicy policy = OutOfRangePolicy::error);
  /// Read either format, chosen from the first data line (C04 lines start with a 4-digit year).
  static EopTable read(const std::string& path, OutOfRangePolicy policy = OutOfRangePolicy::error);

  /// The same rows with another policy.
  EopTable with_policy(OutOfRangePolicy policy) const;

  /// EOP at epoch. Outside [first row, last row] the policy applies; with `error`, throws
  /// std::invalid_argument("epoch: 2031-01-01T00:00:00.000 UTC is outside the EOP table (MJD 41684 ..
  /// 61770 = 1973-01-02 .. 2027-11-20 UTC) (hint: ...)").
  EopValues at(const core::Epoch& epoch) const;
  /// UT1-UTC at epoch, s.
  double ut1_minus_utc(const core::Epoch& epoch) const { return at(epoch).ut1_utc; }
  /// UT1 at epoch as a two-part Julian date (days), for eraEra00 and friends.
  core::JulianDate ut1_jd(const core::Epoch& epoch) const;
  /// True when epoch lies within [first row, last row].
  bool covers(const core::Epoch& epoch) const;

  const std::vector<EopRow>& rows() const { return rows_; }  ///< the rows, as read
  OutOfRangePolicy policy() const { return policy_; }        ///< the out-of-range policy
  core::Epoch first_epoch() const;                           ///< 0h UTC of the first row
  core::Epoch last_epoch() const;                            ///< 0h UTC of the last row

 private:
  std::vector<EopRow> rows_;
  std::vector<double> t_;        // TAI s of each row's 0h UTC, relative to t0_
  std::vector<double> ut1_tai_;  // UT1-TAI of each row, s
  std::vector<double> dat_;      // TAI-UTC of each row's day, s
  core::Epoch t0_;
  OutOfRangePolicy policy_;
};

}  // namespace satgnc::frames
