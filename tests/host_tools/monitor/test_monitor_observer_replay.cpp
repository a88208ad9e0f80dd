// The instrumented wall end to end through files and real processes: `rockwatch simulate --sensors-out` makes the
// sensors of a true wall (r_ana) that the nominal one (r_exp) misjudges; `rockwatch replay --log --wall-sensors`
// writes the ground and wall-sensor messages as a monitor would receive them; `rockwatch-monitor --observer` runs
// the log offline; and `rockwatch simulate --arith fixed --alarms --wall-sensors` runs the same observer offline.
// The two must agree bit for bit: the same alarm transitions at the same samples with the same state, the same r̂
// and offset estimate. Then the plant route of a hardware-in-the-loop rig: `rockwatch replay --wall-file` simulates a
// wall 10 % thinner than the drawings and sends its sensors; the monitor, told only the nominal wall, learns the
// plant's capacity and r and reaches the plant's verdict.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "monitor_output.hpp"
#include "monitor_test_support.hpp"
#include "rockwatch/wall_estimate_t.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_monitor_observer_replay {

using nlohmann::json;
using rockwatch::test::OutputLog;
using rockwatch::test::ProcessResult;
using rockwatch::test::TempDir;

namespace {

// Set 3 X of the shipped suite at 0.25 g: the paper's wall with r_exp survives it open loop (max |x| 0.52 x_inst);
// with r_ana it collapses at t = 15.52 s.
std::vector<std::string> record_args() {
  return {"--suite", std::string(ROCKWATCH_SOURCE_DIR) + "/sim/suites/npr9998-2015", "--set", "3", "--component", "X",
          "--scale-pga", "0.25"};
}

std::string describe(const ProcessResult& r) {
  return "exit " + std::to_string(r.exit_status) + "\nstdout:\n" + r.out.substr(0, 3000) + "\nstderr:\n" +
         r.err.substr(0, 3000);
}

ProcessResult rockwatch_with(std::vector<std::string> head, const std::vector<std::string>& tail) {
  const std::vector<std::string> rec = record_args();
  head.insert(head.begin() + 1, rec.begin(), rec.end());
  head.insert(head.end(), tail.begin(), tail.end());
  return rockwatch::test::run_rockwatch(head);
}

// The x_inst estimates of the wall_estimate_t messages of a monitor's output log, in order.
std::vector<double> published_x_inst(const std::string& path) {
  lcm::LogFile log(path, "r");
  CHECK(log.good());
  std::vector<double> out;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel != "ROCKWATCH_WALL_ESTIMATE") continue;
    rockwatch::wall_estimate_t m;
    CHECK(m.decode(e->data, 0, e->datalen) == e->datalen);
    out.push_back(m.x_inst_estimate_m);
  }
  return out;
}

}  // namespace

TEST_GROUP(MonitorObserverReplay){};

TEST(MonitorObserverReplay, MonitorEqualsSimulateWallSensorsBitForBit) {
  const TempDir dir;
  const std::string sensors = dir.file("true_wall.csv"), in_log = dir.file("in.lcmlog"), out_log = dir.file("out.lcmlog");
  const ProcessResult truth = rockwatch_with(
      {"simulate"}, {"--r", "ana", "--sensors-out", sensors, "--sensor-bias-m", "0.002", "--sensor-seed", "7"});
  CHECK_EQUAL_TEXT(0, truth.exit_status, describe(truth).c_str());

  const ProcessResult fused = rockwatch_with({"simulate"}, {"--arith", "fixed", "--alarms", "--wall-sensors", sensors, "--json"});
  CHECK_EQUAL_TEXT(0, fused.exit_status, describe(fused).c_str());
  const json sim = json::parse(fused.out);
  CHECK(sim.at("collapsed").get<bool>());  // the fused nominal wall follows the true one to collapse

  const ProcessResult replay = rockwatch_with({"replay"}, {"--log", in_log, "--wall-sensors", sensors, "--json"});
  CHECK_EQUAL_TEXT(0, replay.exit_status, describe(replay).c_str());
  const json rj = json::parse(replay.out);
  LONGS_EQUAL(sim.at("observer").at("samples").get<long>(), rj.at("wall_sensors").at("samples_sent").get<long>());

  const ProcessResult mon =
      rockwatch::test::run_monitor({"--offline-in", in_log, "--offline-out", out_log, "--observer", "--r", "exp"});
  CHECK_EQUAL_TEXT(0, mon.exit_status, describe(mon).c_str());
  const json summary = rockwatch::test::json_lines(mon.out).back().at("summary");
  const json& obs = summary.at("observer");
  // The same estimates, bit for bit (the monitor's engine and `simulate --arith fixed` run the same fixed-point code
  // on the same samples in the same order).
  DOUBLES_EQUAL(sim.at("observer").at("r_estimate").get<double>(), obs.at("r_estimate").get<double>(), 0.0);
  DOUBLES_EQUAL(sim.at("observer").at("bias_estimate_m").get<double>(), obs.at("bias_estimate_m").get<double>(), 0.0);
  LONGS_EQUAL(sim.at("observer").at("n_updates").get<long>(), obs.at("counters").at("x_updates").get<long>());

  const OutputLog log = rockwatch::test::read_output_log(out_log);
  const json& expected = sim.at("alarm").at("transitions");
  LONGS_EQUAL(expected.size(), log.alarms.size());
  const std::int64_t start = log.states.empty() ? 0 : log.states.front().message.utime;
  for (std::size_t i = 0; i < expected.size() && i < log.alarms.size(); ++i) {
    const json& e = expected[i];
    const rockwatch::alarm_event_t& m = log.alarms[i].message;
    const std::string what = e.dump() + "\nvs\n" + rockwatch::monitor::alarm_json(m).dump();
    const auto sample = static_cast<std::int64_t>(std::ceil(e.at("t_s").get<double>() / 0.005 - 1e-6));
    LONGS_EQUAL_TEXT(start + sample * 5000, m.utime, what.c_str());
    STRCMP_EQUAL_TEXT(e.at("level").get<std::string>().c_str(), rockwatch::monitor::level_name(m.level).c_str(),
                      what.c_str());
    // The monitor adds which state the alarm saw (measured, predicted, sensor fault); the rest is the alarm's own.
    LONGS_EQUAL_TEXT(e.at("reason_bits").get<long>(), m.reasons & 0xff, what.c_str());
    CHECK_TEXT((m.reasons & rockwatch::alarm_event_t::REASON_MEASURED) != 0, what.c_str());
    DOUBLES_EQUAL_TEXT(e.at("x_m").get<double>(), m.x_m, 0.0, what.c_str());
    DOUBLES_EQUAL_TEXT(e.at("xd_mps").get<double>(), m.xd_mps, 0.0, what.c_str());
  }
  // And the open loop (no sensors) says otherwise: the point of the observer.
  const ProcessResult open = rockwatch_with({"simulate"}, {"--arith", "fixed", "--alarms", "--json"});
  CHECK_EQUAL_TEXT(0, open.exit_status, describe(open).c_str());
  CHECK(!json::parse(open.out).at("collapsed").get<bool>());
}

