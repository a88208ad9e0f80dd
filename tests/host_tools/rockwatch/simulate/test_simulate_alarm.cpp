// The instability alarm and the arithmetic choice through `rockwatch simulate`: --alarms lists the transitions
// (checked against sim::analyse in-process), the JSON and the help name the options.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_simulate_alarm {

using rockwatch::test::describe;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace sim = rockwatch::sim;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;
const char* const kElCentro180 = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2";

void check_ok(const ProcessResult& r) {
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

// El Centro 180 scaled to pga_g, as `simulate --scale-pga` scales it.
sim::GroundMotion el_centro_scaled(double pga_g) {
  const rockwatch::records::Record h = rockwatch::records::read_record(record_path(kElCentro180));
  sim::GroundMotion m;
  m.dt_s = h.dt_s;
  m.ug_mps2 = h.horizontal_mps2;
  const double factor = pga_g * kG / sim::peak_abs(m.ug_mps2);
  for (double& u : m.ug_mps2) u *= factor;
  return m;
}

std::vector<std::string> simulate_el_centro(const std::vector<std::string>& more) {
  return with({"simulate", "--record", record_path(kElCentro180), "--scale-pga", "0.25"}, more);
}

}  // namespace

TEST_GROUP(SimulateAlarm){};

// The look-ahead rule (--imminent-horizon, SPEC §11; 0.13 s by default since 2026-12-01) is named in the settings when
// on and absent at 0, and it can only bring IMMINENT earlier (it adds a condition; the others are unchanged).
TEST(SimulateAlarm, TheImminentHorizonIsNamedWhenOnAndOnlyBringsImminentEarlier) {
  const ProcessResult by_default = run_rockwatch(simulate_el_centro({"--alarms", "--json"}));
  check_ok(by_default);
  const nlohmann::json default_settings = nlohmann::json::parse(by_default.out)["alarm"]["settings"];
  DOUBLES_EQUAL(0.13, default_settings["imminent_horizon_s"].get<double>(), 0.0);
  const ProcessResult off = run_rockwatch(simulate_el_centro({"--alarms", "--json", "--imminent-horizon", "0"}));
  const ProcessResult on = run_rockwatch(simulate_el_centro({"--alarms", "--json", "--imminent-horizon", "0.3"}));
  check_ok(off);
  check_ok(on);
  const nlohmann::json a_off = nlohmann::json::parse(off.out)["alarm"];
  const nlohmann::json a_on = nlohmann::json::parse(on.out)["alarm"];
  CHECK_FALSE(a_off["settings"].contains("imminent_horizon_s"));
  DOUBLES_EQUAL(0.3, a_on["settings"]["imminent_horizon_s"].get<double>(), 0.0);
  CHECK_TRUE(a_on["t_first_imminent_s"].get<double>() <= a_off["t_first_imminent_s"].get<double>());
  const ProcessResult text = run_rockwatch(simulate_el_centro({"--alarms", "--imminent-horizon", "0.3"}));
  check_ok(text);
  CHECK_TEXT(text.out.find("predicted within 0.3 s") != std::string::npos, text.out.c_str());
}

