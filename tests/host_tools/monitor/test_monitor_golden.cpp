// Offline golden replay: the shipped input log (suite set 1 X at 0.40 g, 8 s at 200 Hz: the wall collapses) through
// `rockwatch-monitor --offline-in/--offline-out`; the decoded output (every alarm event, a digest and summary of every
// wall_state, every status) compared with the committed golden file. ROCKWATCH_REGENERATE_GOLDEN=1 rewrites it
// (tests/data/monitor/README.md). Also: the run is deterministic byte for byte, stdout carries the same alarm events,
// the alarm timeline equals `rockwatch simulate --arith fixed --alarms` on the same record, the shipped log is what
// the generator makes from the suite, and the offline adapter's own handling of odd logs.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "monitor_config.hpp"
#include "monitor_output.hpp"
#include "monitor_test_support.hpp"
#include "rockwatch/ground_accel_t.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_monitor_golden {

using nlohmann::json;
using rockwatch::test::monitor_data_path;
using rockwatch::test::OutputLog;
using rockwatch::test::ProcessResult;
using rockwatch::test::TempDir;

namespace {

constexpr const char* kRegenerateVariable = "ROCKWATCH_REGENERATE_GOLDEN";
constexpr std::int64_t kLogStartUtime = 1700000000000000;  // make_monitor_log's first sample time
constexpr double kLogSeconds = 8.0;
const std::vector<std::string> kSimulateArgs{"--suite",     std::string(ROCKWATCH_SOURCE_DIR) + "/sim/suites/npr9998-2015",
                                             "--set",       "1",
                                             "--component", "X",
                                             "--scale-pga", "0.40"};

std::string describe(const ProcessResult& r) {
  return "exit " + std::to_string(r.exit_status) + " signal " + std::to_string(r.signal) + "\nstdout:\n" +
         r.out.substr(0, 4000) + "\nstderr:\n" + r.err.substr(0, 4000);
}

ProcessResult run_offline(const std::string& in, const std::string& out, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args{"--offline-in", in, "--offline-out", out};
  args.insert(args.end(), extra.begin(), extra.end());
  return rockwatch::test::run_monitor(args);
}

json status_json(const OutputLog::Status& s) {
  const rockwatch::monitor_status_t& m = s.message;
  return json{{"event_utime", s.event_utime},
              {"utime", m.utime},
              {"seq", m.seq},
              {"schema_version", m.schema_version},
              {"config_digest", rockwatch::monitor::digest_hex(m.config_digest)},
              {"samples_received", m.samples_received},
              {"samples_processed", m.samples_processed},
              {"samples_bridged", m.samples_bridged},
              {"gaps", m.gaps},
              {"state_resets", m.state_resets},
              {"duplicates", m.duplicates},
              {"out_of_order", m.out_of_order},
              {"late", m.late},
              {"rejected_not_finite", m.rejected_not_finite},
              {"rejected_out_of_range", m.rejected_out_of_range},
              {"lift_off", m.lift_off},
              {"publisher_restarts", m.publisher_restarts},
              {"decode_errors", m.decode_errors},
              {"saturated", m.saturated},
              {"worst_step_ns", m.worst_step_ns},
              {"sensor_flags", m.sensor_flags},
              {"messages_ignored", m.messages_ignored},
              {"publish_failures", m.publish_failures},
              {"log_write_failures", m.log_write_failures},
              {"time_untrusted", m.time_untrusted},
              {"datagrams_rejected", m.datagrams_rejected},
              {"datagrams_from_other_sources", m.datagrams_from_other_sources},
              {"arithmetic", m.arithmetic},
              {"data_quality", m.data_quality},
              {"alarm_level", rockwatch::monitor::level_name(m.alarm_level)}};
}

json state_json(const OutputLog::State& s) {
  const rockwatch::wall_state_t& m = s.message;
  return json{{"event_utime", s.event_utime}, {"utime", m.utime},
              {"seq", m.seq},                 {"input_seq", m.input_seq},
              {"x_m", m.x_m},                 {"xd_mps", m.xd_mps},
              {"theta1_rad", m.theta1_rad},   {"side", m.side},
              {"moving", m.moving},           {"energy_ratio", m.energy_ratio},
              {"alarm_level", rockwatch::monitor::level_name(m.alarm_level)},
              {"alarm_reasons", m.alarm_reasons},
              {"t_to_instability_s", m.t_to_instability_s},
              {"data_quality", m.data_quality}};
}

// What the golden file pins down: every alarm event and status in full, the wall states by digest and summary.
json golden_view(const OutputLog& log) {
  json alarms = json::array();
  for (const OutputLog::Alarm& a : log.alarms) {
    json j = rockwatch::monitor::alarm_json(a.message);
    j["event_utime"] = a.event_utime;
    j["schema_version"] = a.message.schema_version;
    alarms.push_back(j);
  }
  json statuses = json::array();
  for (const OutputLog::Status& s : log.statuses) statuses.push_back(status_json(s));
  json states;
  states["count"] = log.states.size();
  states["digest"] = rockwatch::monitor::digest_hex(static_cast<std::int64_t>(log.state_digest));
  if (!log.states.empty()) {
    double max_abs_x = 0.0;
    std::int64_t moving = 0;
    bool seq_contiguous = true;
    for (std::size_t i = 0; i < log.states.size(); ++i) {
      const rockwatch::wall_state_t& m = log.states[i].message;
      max_abs_x = std::fmax(max_abs_x, std::fabs(m.x_m));
      moving += m.moving;
      seq_contiguous = seq_contiguous && m.seq == log.states.front().message.seq + static_cast<std::int64_t>(i);
    }
    states["max_abs_x_m"] = max_abs_x;
    states["samples_moving"] = moving;
    states["seq_contiguous"] = seq_contiguous;
    states["first"] = state_json(log.states.front());
    states["last"] = state_json(log.states.back());
  }
  return json{{"output_events", log.events},
              {"other_channels", log.other_channels},
              {"alarms", alarms},
              {"wall_state", states},
              {"status", statuses}};
}

std::string first_differences(const json& expected, const json& actual) {
  const json patch = json::diff(expected, actual);
  std::string text;
  for (std::size_t i = 0; i < patch.size() && i < 12; ++i) text += patch[i].dump() + "\n";
  if (patch.size() > 12) text += "... " + std::to_string(patch.size() - 12) + " more\n";
  return text;
}

bool regenerating() {
  const char* v = std::getenv(kRegenerateVariable);
  return v != nullptr && std::string(v) == "1";
}

}  // namespace

