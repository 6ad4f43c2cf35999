// core/status.hpp: every status table has unique snake_case names and values, `unsolved` first
// (Verdict, a verdict and not a run outcome, is the named exception), non-empty messages, and the
// name <-> value round trip holds; the room headers re-export the same enums.
#include <gtest/gtest.h>

#include <cctype>
#include <set>
#include <string>

#include "satgnc/analysis/rank.hpp"
#include "satgnc/core/solver.hpp"
#include "satgnc/core/status.hpp"
#include "satgnc/filter/orbit_filter.hpp"
#include "satgnc/filter/status.hpp"
#include "satgnc/guidance/admm.hpp"
#include "satgnc/guidance/ilqr_admm.hpp"
#include "satgnc/guidance/riccati.hpp"
#include "satgnc/guidance/scp.hpp"
#include "satgnc/od/solver.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/kepler.hpp"
#include "satgnc/propagation/trajectory.hpp"

namespace core = satgnc::core;

namespace {

bool is_snake_case(const std::string& s) {
  if (s.empty() || !std::islower(static_cast<unsigned char>(s.front())) || s.back() == '_') return false;
  for (char c : s)
    if (!(std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) ||
          c == '_'))
      return false;
  return s.find("__") == std::string::npos;
}

template <class E>
void check_table(const char* enum_name, bool unsolved_first, std::size_t expected_rows) {
  SCOPED_TRACE(enum_name);
  const auto table = core::status_table<E>();
  EXPECT_EQ(table.size(), expected_rows);
  std::set<std::string> names;
  std::set<int> values;
  for (const core::StatusEntry& row : table) {
    const std::string name = row.name;
    EXPECT_TRUE(is_snake_case(name)) << name;
    EXPECT_TRUE(names.insert(name).second) << "duplicate name " << name;
    EXPECT_TRUE(values.insert(row.value).second) << "duplicate value " << row.value;
    EXPECT_GT(std::string(row.message).size(), 3u) << name;
    const E e = static_cast<E>(row.value);
    EXPECT_EQ(std::string(core::status_name(e)), name);
    EXPECT_EQ(std::string(core::status_message(e)), std::string(row.message));
    EXPECT_EQ(core::status_from_name(row.name, static_cast<E>(-1)), e);
  }
  // values are 0..n-1: appended statuses keep the numbers of the old ones
  EXPECT_EQ(*values.begin(), 0);
  EXPECT_EQ(*values.rbegin(), static_cast<int>(table.size()) - 1);
  EXPECT_EQ(std::string(table.front().name) == "unsolved", unsolved_first);
  EXPECT_EQ(std::string(core::status_name(static_cast<E>(-1))), "unknown");
  EXPECT_EQ(core::status_from_name("no_such_status", static_cast<E>(-1)), static_cast<E>(-1));
}

}  // namespace

TEST(Status, EveryTableIsUniqueSnakeCaseUnsolvedFirst) {
  check_table<core::AdmmStatus>("AdmmStatus", true, 9);
  check_table<core::RiccatiStatus>("RiccatiStatus", true, 3);
  check_table<core::IlqrAdmmStatus>("IlqrAdmmStatus", true, 7);
  check_table<core::ScpStatus>("ScpStatus", true, 9);
  check_table<core::OdStatus>("OdStatus", true, 8);
  check_table<core::PropagationStatus>("PropagationStatus", true, 9);
  check_table<core::Dop853Status>("Dop853Status", true, 8);
  check_table<core::KeplerStatus>("KeplerStatus", true, 5);
  check_table<core::Verdict>("Verdict", false, 3);
}