// The energy rule's displacement (--energy-min-x, SPEC §11; 0.5 by default since 2026-12-01): named when on, absent
// at 0, and it can only bring IMMINENT later (it removes part of a condition); at 1 the energy margin never decides
// before |x| ≥ x_inst, so IMMINENT comes no earlier than the first exceedance of x_inst (the horizon off here: it is
// not gated); out of [0, 1] or without --alarms an error naming it.
TEST(SimulateAlarm, TheEnergyRulesDisplacementIsNamedWhenOnAndOnlyDelaysImminent) {
  const ProcessResult by_default = run_rockwatch(simulate_el_centro({"--alarms", "--json"}));
  check_ok(by_default);
  DOUBLES_EQUAL(0.5, nlohmann::json::parse(by_default.out)["alarm"]["settings"]["energy_min_x"].get<double>(), 0.0);
  const auto without_horizon = [](std::vector<std::string> a) {
    a.insert(a.end(), {"--imminent-horizon", "0"});
    return simulate_el_centro(a);
  };
  const ProcessResult off = run_rockwatch(without_horizon({"--alarms", "--json", "--energy-min-x", "0"}));
  const ProcessResult half = run_rockwatch(without_horizon({"--alarms", "--json", "--energy-min-x", "0.5"}));
  const ProcessResult one = run_rockwatch(without_horizon({"--alarms", "--json", "--energy-min-x", "1"}));
  check_ok(off);
  check_ok(half);
  check_ok(one);
  const nlohmann::json j_off = nlohmann::json::parse(off.out), j_one = nlohmann::json::parse(one.out);
  const nlohmann::json a_off = j_off["alarm"], a_half = nlohmann::json::parse(half.out)["alarm"], a_one = j_one["alarm"];
  CHECK_FALSE(a_off["settings"].contains("energy_min_x"));
  DOUBLES_EQUAL(0.5, a_half["settings"]["energy_min_x"].get<double>(), 0.0);
  const double t_off = a_off["t_first_imminent_s"].get<double>(), t_half = a_half["t_first_imminent_s"].get<double>(),
               t_one = a_one["t_first_imminent_s"].get<double>();
  CHECK(t_off <= t_half && t_half <= t_one);
  CHECK(t_off < t_one);  // the energy margin decided this record's first IMMINENT before x_inst
  DOUBLES_EQUAL(j_one["t_exceed_s"].get<double>(), t_one, 0.011);  // at the first exceedance (a sample later at most)
  CHECK(t_one >= j_one["t_exceed_s"].get<double>() - 1e-9);
  const ProcessResult text = run_rockwatch(simulate_el_centro({"--alarms", "--energy-min-x", "0.5"}));
  check_ok(text);
  CHECK_TEXT(text.out.find("only from |x| >= 0.5 x_inst") != std::string::npos, text.out.c_str());
  const ProcessResult bad = run_rockwatch(simulate_el_centro({"--alarms", "--energy-min-x", "1.5"}));
  CHECK_EQUAL(2, bad.exit_status);
  CHECK_TEXT(bad.err.find("--energy-min-x must be in [0, 1]") != std::string::npos, bad.err.c_str());
  const ProcessResult lone = run_rockwatch(simulate_el_centro({"--energy-min-x", "0.5"}));
  CHECK_TEXT(lone.err.find("--energy-min-x sets the instability alarm") != std::string::npos, lone.err.c_str());
}

TEST(SimulateAlarm, CollapseIsForetoldByWarningThenImminentAtIncreasingTimes) {
  const ProcessResult r = run_rockwatch(simulate_el_centro({"--alarms", "--json"}));
  check_ok(r);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK_TRUE(j["collapsed"].get<bool>());
  const nlohmann::json& a = j["alarm"];
  STRCMP_EQUAL("COLLAPSED", a["max_level"].get<std::string>().c_str());
  const double t_warning = a["t_first_warning_s"].get<double>();
  const double t_imminent = a["t_first_imminent_s"].get<double>();
  const double t_collapsed = a["t_first_collapsed_s"].get<double>();
  CHECK_TRUE(t_warning < t_imminent);
  CHECK_TRUE(t_imminent < t_collapsed);
  DOUBLES_EQUAL(j["t_collapse_s"].get<double>(), t_collapsed, 1e-12);
  DOUBLES_EQUAL(0.4, a["settings"]["lambda_warning"].get<double>(), 0.0);
  DOUBLES_EQUAL(1.0, a["settings"]["hold_s"].get<double>(), 0.0);
  DOUBLES_EQUAL(1.5, a["settings"]["energy_margin"].get<double>(), 0.0);

  const nlohmann::json& transitions = a["transitions"];
  LONGS_EQUAL(a["n_transitions"].get<std::size_t>(), transitions.size());
  CHECK_TRUE(transitions.size() >= 3);
  double t_previous = 0.0;
  std::string previous_level = "QUIET";
  std::vector<std::string> levels;
  for (const nlohmann::json& t : transitions) {
    CHECK_TRUE(t["t_s"].get<double>() > t_previous);
    t_previous = t["t_s"].get<double>();
    STRCMP_EQUAL(previous_level.c_str(), t["previous"].get<std::string>().c_str());
    previous_level = t["level"].get<std::string>();
    levels.push_back(previous_level);
    CHECK_TRUE(t["reasons"].is_array() && !t["reasons"].empty());
    CHECK_TRUE(t["x_m"].is_number() && t["xd_mps"].is_number() && t["energy_ratio"].is_number());
    CHECK_TRUE(t["t_to_instability_s"].is_null() || t["t_to_instability_s"].get<double>() >= 0.0);
  }
  // WARNING comes first, then IMMINENT, before the last transition, to COLLAPSED at the collapse.
  std::size_t first_warning = levels.size(), first_imminent = levels.size();
  for (std::size_t i = 0; i < levels.size(); ++i) {
    if (levels[i] == "WARNING" && first_warning == levels.size()) first_warning = i;
    if (levels[i] == "IMMINENT" && first_imminent == levels.size()) first_imminent = i;
  }
  CHECK_TRUE(first_warning < first_imminent);
  CHECK_TRUE(first_imminent + 1 < levels.size());
  STRCMP_EQUAL("COLLAPSED", levels.back().c_str());
  const nlohmann::json& last = transitions.back();
  DOUBLES_EQUAL(0.0, last["t_to_instability_s"].get<double>(), 0.0);
  std::set<std::string> reasons;
  for (const nlohmann::json& name : last["reasons"]) reasons.insert(name.get<std::string>());
  CHECK_TRUE(reasons.count("over_collapse_displacement") == 1);
  CHECK_TRUE(reasons.count("over_instability_displacement") == 1);
  CHECK_FALSE(j.contains("arithmetic"));  // only with --arith
}