TEST_GROUP(MonitorGoldenReplay){};

TEST(MonitorGoldenReplay, OfflineOutputMatchesTheGoldenFile) {
  const TempDir dir;
  const std::string in = monitor_data_path(rockwatch::test::kShippedLog);
  const std::string out = dir.file("monitor.lcmlog");
  const ProcessResult r = run_offline(in, out);
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
  const OutputLog log = rockwatch::test::read_output_log(out);
  const json actual = golden_view(log);

  const std::string golden_path = monitor_data_path(rockwatch::test::kGoldenFile);
  if (regenerating()) {
    const json file{
        {"about",
         {{"what", "rockwatch-monitor --offline-in " + std::string(rockwatch::test::kShippedLog) +
                       " --offline-out OUT (default settings), OUT decoded by tests/host_tools/monitor/test_monitor_golden.cpp"},
          {"input", "tests/data/monitor/README.md"},
          {"regenerate", std::string(kRegenerateVariable) + "=1 build/release/tests/host_tools/monitor/test_monitor -g MonitorGoldenReplay"}}},
        {"expected", actual}};
    rockwatch::test::write_file(golden_path, file.dump(1) + "\n");
    UT_PRINT(("rewrote " + golden_path).c_str());
    return;
  }
  const std::string text = rockwatch::test::read_file(golden_path);
  CHECK_TEXT(!text.empty(), ("missing golden file " + golden_path + " (run with " + kRegenerateVariable + "=1)").c_str());
  const json expected = json::parse(text).at("expected");
  CHECK_TEXT(expected == actual, ("offline output differs from " + golden_path + " (JSON patch golden -> actual):\n" +
                                  first_differences(expected, actual) + "If the change is intended, rerun with " +
                                  kRegenerateVariable + "=1 and commit the file.")
                                     .c_str());

  // What the golden run must show, whatever the file says: the wall collapses, one state per sample.
  LONGS_EQUAL(1601, log.states.size());
  CHECK(!log.alarms.empty());
  STRCMP_EQUAL("COLLAPSED", rockwatch::monitor::level_name(log.alarms.back().message.level).c_str());
  CHECK(log.other_channels.empty());
}