// The capacity from the decline of the restoring force (SPEC §11), opt-in: the configuration's
// observer.capacity_min_x and observer.doubt_capacity_min_x are `simulate --observer-capacity-min-x
// --observer-doubt-capacity-min-x` in the monitor's fixed-point observer, bit for bit (its published x_inst estimate
// and the summary's), and on this instrumented wall they change the estimate (a monitor that dropped them fails).
TEST(MonitorObserverReplay, TheCapacityMinimumsGiveSimulatesEstimate) {
  const TempDir dir;
  const std::string sensors = dir.file("true_wall.csv"), in_log = dir.file("in.lcmlog");
  const ProcessResult truth = rockwatch_with(
      {"simulate"}, {"--r", "ana", "--sensors-out", sensors, "--sensor-bias-m", "0.002", "--sensor-seed", "7"});
  CHECK_EQUAL_TEXT(0, truth.exit_status, describe(truth).c_str());
  const ProcessResult replay = rockwatch_with({"replay"}, {"--log", in_log, "--wall-sensors", sensors, "--json"});
  CHECK_EQUAL_TEXT(0, replay.exit_status, describe(replay).c_str());
  const std::string config = dir.file("monitor.json");
  rockwatch::test::write_file(config, R"({"observer": {"capacity_min_x": 0.1, "doubt_capacity_min_x": 0.2}})");

  const std::vector<std::string> fused{"--arith", "fixed", "--alarms", "--wall-sensors", sensors, "--json"};
  std::vector<std::string> with = fused;
  with.insert(with.end(), {"--observer-capacity-min-x", "0.1", "--observer-doubt-capacity-min-x", "0.2"});
  const ProcessResult sim_off = rockwatch_with({"simulate"}, fused), sim_on = rockwatch_with({"simulate"}, with);
  CHECK_EQUAL_TEXT(0, sim_off.exit_status, describe(sim_off).c_str());
  CHECK_EQUAL_TEXT(0, sim_on.exit_status, describe(sim_on).c_str());
  const json so = json::parse(sim_off.out).at("observer"), sn = json::parse(sim_on.out).at("observer");

  const std::string off_log = dir.file("off.lcmlog"), on_log = dir.file("on.lcmlog");
  const ProcessResult off =
      rockwatch::test::run_monitor({"--offline-in", in_log, "--offline-out", off_log, "--observer", "--r", "exp"});
  const ProcessResult on = rockwatch::test::run_monitor(
      {"--offline-in", in_log, "--offline-out", on_log, "--observer", "--r", "exp", "--config", config});
  CHECK_EQUAL_TEXT(0, off.exit_status, describe(off).c_str());
  CHECK_EQUAL_TEXT(0, on.exit_status, describe(on).c_str());
  const json mo = rockwatch::test::json_lines(off.out).back().at("summary").at("observer");
  const json mn = rockwatch::test::json_lines(on.out).back().at("summary").at("observer");
  const std::string what = "simulate " + sn.dump() + "\nmonitor " + mn.dump();
  // Simulate's estimates, bit for bit, with and without.
  for (const char* key : {"x_inst_estimate_m", "sigma_x_inst_m", "r_estimate"}) {
    const std::string key_what = key + std::string(" ") + what;
    DOUBLES_EQUAL_TEXT(sn.at(key).get<double>(), mn.at(key).get<double>(), 0.0, key_what.c_str());
    DOUBLES_EQUAL_TEXT(so.at(key).get<double>(), mo.at(key).get<double>(), 0.0, key);
  }
  // The summary names the settings only when on.
  CHECK_TEXT(mn.at("settings").contains("capacity_min_x") && mn.at("settings").contains("doubt_capacity_min_x"),
             what.c_str());
  DOUBLES_EQUAL_TEXT(0.1, mn.at("settings").at("capacity_min_x").get<double>(), 0.0, what.c_str());
  DOUBLES_EQUAL_TEXT(0.2, mn.at("settings").at("doubt_capacity_min_x").get<double>(), 0.0, what.c_str());
  CHECK_FALSE(mo.at("settings").contains("capacity_min_x"));
  // What the monitor published: the last wall_estimate_t is the summary's estimate; the setting changes it.
  const std::vector<double> published_off = published_x_inst(off_log), published_on = published_x_inst(on_log);
  CHECK(!published_on.empty() && published_on.size() == published_off.size());
  DOUBLES_EQUAL_TEXT(mn.at("x_inst_estimate_m").get<double>(), published_on.back(), 0.0, what.c_str());
  DOUBLES_EQUAL(mo.at("x_inst_estimate_m").get<double>(), published_off.back(), 0.0);
  CHECK_TEXT(published_on.back() != published_off.back(), what.c_str());
  CHECK_TEXT(sn.at("x_inst_estimate_m").get<double>() != so.at("x_inst_estimate_m").get<double>(), what.c_str());
}

