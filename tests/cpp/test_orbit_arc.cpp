// One orbit-arc validator (issue 12, I4): validate_orbit_arc_input with CVODES's rules (kOneSidedArc)
// and DOP853's / Kepler's (kTwoSidedArc) refuses and accepts what the three former validators did,
// with one wording per rule. tests/python/test_orbit_arc_input.py runs the same table through the
// bindings (and was run against the former validators: same outcomes, texts aside).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "error_checks.hpp"
#include "satgnc/core/constants.hpp"
#include "satgnc/propagation/cvodes.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace {

using satgnc::Vec6;
namespace prop = satgnc::propagation;

Vec6 leo() {
  Vec6 x;
  x << 7000.0, 0.0, 0.0, 0.0, 7.546, 0.0;
  return x;
}

struct Row {
  const char* id;
  Vec6 x0;
  double t0;
  std::vector<double> times;
  const char* one_sided;  // CVODES: nullptr = accepted, else the start of the message
  const char* two_sided;  // DOP853 and Kepler
};

const char* const kMonoStrict =
    "times: must be strictly monotone (sorted, no duplicates) in the direction of propagation";
const char* const kMono = "times: must be monotone (sorted increasing or decreasing)";
const char* const kSide = "times: must all lie on one side of t0 (forward or backward)";
const char* const kZero = "x0: position must be non-zero (|r0| = 0) (hint: ";

std::vector<Row> rows() {
  Vec6 zero_r = leo();
  zero_r.head<3>().setZero();
  Vec6 nan_x = leo();
  nan_x(4) = NAN;
  Vec6 huge = leo();
  huge(0) = 1e200;
  return {
      {"forward", leo(), 0.0, {10.0, 20.0}, nullptr, nullptr},
      {"backward", leo(), 0.0, {-10.0, -20.0}, nullptr, nullptr},
      {"starts-at-t0", leo(), 0.0, {0.0, 10.0}, nullptr, nullptr},
      {"ends-at-t0-backward", leo(), 0.0, {-10.0, 0.0}, kSide, nullptr},
      {"empty", leo(), 0.0, {}, "times: must not be empty (hint: ", nullptr},
      {"both-sides-up", leo(), 0.0, {-10.0, 10.0}, kSide, nullptr},
      {"both-sides-down", leo(), 0.0, {10.0, -10.0}, kSide, nullptr},
      {"t0-between", leo(), 5.0, {0.0, 10.0}, kSide, nullptr},
      {"unsorted", leo(), 0.0, {10.0, 5.0, 20.0}, kMonoStrict, kMono},
      {"duplicate", leo(), 0.0, {10.0, 10.0}, kMonoStrict, nullptr},
      {"down-after-t0", leo(), 0.0, {20.0, 10.0}, kMonoStrict, nullptr},
      {"zero-position", zero_r, 0.0, {10.0}, kZero, kZero},
      {"nan-state",
       nan_x,
       0.0,
       {10.0},
       "x0: must be finite (no NaN or Inf)",
       "x0: must be finite (no NaN or Inf)"},
      {"huge-state",
       huge,
       0.0,
       {10.0},
       "x0: every component must be below 1e100",
       "x0: every component must be below 1e100"},
      {"nan-t0",
       leo(),
       NAN,
       {10.0},
       "t0: must be finite (no NaN or Inf)",
       "t0: must be finite (no NaN or Inf)"},
      {"inf-time",
       leo(),
       0.0,
       {10.0, INFINITY},
       "times: must be finite (no NaN or Inf), times[1] is not",
       "times: must be finite (no NaN or Inf), times[1] is not"},
  };
}

// "" when accepted, else the message.
template <class F>
std::string outcome(F&& f) {
  return satgnc::testing::message_of(std::forward<F>(f), "");
}

void expect(const Row& r, const char* entry, const std::string& got, const char* want) {
  if (want == nullptr)
    EXPECT_EQ(got, "") << r.id << " via " << entry << " was refused";
  else
    EXPECT_EQ(got.rfind(want, 0), 0u) << r.id << " via " << entry << ": " << got;
}

}  // namespace

TEST(OrbitArcInput, SameRowsRefusedAndAcceptedByTheThreeEntryPoints) {
  const double mu = satgnc::core::earth::mu;
  prop::CvodesSettings cs;
  cs.with_stm = false;
  prop::CvodesPropagator cvodes(satgnc::dynamics::ForceModel{}, cs);
  int refused = 0;
  for (const Row& r : rows()) {
    expect(r, "validator(kOneSidedArc)",
           outcome([&] { prop::validate_orbit_arc_input(r.x0, r.t0, r.times, prop::kOneSidedArc, "h"); }),
           r.one_sided);
    expect(r, "validator(kTwoSidedArc)",
           outcome([&] { prop::validate_orbit_arc_input(r.x0, r.t0, r.times, prop::kTwoSidedArc, "h"); }),
           r.two_sided);
    expect(r, "CvodesPropagator::propagate", outcome([&] { cvodes.propagate(r.x0, r.t0, r.times); }),
           r.one_sided);
    expect(r, "propagate_dop853", outcome([&] {
             prop::propagate_dop853(satgnc::dynamics::ForceModel{}, r.x0, r.t0, r.times, {}, false);
           }),
           r.two_sided);
    expect(r, "propagate_kepler", outcome([&] { prop::propagate_kepler(r.x0, r.t0, r.times, mu, false); }),
           r.two_sided);
    // The former names are forwards with the same rules.
    expect(r, "validate_propagation_input",
           outcome([&] { prop::validate_propagation_input(r.x0, r.t0, r.times); }), r.one_sided);
    expect(r, "dop853_validate_orbit_input",
           outcome([&] { prop::dop853_validate_orbit_input(r.x0, r.t0, r.times); }), r.two_sided);
    refused += (r.one_sided != nullptr) + (r.two_sided != nullptr);
  }
  EXPECT_EQ(refused, 13 + 6);
}

TEST(OrbitArcInput, MessagesNameTheEntriesAndTheCallersHint) {
  const Vec6 x0 = leo();
  EXPECT_EQ(outcome([&] { prop::validate_orbit_arc_input(x0, 0.0, {10.0, 10.0}, prop::kOneSidedArc, "h"); }),
            std::string(kMonoStrict) +
                ", times[0] = 10, times[1] = 10 (hint: increasing after t0, decreasing before it)");
  EXPECT_EQ(outcome([&] { prop::validate_orbit_arc_input(x0, 0.0, {-10.0, 10.0}, prop::kOneSidedArc, "h"); }),
            std::string(kSide) +
                ", times[0] = -10, t0 = 0 (hint: propagate the arcs before and after t0 in two calls)");
  Vec6 zero_r = x0;
  zero_r.head<3>().setZero();
  EXPECT_EQ(outcome([&] { prop::validate_propagation_input(zero_r, 0.0, {10.0}); }),
            "x0: position must be non-zero (|r0| = 0) (hint: gravity is singular at the centre of the body)");
  EXPECT_EQ(outcome([&] { prop::validate_orbit_arc_input(zero_r, 0.0, {10.0}, nullptr); }),
            "x0: position must be non-zero (|r0| = 0)");
}