TEST(MonitorGoldenReplay, DeterministicAndStdoutCarriesTheSameAlarms) {
  const TempDir dir;
  const std::string in = monitor_data_path(rockwatch::test::kShippedLog);
  const ProcessResult first = run_offline(in, dir.file("a.lcmlog"));
  const ProcessResult second = run_offline(in, dir.file("b.lcmlog"));
  CHECK_EQUAL_TEXT(0, first.exit_status, describe(first).c_str());
  CHECK_EQUAL_TEXT(0, second.exit_status, describe(second).c_str());
  const std::string a = rockwatch::test::read_file(dir.file("a.lcmlog"));
  const std::string b = rockwatch::test::read_file(dir.file("b.lcmlog"));
  CHECK(!a.empty());
  CHECK_TEXT(a == b, "two offline runs of one log wrote different output logs");

  // stdout: one JSON line per alarm event of the log, then the summary; identical across runs except the output path.
  const OutputLog log = rockwatch::test::read_output_log(dir.file("a.lcmlog"));
  const std::vector<json> lines = rockwatch::test::json_lines(first.out);
  LONGS_EQUAL(log.alarms.size() + 1, lines.size());
  for (std::size_t i = 0; i < log.alarms.size(); ++i) {
    CHECK_TEXT(lines[i] == rockwatch::monitor::alarm_json(log.alarms[i].message), lines[i].dump().c_str());
    for (const char* key : {"utime", "seq", "level", "reason", "x_m", "t_to_instability_s"}) {
      CHECK_TEXT(lines[i].contains(key), key);
    }
  }
  const json& summary = lines.back().at("summary");
  STRCMP_EQUAL("offline", summary.at("mode").get<std::string>().c_str());
  STRCMP_EQUAL("end of log", summary.at("stopped_by").get<std::string>().c_str());
  LONGS_EQUAL(1601, summary.at("log_events").get<long>());
  LONGS_EQUAL(1601, summary.at("counters").at("samples_received").get<long>());
  LONGS_EQUAL(1601, summary.at("counters").at("samples_processed").get<long>());
  LONGS_EQUAL(log.events, summary.at("output_events").get<long>());
  CHECK(summary.at("input_log_complete").get<bool>());
  STRCMP_EQUAL("COLLAPSED", summary.at("alarm_level").get<std::string>().c_str());
  // Statuses: one at the first event, one per second of log time (8 s), one at the end; LCM log time.
  LONGS_EQUAL(10, log.statuses.size());
  LONGS_EQUAL(10, summary.at("status_published").get<long>());
  CHECK(log.statuses.back().message.samples_received == 1601);
  // Output events carry the timestamps of the input events (1 ms after the sample time), never the wall clock: the
  // sample's own, or a later sample's when the engine finished it at a later call (carry-over, at most
  // max_late_calls later).
  const long max_late = summary.at("counters").at("max_late_calls").get<long>();
  for (const OutputLog::State& s : log.states) {
    const std::int64_t later_us = s.event_utime - (s.message.utime + 1000);
    CHECK_TRUE(later_us >= 0 && later_us % 5000 == 0 && later_us / 5000 <= max_late);
  }
  json first_summary = summary, second_summary = rockwatch::test::json_lines(second.out).back().at("summary");
  first_summary.erase("output_log");
  second_summary.erase("output_log");
  CHECK_TEXT(first_summary == second_summary, second_summary.dump().c_str());
  CHECK(first.err.find("offline: 1601 log events") != std::string::npos);
}

