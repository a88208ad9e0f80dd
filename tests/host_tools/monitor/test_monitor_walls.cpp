// rockwatch-monitor with a `walls` configuration, end to end over LCM (udpm multicast on loopback, ttl=0): three
// walls share one ground channel, `rockwatch replay` sends a pulse on it, and each wall publishes on its own channels
// (the wall named "wall" on the unsuffixed ones, the others suffixed _NAME) the alarm transitions `rockwatch simulate
// --arith fixed --alarms` gives for that wall's parameters, with its statuses; stdout names the wall in each
// transition and the summary lists the walls. Configuration mistakes in `walls` are refused naming walls[i] and the
// key (exit 2).
#include <signal.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "monitor_live_support.hpp"
#include "monitor_output.hpp"
#include "monitor_test_support.hpp"
#include "rockwatch/alarm_event_t.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "rockwatch/monitor_status_t.hpp"
#include "rockwatch/process/child_process.hpp"
#include "rockwatch/wall_state_t.hpp"

#include <CppUTest/TestHarness.h>

using nlohmann::json;
using rockwatch::test::now_s;
using rockwatch::test::TempDir;

namespace {

struct WallsInbox {
  std::map<std::string, std::vector<rockwatch::alarm_event_t>> alarms;      // by channel
  std::map<std::string, std::vector<rockwatch::monitor_status_t>> statuses;  // by channel
  std::map<std::string, long> states;                                        // by channel

  static void on_alarm(const lcm::ReceiveBuffer* rbuf, const std::string& channel, WallsInbox* self) {
    rockwatch::alarm_event_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0) self->alarms[channel].push_back(m);
  }
  static void on_status(const lcm::ReceiveBuffer* rbuf, const std::string& channel, WallsInbox* self) {
    rockwatch::monitor_status_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0) self->statuses[channel].push_back(m);
  }
  static void on_state(const lcm::ReceiveBuffer*, const std::string& channel, WallsInbox* self) {
    ++self->states[channel];
  }
};

struct Wall {
  std::string name;
  json fields;                          // the config's "wall" object
  std::vector<std::string> simulate;    // the same wall for `rockwatch simulate`
};

// The paper wall (named "wall": the unsuffixed channels), a thicker one, a taller one.
const std::vector<Wall> kWalls{{"wall", json::object(), {}},
                               {"north", json{{"b", 0.14}}, {"--b", "0.14"}},
                               {"south", json{{"h1", 2.0}, {"h2", 2.0}}, {"--h1", "2", "--h2", "2"}}};

std::string suffixed(const std::string& channel, const Wall& w) {
  return w.name == "wall" ? channel : channel + "_" + w.name;
}

std::string write_walls_config(const TempDir& dir, const rockwatch::test::LiveChannels& c) {
  json walls = json::array();
  for (const Wall& w : kWalls) {
    json entry{{"name", w.name}};
    if (!w.fields.empty()) entry["wall"] = w.fields;
    walls.push_back(entry);
  }
  const json j{{"channels",
                {{"accel", c.accel}, {"accel_batch", c.batch}, {"wall_state", c.state}, {"alarm", c.alarm},
                 {"status", c.status}}},
               {"walls", walls}};
  const std::string path = dir.file("walls.json");
  rockwatch::test::write_file(path, j.dump());
  return path;
}

// 0.5 s of -3 m/s2 after 0.2 s of rest, then 1.3 s of rest (400 samples at 200 Hz): the paper wall collapses.
std::string write_pulse(const TempDir& dir) {
  std::string column;
  for (int i = 0; i < 400; ++i) column += (i >= 40 && i < 140 ? "-3\n" : "0\n");
  const std::string path = dir.file("pulse.txt");
  rockwatch::test::write_file(path, column);
  return path;
}

// `rockwatch simulate --arith fixed --alarms` of the pulse for the wall: its transitions' levels in order and the
// sample of each.
std::vector<std::pair<std::string, long>> simulated(const std::string& pulse, const Wall& w) {
  std::vector<std::string> args{"simulate", "--record", pulse, "--units", "mps2", "--dt", "0.005", "--arith", "fixed",
                                "--alarms", "--json"};
  args.insert(args.end(), w.simulate.begin(), w.simulate.end());
  const rockwatch::test::ProcessResult sim = rockwatch::test::run_rockwatch(args);
  CHECK_EQUAL_TEXT(0, sim.exit_status, sim.err.c_str());
  std::vector<std::pair<std::string, long>> out;
  const json result = json::parse(sim.out);  // kept: the loop below refers into it
  for (const json& t : result.at("alarm").at("transitions")) {
    out.emplace_back(t.at("level").get<std::string>(),
                     static_cast<long>(std::ceil(t.at("t_s").get<double>() / 0.005 - 1e-6)));
  }
  return out;
}

}  // namespace