TEST(SimulateAlarm, JsonEqualsTheEngineCalledInProcess) {
  const nlohmann::json j = nlohmann::json::parse(
      run_rockwatch(simulate_el_centro({"--alarms", "--lambda-w", "0.3", "--alarm-hold", "0.5", "--energy-margin",
                                        "1.2", "--arith", "double", "--json"}))
          .out);
  sim::AnalysisOptions o;
  o.evaluate_alarm = true;
  o.alarm = rockwatch::core::AlarmSettings{0.3, 0.5, 1.2};
  o.max_alarm_transitions_kept = 1000;
  const sim::AnalysisResult e = sim::analyse(rockwatch::core::paper_wall(), el_centro_scaled(0.25), o);
  const nlohmann::json& a = j["alarm"];
  STRCMP_EQUAL("double", j["arithmetic"].get<std::string>().c_str());
  CHECK_FALSE(j.contains("saturated"));  // fixed point only
  DOUBLES_EQUAL(0.3, a["settings"]["lambda_warning"].get<double>(), 0.0);
  DOUBLES_EQUAL(*e.alarm.t_first_imminent_s, a["t_first_imminent_s"].get<double>(), 1e-12);
  DOUBLES_EQUAL(*e.alarm.t_first_warning_s, a["t_first_warning_s"].get<double>(), 1e-12);
  LONGS_EQUAL(e.alarm.n_transitions, a["n_transitions"].get<std::size_t>());
  LONGS_EQUAL(e.alarm.transitions.size(), a["transitions"].size());
  for (std::size_t i = 0; i < e.alarm.transitions.size(); ++i) {
    const sim::AlarmTransition& t = e.alarm.transitions[i];
    const nlohmann::json& jt = a["transitions"][i];
    DOUBLES_EQUAL(t.t_s, jt["t_s"].get<double>(), 1e-12);
    STRCMP_EQUAL(rockwatch::core::alarm_level_name(t.level), jt["level"].get<std::string>().c_str());
    LONGS_EQUAL(t.reasons, jt["reason_bits"].get<std::uint32_t>());
    DOUBLES_EQUAL(t.x_m, jt["x_m"].get<double>(), 1e-15);
    DOUBLES_EQUAL(t.energy_ratio, jt["energy_ratio"].get<double>(), 1e-12);
    CHECK_EQUAL(t.t_to_instability_s.has_value(), !jt["t_to_instability_s"].is_null());
  }
}

TEST(SimulateAlarm, HumanOutputListsTheTransitions) {
  const ProcessResult r = run_rockwatch(simulate_el_centro({"--alarms"}));
  check_ok(r);
  for (const char* text : {"Instability alarm", "highest level", "COLLAPSED", "first WARNING", "first IMMINENT",
                           "transitions", "WARNING", "IMMINENT", "over_warning_displacement",
                           "over_collapse_displacement", "t_inst", "double precision"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
  const ProcessResult plain = run_rockwatch(simulate_el_centro({}));
  check_ok(plain);
  CHECK_TRUE(plain.out.find("Instability alarm") == std::string::npos);
}

TEST(SimulateAlarm, FixedPointArithmeticIsReported) {
  const ProcessResult r = run_rockwatch(simulate_el_centro({"--arith", "fixed", "--alarms", "--json"}));
  check_ok(r);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  STRCMP_EQUAL("fixed", j["arithmetic"].get<std::string>().c_str());
  CHECK_TRUE(j["saturated"].is_boolean());
  STRCMP_EQUAL("COLLAPSED", j["alarm"]["max_level"].get<std::string>().c_str());
  const ProcessResult text = run_rockwatch(simulate_el_centro({"--arith", "fixed"}));
  check_ok(text);
  STRCMP_CONTAINS("fixed point", text.out.c_str());
}

TEST(SimulateAlarm, HelpListsTheOptions) {
  const ProcessResult r = run_rockwatch({"simulate", "--help"});
  check_ok(r);
  for (const char* text : {"--arith", "--alarms", "--lambda-w", "--alarm-hold", "--energy-margin", "IMMINENT"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
}

}  // namespace unity_test_simulate_alarm