namespace {

// `rockwatch simulate` on a record (default: the shipped log's, suite set 1 X at 0.40 g) with these options after
// --alarms --json.
json simulate_json(const std::vector<std::string>& options, const std::vector<std::string>& record = kSimulateArgs) {
  std::vector<std::string> args{"simulate"};
  args.insert(args.end(), record.begin(), record.end());
  args.insert(args.end(), {"--alarms", "--json"});
  args.insert(args.end(), options.begin(), options.end());
  const ProcessResult sim = rockwatch::test::run_rockwatch(args);
  CHECK_EQUAL_TEXT(0, sim.exit_status, describe(sim).c_str());
  return json::parse(sim.out);
}

// The sample at the end of the step simulate reports (or in which it located the collapse): the sample that ends it.
std::int64_t sample_of(double t_s) { return static_cast<std::int64_t>(std::ceil(t_s / 0.005 - 1e-6)); }

// The sample of the monitor's first IMMINENT (its alarm event's input_seq − 1); -1 when none.
std::int64_t first_imminent_sample(const OutputLog& log) {
  for (const OutputLog::Alarm& a : log.alarms) {
    if (rockwatch::monitor::level_name(a.message.level) == "IMMINENT") return a.message.input_seq - 1;
  }
  return -1;
}

// Every transition simulate reports within the logged 8 s against the monitor's alarm events: the same sample,
// level, reasons and state.
void expect_simulate_transitions(const json& sim_json, const OutputLog& log) {
  std::vector<json> expected;
  for (const json& t : sim_json.at("alarm").at("transitions")) {
    if (t.at("t_s").get<double>() <= kLogSeconds + 1e-9) expected.push_back(t);
  }
  CHECK(expected.size() >= 3);
  LONGS_EQUAL(expected.size(), log.alarms.size());
  for (std::size_t i = 0; i < expected.size() && i < log.alarms.size(); ++i) {
    const json& e = expected[i];
    const rockwatch::alarm_event_t& m = log.alarms[i].message;
    const std::string what = e.dump() + "\nvs\n" + rockwatch::monitor::alarm_json(m).dump();
    // simulate reports the step's end, or the collapse located inside the step: the sample that ends that step.
    const std::int64_t sample = sample_of(e.at("t_s").get<double>());
    LONGS_EQUAL_TEXT(kLogStartUtime + sample * 5000, m.utime, what.c_str());
    LONGS_EQUAL_TEXT(1 + sample, m.input_seq, what.c_str());
    STRCMP_EQUAL_TEXT(e.at("level").get<std::string>().c_str(), rockwatch::monitor::level_name(m.level).c_str(),
                      what.c_str());
    STRCMP_EQUAL_TEXT(e.at("previous").get<std::string>().c_str(),
                      rockwatch::monitor::level_name(m.previous_level).c_str(), what.c_str());
    LONGS_EQUAL_TEXT(e.at("reason_bits").get<long>(), m.reasons, what.c_str());
    DOUBLES_EQUAL_TEXT(e.at("x_m").get<double>(), m.x_m, 1e-12, what.c_str());
    DOUBLES_EQUAL_TEXT(e.at("xd_mps").get<double>(), m.xd_mps, 1e-12, what.c_str());
    DOUBLES_EQUAL_TEXT(e.at("energy_ratio").get<double>(), m.energy_ratio, 1e-9, what.c_str());
    const json& t_inst = e.at("t_to_instability_s");
    if (t_inst.is_null()) {
      DOUBLES_EQUAL_TEXT(-1.0, m.t_to_instability_s, 0.0, what.c_str());
    } else {
      DOUBLES_EQUAL_TEXT(t_inst.get<double>(), m.t_to_instability_s, 1e-9, what.c_str());
    }
  }
}

}  // namespace

TEST(MonitorGoldenReplay, AlarmTimelineEqualsSimulateFixed) {
  // The same record through `rockwatch simulate --arith fixed --alarms`: the monitor's engine starts from the first
  // sample as simulate does, so every transition in the logged 8 s has the same time, level, reasons and state.
  const json sim_json = simulate_json({"--arith", "fixed"});
  const TempDir dir;
  const ProcessResult r = run_offline(monitor_data_path(rockwatch::test::kShippedLog), dir.file("out.lcmlog"));
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  expect_simulate_transitions(sim_json, rockwatch::test::read_output_log(dir.file("out.lcmlog")));
}