TEST_GROUP(MonitorWalls){};

TEST(MonitorWalls, ThreeWallsOnOneGroundSensorEachAlarmAsSimulateSays) {
  const std::string url = rockwatch::test::live_test_url(1);
  if (rockwatch::test::skip_without_multicast(url)) return;
  const TempDir dir;
  const rockwatch::test::LiveChannels c("RWW");
  lcm::LCM lcm(url);
  CHECK(lcm.good());
  WallsInbox inbox;
  for (const Wall& w : kWalls) {
    lcm.subscribeFunction(suffixed(c.alarm, w), &WallsInbox::on_alarm, &inbox);
    lcm.subscribeFunction(suffixed(c.status, w), &WallsInbox::on_status, &inbox);
    lcm.subscribeFunction(suffixed(c.state, w), &WallsInbox::on_state, &inbox);
  }
  const pid_t pid = rockwatch::test::start_monitor_listening(
      {"--config", write_walls_config(dir, c), "--lcm-url", url}, dir.file("stdout"), dir.file("stderr"));
  // The walls' line follows "listening on" in a write of its own: a loaded machine may show the first alone.
  const double announced_by = now_s() + 10.0;
  while (rockwatch::test::read_file(dir.file("stderr")).find("3 walls: wall (") == std::string::npos &&
         now_s() < announced_by) {
    rockwatch::test::sleep_s(0.01);
  }
  STRCMP_CONTAINS("3 walls: wall (", rockwatch::test::read_file(dir.file("stderr")).c_str());

  // `rockwatch replay` drives it: the pulse on the shared ground channel, in real time.
  const std::string pulse = write_pulse(dir);
  // Spawned, so that this process drains LCM meanwhile (1 200 wall states would overflow its socket buffer).
  const pid_t replay = rockwatch::test::spawn_rockwatch(
      {"replay", "--record", pulse, "--units", "mps2", "--dt", "0.005", "--lcm-url", url, "--lcm-channel", c.accel},
      dir.file("replay.out"), dir.file("replay.err"));
  std::optional<int> replay_status;
  while (!(replay_status = rockwatch::process::poll_status(replay))) lcm.handleTimeout(10);
  CHECK_TEXT(WIFEXITED(*replay_status) && WEXITSTATUS(*replay_status) == 0,
             rockwatch::test::read_file(dir.file("replay.err")).c_str());
  // Each wall's status counting every sample comes after every alarm event those samples caused.
  const double deadline = now_s() + 5.0;
  const auto all_counted = [&] {
    for (const Wall& w : kWalls) {
      const auto& s = inbox.statuses[suffixed(c.status, w)];
      if (s.empty() || s.back().samples_received < 400) return false;
    }
    return true;
  };
  while (!all_counted() && now_s() < deadline) lcm.handleTimeout(50);
  CHECK_TEXT(all_counted(), rockwatch::test::read_file(dir.file("stderr")).c_str());
  kill(pid, SIGTERM);
  const int status = rockwatch::test::wait_status(pid);
  const std::string err = rockwatch::test::read_file(dir.file("stderr"));
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, err.c_str());
  const std::vector<json> lines = rockwatch::test::json_lines(rockwatch::test::read_file(dir.file("stdout")));
  CHECK_TEXT(!lines.empty() && lines.back().contains("summary"), err.c_str());
  const json& summary = lines.back().at("summary");
  LONGS_EQUAL(3, summary.at("walls").size());
  STRCMP_EQUAL("COLLAPSED", summary.at("max_alarm_level").get<std::string>().c_str());

  std::set<std::vector<std::int64_t>> timelines;  // each wall's transition times: the walls differ
  for (std::size_t k = 0; k < kWalls.size(); ++k) {
    const Wall& w = kWalls[k];
    const json& ws = summary.at("walls")[k];
    STRCMP_EQUAL(w.name.c_str(), ws.at("name").get<std::string>().c_str());
    STRCMP_EQUAL(suffixed(c.alarm, w).c_str(), ws.at("alarm_channel").get<std::string>().c_str());
    const json& counters = ws.at("counters");
    LONGS_EQUAL_TEXT(400, counters.at("samples_received").get<long>(), ws.dump().c_str());
    LONGS_EQUAL_TEXT(400, inbox.states[suffixed(c.state, w)], w.name.c_str());
    // stdout: this wall's transitions, named, the same as on its LCM channel.
    std::vector<json> printed;
    for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
      if (lines[i].at("wall").get<std::string>() == w.name) printed.push_back(lines[i]);
    }
    const std::vector<rockwatch::alarm_event_t>& received = inbox.alarms[suffixed(c.alarm, w)];
    LONGS_EQUAL_TEXT(printed.size(), received.size(), w.name.c_str());
    for (std::size_t i = 0; i < printed.size() && i < received.size(); ++i) {
      json expected = rockwatch::monitor::alarm_json(received[i]);
      expected["wall"] = w.name;
      CHECK_TEXT(printed[i] == expected, printed[i].dump().c_str());
    }
    std::vector<std::int64_t> times;
    for (const rockwatch::alarm_event_t& e : received) times.push_back(e.utime);
    timelines.insert(times);
    // Against `rockwatch simulate` with this wall (when loopback delivered every sample in order).
    if (counters.at("gaps").get<long>() != 0 || counters.at("out_of_order").get<long>() != 0) {
      UT_PRINT(("samples lost on loopback; simulate comparison skipped: " + counters.dump()).c_str());
      continue;
    }
    const std::vector<std::pair<std::string, long>> expected = simulated(pulse, w);
    LONGS_EQUAL_TEXT(expected.size(), received.size(), w.name.c_str());
    for (std::size_t i = 0; i < expected.size() && i < received.size(); ++i) {
      STRCMP_EQUAL_TEXT(expected[i].first.c_str(), rockwatch::monitor::level_name(received[i].level).c_str(),
                        w.name.c_str());
      LONGS_EQUAL_TEXT(expected[i].second - expected[0].second, (received[i].utime - received[0].utime) / 5000,
                       w.name.c_str());
    }
  }
  LONGS_EQUAL_TEXT(3, timelines.size(), "each wall should have its own alarm timeline");
}