// A wall file as `rockwatch identify --wall-out` writes it (the reduced block is optional): the paper wall 10 %
// thinner, r 0.85. Its x_inst (SPEC §9: c/k) is 0.0902 m against the nominal 0.1003 m.
TEST(MonitorObserverReplay, MonitorLearnsThePlantOfReplayWallFile) {
  const TempDir dir;
  const std::string wall = dir.file("thin_wall.json"), in_log = dir.file("in.lcmlog"), out_log = dir.file("out.lcmlog");
  {
    std::ofstream f(wall);
    f << "{\"format\": \"rockwatch-wall\", \"version\": 1, \"b_m\": 0.09, \"h1_m\": 1.75, \"h2_m\": 1.75, "
         "\"rho_kgpm3\": 1800, \"fp_npm\": 0, \"a\": 0, \"a_prime\": 0, \"g_mps2\": 9.81, \"r\": 0.85}\n";
  }
  const ProcessResult replay =
      rockwatch_with({"replay"}, {"--log", in_log, "--wall-file", wall, "--sensor-seed", "3", "--json"});
  CHECK_EQUAL_TEXT(0, replay.exit_status, describe(replay).c_str());
  const json plant = json::parse(replay.out).at("plant");
  const double x_inst_true = plant.at("x_inst_m").get<double>();
  DOUBLES_EQUAL(0.0902, x_inst_true, 0.0005);
  // The plant rocks for the whole record (about a hundred impacts): enough for the observer to learn from.
  CHECK_TEXT(plant.at("n_impacts").get<long>() >= 20, plant.dump().c_str());

  const ProcessResult mon =
      rockwatch::test::run_monitor({"--offline-in", in_log, "--offline-out", out_log, "--observer", "--r", "exp"});
  CHECK_EQUAL_TEXT(0, mon.exit_status, describe(mon).c_str());
  const json summary = rockwatch::test::json_lines(mon.out).back().at("summary");
  const json& obs = summary.at("observer");
  const std::string what = plant.dump() + "\nvs\n" + summary.dump();
  LONGS_EQUAL_TEXT(plant.at("sensor_samples_sent").get<long>(), obs.at("sensor_samples_received").get<long>(),
                   what.c_str());
  // The capacity and r of the wall file, not the nominal wall's (0.1003 m, r_exp 0.894), within 3 sigma and 2 %.
  const double x_inst = obs.at("x_inst_estimate_m").get<double>(), sx = obs.at("sigma_x_inst_m").get<double>();
  CHECK_TEXT(std::fabs(x_inst - x_inst_true) <= 3.0 * sx, what.c_str());
  CHECK_TEXT(std::fabs(x_inst - x_inst_true) <= 0.02 * x_inst_true, what.c_str());
  const double r = obs.at("r_estimate").get<double>(), sr = obs.at("sigma_r").get<double>();
  CHECK_TEXT(std::fabs(r - 0.85) <= 3.0 * sr && sr < 0.02, what.c_str());
  // The monitor's verdict is the plant's.
  const bool monitor_collapsed = summary.at("max_alarm_level").get<std::string>() == "COLLAPSED";
  CHECK_EQUAL_TEXT(plant.at("collapsed").get<bool>(), monitor_collapsed, what.c_str());
}

}  // namespace unity_test_monitor_observer_replay