// The look-ahead (issue 40): `--imminent-horizon 0.17` gives the monitor simulate's alarm with the same horizon,
// every transition and so the first IMMINENT, with either engine (the fixed-point one: the firmware's indicators).
// Suite set 2 X at 0.30 g (the shipped log's record does not tell: there the horizon changes nothing): the wall
// collapses at 4.65 s, IMMINENT at 3.755 s without the horizon, 3.4 s with it, so a monitor that dropped the setting
// fails here. The file's alarm.imminent_horizon_s is the same run, byte for byte.
TEST(MonitorGoldenReplay, TheImminentHorizonGivesSimulatesFirstImminent) {
  const TempDir dir;
  const std::vector<std::string> record{"--suite", std::string(ROCKWATCH_SOURCE_DIR) + "/sim/suites/npr9998-2015",
                                        "--set", "2", "--component", "X", "--scale-pga", "0.30"};
  const std::string in = dir.file("in.lcmlog");
  std::vector<std::string> make{in, "8"};
  make.insert(make.end(), record.begin(), record.end());
  const ProcessResult made = rockwatch::test::run_program(ROCKWATCH_MAKE_MONITOR_LOG_PATH, make);
  CHECK_EQUAL_TEXT(0, made.exit_status, describe(made).c_str());
  for (const std::string arith : {"fixed", "double"}) {
    const json sim_off = simulate_json({"--arith", arith}, record);
    const json sim_on = simulate_json({"--arith", arith, "--imminent-horizon", "0.17"}, record);
    DOUBLES_EQUAL(0.17, sim_on.at("alarm").at("settings").at("imminent_horizon_s").get<double>(), 0.0);
    const double t_off = sim_off.at("alarm").at("t_first_imminent_s").get<double>();
    const double t_on = sim_on.at("alarm").at("t_first_imminent_s").get<double>();
    const std::string times = arith + ": simulate's first IMMINENT " + std::to_string(t_on) + " s with the horizon, " +
                              std::to_string(t_off) + " s without";
    CHECK_TEXT(sample_of(t_on) < sample_of(t_off), times.c_str());

    const std::string off_log = dir.file(arith + "_off.lcmlog"), on_log = dir.file(arith + "_on.lcmlog");
    const ProcessResult off = run_offline(in, off_log, {"--arith", arith});
    const ProcessResult on = run_offline(in, on_log, {"--arith", arith, "--imminent-horizon", "0.17"});
    CHECK_EQUAL_TEXT(0, off.exit_status, describe(off).c_str());
    CHECK_EQUAL_TEXT(0, on.exit_status, describe(on).c_str());
    const OutputLog log_off = rockwatch::test::read_output_log(off_log);
    const OutputLog log_on = rockwatch::test::read_output_log(on_log);
    LONGS_EQUAL_TEXT(sample_of(t_on), first_imminent_sample(log_on), times.c_str());
    LONGS_EQUAL_TEXT(sample_of(t_off), first_imminent_sample(log_off), times.c_str());
    expect_simulate_transitions(sim_on, log_on);
    expect_simulate_transitions(sim_off, log_off);

    const std::string config = dir.file(arith + ".json"), file_log = dir.file(arith + "_file.lcmlog");
    rockwatch::test::write_file(config, R"({"alarm": {"imminent_horizon_s": 0.17}})");
    const ProcessResult file = run_offline(in, file_log, {"--arith", arith, "--config", config});
    CHECK_EQUAL_TEXT(0, file.exit_status, describe(file).c_str());
    CHECK_TEXT(rockwatch::test::read_file(file_log) == rockwatch::test::read_file(on_log),
               (arith + ": alarm.imminent_horizon_s and --imminent-horizon wrote different logs").c_str());
  }
}