TEST(Status, FilterTablesComeFromTheSameGenerator) {
  // filter/status.hpp declares its four enums with core's SATGNC_DEFINE_STATUS_ (no second copy of
  // the name / message switches); OrbitStepStatus's `not_run` plays the part of `unsolved`.
  check_table<core::FilterStatus>("FilterStatus", true, 10);
  check_table<core::ModelStatus>("ModelStatus", true, 3);
  check_table<core::EditFlag>("EditFlag", true, 5);
  check_table<core::OrbitStepStatus>("OrbitStepStatus", false, 6);
  static_assert(std::is_same_v<satgnc::filter::FilterStatus, core::FilterStatus>);
  static_assert(std::is_same_v<satgnc::filter::OrbitStepStatus, core::OrbitStepStatus>);
  // the names Python reads (satgnc._satgnc.FILTER_STEP_STATUS, by value) and the values are the old ones
  using S = satgnc::filter::OrbitStepStatus;
  const char* old_names[] = {
      "updated", "rejected", "propagation_failed", "measurement_failed", "not_positive_definite", "not_run"};
  for (int k = 0; k < 6; ++k) EXPECT_STREQ(satgnc::filter::status_name(static_cast<S>(k)), old_names[k]);
  EXPECT_STREQ(satgnc::filter::status_name(satgnc::filter::EditFlag::warm_up), "warm_up");
  EXPECT_STREQ(satgnc::filter::status_name(static_cast<S>(-1)), "unknown");
}

TEST(Status, NumericValuesAreTheOldOnes) {
  // Python keys results by these numbers (guidance.STATUS_NAMES, od/paper.py int(r.status.value))
  EXPECT_EQ(static_cast<int>(core::AdmmStatus::solved), 0);
  EXPECT_EQ(static_cast<int>(core::AdmmStatus::unsolved), 5);
  EXPECT_EQ(static_cast<int>(core::AdmmStatus::time_limit), 8);
  EXPECT_EQ(static_cast<int>(core::RiccatiStatus::unsolved), 2);
  EXPECT_EQ(static_cast<int>(core::IlqrAdmmStatus::unsolved), 4);
  EXPECT_EQ(static_cast<int>(core::IlqrAdmmStatus::time_limit), 6);
  EXPECT_EQ(static_cast<int>(core::ScpStatus::unsolved), 5);
  EXPECT_EQ(static_cast<int>(core::ScpStatus::time_limit), 8);
  EXPECT_EQ(static_cast<int>(core::OdStatus::converged), 0);
  EXPECT_EQ(static_cast<int>(core::OdStatus::unsolved), 6);
  EXPECT_EQ(static_cast<int>(core::OdStatus::stalled), 7);
  EXPECT_EQ(static_cast<int>(core::PropagationStatus::impact), 7);
  EXPECT_EQ(static_cast<int>(core::PropagationStatus::unsolved), 8);
  EXPECT_EQ(static_cast<int>(core::Dop853Status::event), 6);
  EXPECT_EQ(static_cast<int>(core::Dop853Status::unsolved), 7);
  EXPECT_EQ(static_cast<int>(core::KeplerStatus::unsolved), 4);
  EXPECT_EQ(static_cast<int>(core::Verdict::not_robustly_decidable), 2);
}

TEST(Status, MessagesUsersReadAreUnchanged) {
  EXPECT_STREQ(core::status_message(core::OdStatus::converged), "converged");
  EXPECT_STREQ(core::status_message(core::OdStatus::unsolved), "not solved yet");
  EXPECT_STREQ(core::status_message(core::PropagationStatus::success), "success");
  EXPECT_STREQ(core::status_message(core::Verdict::full_rank), "full rank");
  EXPECT_STREQ(core::status_message(core::Verdict::rank_deficient), "rank deficient");
  EXPECT_STREQ(core::status_message(core::AdmmStatus::unsolved), "not solved yet");
  EXPECT_NE(std::string(core::status_message(core::PropagationStatus::impact)).find("surface"),
            std::string::npos);
}