TEST(MonitorWalls, WallMistakesAreRefusedNamingTheWall) {
  const TempDir dir;
  struct Case {
    std::string walls;
    std::string mentions;
  };
  const std::size_t max = rockwatch::firmware::kMaxMonitorWalls;  // 64 on hosts
  std::string too_many = "[";
  for (std::size_t i = 0; i <= max; ++i) too_many += std::string(i ? "," : "") + "{\"name\":\"w" + std::to_string(i) + "\"}";
  too_many += "]";
  const std::vector<Case> cases{
      {"[]", "walls: expected an array of 1 to " + std::to_string(max)},
      {too_many, std::to_string(max + 1) + " walls: one monitor follows at most " + std::to_string(max)},
      {"[{\"wall\":{}}]", "walls[0].name: expected a name"},
      {"[{\"name\":\"a b\"}]", "walls[0].name: expected a name"},
      {"[{\"name\":\"a\"},{\"name\":\"a\"}]", "walls[1].name: \"a\" is the name of an earlier wall"},
      {"[{\"name\":\"a\",\"colour\":1}]", "walls[0]: unknown key 'colour'"},
      {"[{\"name\":\"a\",\"wall\":{\"b\":\"x\"}}]", "walls[0].wall.b: expected a finite number"},
      {"[{\"name\":\"a\",\"wall\":{\"h1\":0.05}}]", "walls[0].wall.h1"},
      {"[{\"name\":\"a\",\"r\":2}]", "walls[0].r: expected"},
      {"[{\"name\":\"a\",\"channels\":{\"wall_state\":\"X\"}}]", "walls[0].channels: unknown key 'wall_state'"},
      {"[{\"name\":\"a\"},{\"name\":\"b\",\"channels\":{\"accel\":\"ROCKWATCH_STATUS_a\"}}]",
       "walls[1] (b): a wall reads a channel another wall publishes on"},
  };
  for (const Case& k : cases) {
    const std::string path = dir.file("bad.json");
    rockwatch::test::write_file(path, "{\"walls\": " + k.walls + "}");
    const std::string out = dir.file("out"), errf = dir.file("err");
    const pid_t pid = rockwatch::test::spawn_monitor({"--config", path, "--offline-in", path, "--offline-out",
                                                      dir.file("o.log")},
                                                     out, errf);
    const int status = rockwatch::test::wait_status(pid);
    const std::string err = rockwatch::test::read_file(errf);
    CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 2, (k.walls + "\n" + err).c_str());
    CHECK_TEXT(err.find(k.mentions) != std::string::npos, (k.mentions + " in\n" + err).c_str());
  }
}