// With the Cortex-M4 firmware's work budget (--work-budget, carry-over): the same alarm events, a sample whose work
// does not fit one call published at a later sample's event; the IMMINENT at the sample that simulate's
// alarm.published names (the study's "as published" figures are this monitor's). The alarm's rules before 2026-12-01
// (no horizon, the margin from the vertical): their IMMINENT on this log falls on a sample the budget delays; the
// defaults' falls on one it does not, and the late publication is what this checks.
TEST(MonitorGoldenReplay, WithTheFirmwaresWorkBudgetTheSameEventsArePublishedWhereSimulateSays) {
  const TempDir dir;
  const std::string in = monitor_data_path(rockwatch::test::kShippedLog);
  const std::vector<std::string> rules{"--imminent-horizon", "0", "--energy-min-x", "0"};
  const ProcessResult plain = run_offline(in, dir.file("plain.lcmlog"), rules);
  std::vector<std::string> with_budget = rules;
  with_budget.insert(with_budget.end(), {"--work-budget", "23000"});
  const ProcessResult budgeted = run_offline(in, dir.file("budget.lcmlog"), with_budget);
  CHECK_EQUAL_TEXT(0, plain.exit_status, describe(plain).c_str());
  CHECK_EQUAL_TEXT(0, budgeted.exit_status, describe(budgeted).c_str());
  const OutputLog a = rockwatch::test::read_output_log(dir.file("plain.lcmlog"));
  const OutputLog b = rockwatch::test::read_output_log(dir.file("budget.lcmlog"));
  LONGS_EQUAL(a.states.size(), b.states.size());
  for (std::size_t i = 0; i < a.states.size(); ++i) {
    CHECK_TRUE(a.states[i].message.input_seq == b.states[i].message.input_seq);
    CHECK_TRUE(a.states[i].message.x_m == b.states[i].message.x_m);
    CHECK_TRUE(a.states[i].event_utime <= b.states[i].event_utime);
  }
  LONGS_EQUAL(a.alarms.size(), b.alarms.size());
  std::int64_t imminent_event_utime = 0;
  for (std::size_t i = 0; i < a.alarms.size(); ++i) {
    CHECK_TRUE(a.alarms[i].message.input_seq == b.alarms[i].message.input_seq);
    CHECK_TRUE(a.alarms[i].message.level == b.alarms[i].message.level);
    CHECK_TRUE(a.alarms[i].message.x_m == b.alarms[i].message.x_m);
    if (rockwatch::monitor::level_name(b.alarms[i].message.level) == "IMMINENT") {
      imminent_event_utime = b.alarms[i].event_utime;
    }
  }
  const json counters = rockwatch::test::json_lines(budgeted.out).back().at("summary").at("counters");
  CHECK_TRUE(counters.at("samples_late").get<long>() > 0);
  LONGS_EQUAL(0, counters.at("samples_work_shed").get<long>());
  CHECK_TRUE(imminent_event_utime > 0);

  std::vector<std::string> args{"simulate"};
  args.insert(args.end(), kSimulateArgs.begin(), kSimulateArgs.end());
  args.insert(args.end(), {"--arith", "fixed", "--alarms", "--json"});
  args.insert(args.end(), rules.begin(), rules.end());
  const ProcessResult sim = rockwatch::test::run_rockwatch(args);
  CHECK_EQUAL_TEXT(0, sim.exit_status, describe(sim).c_str());
  const json published = json::parse(sim.out).at("alarm").at("published");
  LONGS_EQUAL(23000, published.at("work_budget_units").get<long>());
  STRCMP_EQUAL("shed", published.at("work_overflow").get<std::string>().c_str());
  LONGS_EQUAL(0, published.at("overruns").get<long>());
  CHECK_TRUE(published.at("max_call_units").get<long>() <= 23000);
  const auto sample = static_cast<std::int64_t>(std::llround(published.at("t_first_imminent_s").get<double>() / 0.005));
  // Output events carry the time of the input event whose call finished them: the sample's time + 1 ms.
  LONGS_EQUAL(kLogStartUtime + sample * 5000 + 1000, imminent_event_utime);
  CHECK_TRUE(published.at("imminent_late_samples").get<long>() >= 1);
}