TEST(Status, RoomsReExportTheCoreEnums) {
  static_assert(std::is_same_v<satgnc::guidance::AdmmStatus, core::AdmmStatus>);
  static_assert(std::is_same_v<satgnc::guidance::RiccatiStatus, core::RiccatiStatus>);
  static_assert(std::is_same_v<satgnc::guidance::IlqrAdmmStatus, core::IlqrAdmmStatus>);
  static_assert(std::is_same_v<satgnc::guidance::ScpStatus, core::ScpStatus>);
  static_assert(std::is_same_v<satgnc::od::OdStatus, core::OdStatus>);
  static_assert(std::is_same_v<satgnc::propagation::PropagationStatus, core::PropagationStatus>);
  static_assert(std::is_same_v<satgnc::propagation::Dop853Status, core::Dop853Status>);
  static_assert(std::is_same_v<satgnc::propagation::KeplerStatus, core::KeplerStatus>);
  static_assert(std::is_same_v<satgnc::analysis::Verdict, core::Verdict>);
  // the room spelling of the message function still resolves
  EXPECT_STREQ(satgnc::guidance::status_message(satgnc::guidance::AdmmStatus::solved_paper_rule),
               core::status_message(core::AdmmStatus::solved_paper_rule));
  EXPECT_STREQ(satgnc::propagation::status_name(satgnc::propagation::PropagationStatus::too_much_work),
               "too_much_work");
}

TEST(Status, FreshResultsAreUnsolved) {
  EXPECT_EQ(satgnc::propagation::Trajectory{}.status, core::PropagationStatus::unsolved);
  EXPECT_EQ(satgnc::guidance::AdmmInfo{}.status, core::AdmmStatus::unsolved);
  EXPECT_EQ(satgnc::guidance::IlqrAdmmInfo{}.status, core::IlqrAdmmStatus::unsolved);
  EXPECT_EQ(satgnc::guidance::ScpInfo{}.status, core::ScpStatus::unsolved);
  EXPECT_EQ(satgnc::od::OdResult{}.info.status, core::OdStatus::unsolved);
  EXPECT_EQ(satgnc::propagation::Dop853Info{}.status, core::Dop853Status::unsolved);
  // every Info derives from the contract's base
  static_assert(std::is_base_of_v<core::InfoBase<core::AdmmStatus>, satgnc::guidance::AdmmInfo>);
  static_assert(std::is_base_of_v<core::InfoBase<core::ScpStatus>, satgnc::guidance::ScpInfo>);
  static_assert(std::is_base_of_v<core::InfoBase<core::OdStatus>, satgnc::od::OdInfo>);
  EXPECT_EQ(satgnc::guidance::ScpInfo{}.iterations, 0);
  EXPECT_EQ(satgnc::guidance::ScpInfo{}.solve_time, 0.0);
}

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
TEST(Status, OldSpellingsAreAliasesOfTheSameValue) {
  EXPECT_EQ(core::AdmmStatus::kSolved, core::AdmmStatus::solved);
  EXPECT_EQ(core::AdmmStatus::kUnsolved, core::AdmmStatus::unsolved);
  EXPECT_EQ(core::AdmmStatus::kTimeLimit, core::AdmmStatus::time_limit);
  EXPECT_EQ(core::RiccatiStatus::kOk, core::RiccatiStatus::solved);
  EXPECT_EQ(core::RiccatiStatus::kNotFactored, core::RiccatiStatus::unsolved);
  EXPECT_EQ(core::IlqrAdmmStatus::not_run, core::IlqrAdmmStatus::unsolved);
  EXPECT_EQ(core::ScpStatus::not_run, core::ScpStatus::unsolved);
  EXPECT_STREQ(satgnc::od::od_status_message(satgnc::od::OdStatus::stalled),
               core::status_message(core::OdStatus::stalled));
  EXPECT_STREQ(satgnc::propagation::kepler_status_message(core::KeplerStatus::overflow),
               core::status_message(core::KeplerStatus::overflow));
  EXPECT_STREQ(satgnc::propagation::dop853_status_message(core::Dop853Status::max_steps),
               core::status_message(core::Dop853Status::max_steps));
  EXPECT_STREQ(satgnc::analysis::verdict_name(core::Verdict::not_robustly_decidable),
               "not robustly decidable");
  // aliases are not table rows: status_name gives the new spelling
  EXPECT_STREQ(core::status_name(core::ScpStatus::not_run), "unsolved");
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