// The firmware's policy at a full queue, end to end through the monitor process: a wall settling at r_ana (set 1 X
// at 0.12 g) chatters long enough to fill the engine's queue of 64 samples. --work-overflow finish publishes every
// state exactly as the monitor without a budget does (overruns counted, nothing shed); the default, shed, keeps every
// call within the budget and counts the samples it shed.
TEST(MonitorGoldenReplay, AtAFullQueueFinishKeepsEveryStateAndShedCountsWhatItShed) {
  const TempDir dir;
  std::vector<std::string> make{dir.file("in.lcmlog"), "8", "--suite", std::string(ROCKWATCH_SOURCE_DIR) + "/sim/suites/npr9998-2015",
                                "--set", "1", "--component", "X", "--scale-pga", "0.12"};
  const ProcessResult made = rockwatch::test::run_program(ROCKWATCH_MAKE_MONITOR_LOG_PATH, make);
  CHECK_EQUAL_TEXT(0, made.exit_status, describe(made).c_str());
  const ProcessResult plain = run_offline(dir.file("in.lcmlog"), dir.file("plain.lcmlog"), {"--r", "ana"});
  const ProcessResult finish = run_offline(dir.file("in.lcmlog"), dir.file("finish.lcmlog"),
                                           {"--r", "ana", "--work-budget", "23000", "--work-overflow", "finish"});
  const ProcessResult shed = run_offline(dir.file("in.lcmlog"), dir.file("shed.lcmlog"),
                                         {"--r", "ana", "--work-budget", "23000"});
  for (const ProcessResult* r : {&plain, &finish, &shed}) CHECK_EQUAL_TEXT(0, r->exit_status, describe(*r).c_str());
  const OutputLog a = rockwatch::test::read_output_log(dir.file("plain.lcmlog"));
  const OutputLog b = rockwatch::test::read_output_log(dir.file("finish.lcmlog"));
  using Status = rockwatch::monitor_status_t;
  const auto flagged = [](const OutputLog& log, std::int32_t bit) {
    long n = 0;
    for (const auto& s : log.states) n += (s.message.data_quality & bit) != 0 ? 1 : 0;
    return n;
  };
  LONGS_EQUAL(a.states.size(), b.states.size());
  for (std::size_t i = 0; i < a.states.size(); ++i) {
    CHECK_TRUE(a.states[i].message.input_seq == b.states[i].message.input_seq);
    CHECK_TRUE(a.states[i].message.x_m == b.states[i].message.x_m);
    CHECK_TRUE(a.states[i].message.xd_mps == b.states[i].message.xd_mps);
  }
  // Every sample finished beyond its budget or shed says so in its own data_quality, as the summary counts.
  const json fc = rockwatch::test::json_lines(finish.out).back().at("summary").at("counters");
  CHECK_TRUE(fc.at("samples_over_budget").get<long>() > 0);
  LONGS_EQUAL(fc.at("samples_over_budget").get<long>(), flagged(b, Status::QUALITY_OVER_BUDGET));
  LONGS_EQUAL(0, fc.at("samples_work_shed").get<long>());
  CHECK_TRUE(fc.at("max_late_calls").get<long>() <= 64);
  const json sc = rockwatch::test::json_lines(shed.out).back().at("summary").at("counters");
  CHECK_TRUE(sc.at("samples_work_shed").get<long>() > 0);
  const OutputLog c = rockwatch::test::read_output_log(dir.file("shed.lcmlog"));
  LONGS_EQUAL(sc.at("samples_work_shed").get<long>(), flagged(c, Status::QUALITY_WORK_SHED));
  LONGS_EQUAL(0, flagged(a, Status::QUALITY_WORK_SHED | Status::QUALITY_OVER_BUDGET));
  const json pc = rockwatch::test::json_lines(plain.out).back().at("summary").at("counters");
  LONGS_EQUAL(0, pc.at("samples_over_budget").get<long>());
  LONGS_EQUAL(0, pc.at("samples_late").get<long>());
}

TEST(MonitorGoldenReplay, ShippedLogIsWhatTheGeneratorMakes) {
  const TempDir dir;
  std::vector<std::string> args{dir.file("made.lcmlog"), "8"};
  args.insert(args.end(), kSimulateArgs.begin(), kSimulateArgs.end());
  const ProcessResult r = rockwatch::test::run_program(ROCKWATCH_MAKE_MONITOR_LOG_PATH, args);
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  const std::string made = rockwatch::test::read_file(dir.file("made.lcmlog"));
  const std::string shipped = rockwatch::test::read_file(monitor_data_path(rockwatch::test::kShippedLog));
  CHECK(!shipped.empty());
  CHECK_TEXT(made == shipped, "tests/data/monitor's input log differs from make_monitor_log's output (README.md)");
}

TEST_GROUP(MonitorOfflineAdapter){};

namespace {

std::vector<std::uint8_t> encode_sample(std::int64_t seq, double ug) {
  rockwatch::ground_accel_t m;
  m.utime = kLogStartUtime + (seq - 1) * 5000;
  m.seq = seq;
  m.schema_version = 1;
  m.ug_mps2 = ug;
  m.vg_mps2 = 0.0;
  m.sensor_status = 0;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

void write_event(lcm::LogFile& log, std::int64_t utime, const std::string& channel, std::vector<std::uint8_t> bytes) {
  lcm::LogEvent e{};
  e.timestamp = utime;
  e.channel = channel;
  e.datalen = static_cast<std::int32_t>(bytes.size());
  e.data = bytes.data();
  CHECK(log.writeEvent(&e) == 0);
}

}  // namespace

TEST(MonitorOfflineAdapter, OnlyTheInputChannelsAreFedAndFaultsAreCounted) {
  const TempDir dir;
  const std::string in = dir.file("odd.lcmlog");
  {
    lcm::LogFile log(in, "w");
    CHECK(log.good());
    for (std::int64_t seq = 1; seq <= 300; ++seq) {
      if (seq == 100 || seq == 101) continue;  // a gap of two samples: bridged
      const std::int64_t t = kLogStartUtime + (seq - 1) * 5000 + 1000;
      write_event(log, t, "ROCKWATCH_ACCEL", encode_sample(seq, 0.0));
      if (seq == 50) write_event(log, t, "ROCKWATCH_ACCEL", encode_sample(seq, 0.0));  // a duplicate
      if (seq == 60) write_event(log, t, "SOMETHING_ELSE", encode_sample(seq, 0.0));   // not an input channel
      if (seq == 70) write_event(log, t, "ROCKWATCH_ACCEL", {1, 2, 3});                // does not decode
    }
  }
  const ProcessResult r = run_offline(in, dir.file("out.lcmlog"));
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  const std::vector<json> lines = rockwatch::test::json_lines(r.out);
  const json& s = lines.back().at("summary");
  LONGS_EQUAL(301, s.at("log_events").get<long>());
  LONGS_EQUAL(300, s.at("log_events_fed").get<long>());
  LONGS_EQUAL(1, s.at("log_events_skipped").get<long>());
  const json& c = s.at("counters");
  LONGS_EQUAL(1, c.at("duplicates").get<long>());
  LONGS_EQUAL(1, c.at("gaps").get<long>());
  LONGS_EQUAL(2, c.at("samples_bridged").get<long>());
  LONGS_EQUAL(1, c.at("decode_errors").get<long>());
  LONGS_EQUAL(0, c.at("messages_ignored").get<long>());
  LONGS_EQUAL(299, c.at("samples_received").get<long>());  // the duplicate was received (then dropped)
  STRCMP_EQUAL("QUIET", s.at("alarm_level").get<std::string>().c_str());
  const OutputLog log = rockwatch::test::read_output_log(dir.file("out.lcmlog"));
  LONGS_EQUAL(300, log.states.size());  // 298 received + 2 bridged
  CHECK(log.other_channels.empty());
}

TEST(MonitorOfflineAdapter, ATruncatedLogIsProcessedUpToTheCutWithAWarning) {
  const TempDir dir;
  const std::string full = rockwatch::test::read_file(monitor_data_path(rockwatch::test::kShippedLog));
  const std::string cut = full.substr(0, full.size() / 2 + 37);  // mid-event
  rockwatch::test::write_file(dir.file("cut.lcmlog"), cut);
  const ProcessResult r = run_offline(dir.file("cut.lcmlog"), dir.file("out.lcmlog"));
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  CHECK_TEXT(r.err.find("warning: --offline-in") != std::string::npos, r.err.c_str());
  CHECK_TEXT(r.err.find("truncated event") != std::string::npos, r.err.c_str());
  const json s = rockwatch::test::json_lines(r.out).back().at("summary");
  CHECK(!s.at("input_log_complete").get<bool>());
  CHECK(s.at("log_events").get<long>() > 700 && s.at("log_events").get<long>() < 900);
}

TEST(MonitorOfflineAdapter, AnEmptyLogGivesAnEmptyOutput) {
  const TempDir dir;
  rockwatch::test::write_file(dir.file("empty.lcmlog"), "");
  const ProcessResult r = run_offline(dir.file("empty.lcmlog"), dir.file("out.lcmlog"));
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  const json s = rockwatch::test::json_lines(r.out).back().at("summary");
  LONGS_EQUAL(0, s.at("log_events").get<long>());
  LONGS_EQUAL(0, s.at("output_events").get<long>());
  LONGS_EQUAL(0, rockwatch::test::read_output_log(dir.file("out.lcmlog")).events);
}

}  // namespace unity_test_monitor_golden
