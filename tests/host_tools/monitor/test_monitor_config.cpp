// rockwatch-monitor's settings: every bad key or value of the configuration file rejected (exit 2, nothing on stdout,
// a message naming the key path and what was expected), unknown keys, the command line overriding the file (read back
// with --print-config), the wall/--r/--model/--kappa options shared with `rockwatch simulate`, --arith fixed|double,
// the config digest; and the adapter's helpers (exact-channel regex, FNV-1a).
#include <sys/stat.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lcm_transport.hpp"
#include "monitor_config.hpp"
#include "monitor_test_support.hpp"
#include "monitor_expect.hpp"

#include <CppUTest/TestHarness.h>

using nlohmann::json;
using rockwatch::test::describe;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_monitor;
using rockwatch::test::TempDir;

namespace {

void expect_rejected(const std::vector<std::string>& args, const std::vector<std::string>& mentions) {
  rockwatch::test::expect_monitor_rejected(args, mentions);
}

// A configuration file with `text` rejected with a message naming each of `mentions`.
void expect_config_rejected(const std::string& text, const std::vector<std::string>& mentions,
                            const std::vector<std::string>& extra_args = {}) {
  const TempDir dir;
  const std::string path = dir.file("monitor.json");
  rockwatch::test::write_file(path, text);
  std::vector<std::string> args{"--config", path};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  // A file value at fault is named with the file; an option at fault (extra_args) by the option alone.
  std::vector<std::string> all_mentions;
  if (extra_args.empty()) all_mentions.push_back("--config " + path);
  all_mentions.insert(all_mentions.end(), mentions.begin(), mentions.end());
  expect_rejected(args, all_mentions);
}

json printed_config(const std::string& text, const std::vector<std::string>& extra) {
  return rockwatch::test::monitor_printed_config(text, extra);
}

}  // namespace

TEST_GROUP(MonitorConfigFile){};

TEST(MonitorConfigFile, UnknownKeysAreRefusedByTheirPath) {
  expect_config_rejected(R"({"kapa": 2})", {"unknown key 'kapa'", "kappa"});
  expect_config_rejected(R"({"wall": {"hh": 3}})", {"unknown key 'wall.hh'", "b, h1, h2, rho, fp, a, a_prime, g"});
  expect_config_rejected(R"({"alarm": {"lambda": 0.4}})", {"alarm.lambda", "lambda_w, hold_s, energy_margin"});
  expect_config_rejected(R"({"channels": {"acc": "X"}})", {"channels.acc", "accel, accel_batch"});
}

TEST(MonitorConfigFile, WrongTypesNameTheKeyAndTheExpectedType) {
  expect_config_rejected(R"({"wall": {"h1": "1.75"}})", {"wall.h1", "expected a number [m]", "a string"});
  expect_config_rejected(R"({"wall": 3})", {"wall:", "expected an object"});
  expect_config_rejected(R"({"alarm": []})", {"alarm:", "expected an object", "an array"});
  expect_config_rejected(R"({"alarm": {"imminent_horizon_s": "0.17"}})",
                         {"alarm.imminent_horizon_s:", "expected a number [s]", "a string"});
  expect_config_rejected(R"({"kappa": true})", {"kappa:", "expected a number", "a boolean"});
  expect_config_rejected(R"({"sample_rate_hz": null})", {"sample_rate_hz:", "expected a number [Hz]", "null"});
  expect_config_rejected(R"({"r": true})", {"r:", "\"ana\", \"exp\", \"impulse\" or an energy ratio in [0, 1]"});
  expect_config_rejected(R"({"model": 1})", {"model:", "expected \"linear\" or \"full\""});
  expect_config_rejected(R"({"arith": 1})", {"arith:", "expected \"fixed\" or \"double\"", "a number"});
  expect_config_rejected(R"({"channels": {"alarm": 5}})", {"channels.alarm:", "expected a string"});
  expect_config_rejected(R"({"lcm_url": 7667})", {"lcm_url:", "expected a string"});
  expect_config_rejected(R"({"max_bridge_samples": 2.5})", {"max_bridge_samples:", "whole number"});
  expect_config_rejected(R"([1, 2])", {"the top level", "expected a JSON object"});
}

TEST(MonitorConfigFile, ValuesOutOfRangeNameTheKeyAndTheRange) {
  expect_config_rejected(R"({"r": "paper"})", {"r:", "\"ana\", \"exp\", \"impulse\""});
  expect_config_rejected(R"({"r": 1.2})", {"r:", "in [0, 1]", "1.2"});
  expect_config_rejected(R"({"model": "full"})", {"model full needs --arith double", "linear model only"});
  expect_config_rejected(R"({"model": "full", "arith": "fixed"})", {"model full needs --arith double", "arith fixed from"});
  expect_config_rejected(R"({"arith": "float"})", {"arith must be fixed or double", "'float'"});
  expect_config_rejected(R"({"model": "quadratic"})", {"model must be linear or full", "quadratic"});
  expect_config_rejected(R"({"kappa": 0.5})", {"kappa must be >= 1", "0.5"});
  expect_config_rejected(R"({"kappa": 150})", {"kappa must be < 100", "150"});
  expect_config_rejected(R"({"alarm": {"lambda_w": 1.5}})", {"alarm.lambda_w must be in (0, 1]", "1.5"});
  expect_config_rejected(R"({"alarm": {"hold_s": -1}})", {"alarm.hold_s must be in [0, 3600] s", "-1"});
  expect_config_rejected(R"({"alarm": {"energy_margin": 0.5}})", {"alarm.energy_margin must be in [1, 100]"});
  expect_config_rejected(R"({"alarm": {"imminent_horizon_s": 11}})",
                         {"alarm.imminent_horizon_s must be in [0, 10] s", "got 11"});
  expect_config_rejected(R"({"alarm": {"imminent_horizon_s": -0.1}})",
                         {"alarm.imminent_horizon_s must be in [0, 10] s", "got -0.1"});
  expect_config_rejected(R"({"sample_rate_hz": 10})", {"sample_rate_hz must be in (0, 10000] Hz", "33.34", "got 10"});
  expect_config_rejected(R"({"sample_rate_hz": 20000})", {"sample_rate_hz must be", "got 20000"});
  expect_config_rejected(R"({"max_bridge_samples": -1})", {"max_bridge_samples:", "[0, 1000]", "-1"});
  expect_config_rejected(R"({"max_bridge_samples": 5000})", {"max_bridge_samples:", "[0, 1000]", "5000"});
  expect_config_rejected(R"({"sensor_range_mps2": 100})", {"sensor_range_mps2 must be in (0, 80] m/s2", "100"});
  expect_config_rejected(R"({"late_limit_s": 0})", {"late_limit_s must be in (0, 60] s", "got 0"});
  expect_config_rejected(R"({"lcm_url": ""})", {"lcm_url:", "expected an LCM URL"});
}

TEST(MonitorConfigFile, WallValuesAreValidatedByCoreNamingTheKey) {
  expect_config_rejected(R"({"wall": {"b": 0.3, "h1": 0.2}})", {"wall.h1 must be greater than b", "got 0.2", "b = 0.3",
                                                                 "wall.b"});
  expect_config_rejected(R"({"wall": {"rho": 0}})", {"wall.rho must be > 0 kg/m3"});
  expect_config_rejected(R"({"wall": {"a_prime": 2}})", {"wall.a_prime must be in [0, 1]"});
  expect_config_rejected(R"({"wall": {"g": -9.81}})", {"wall.g must be > 0 m/s2"});
  // A wall the model accepts but the fixed-point formats cannot hold: refused at start, naming the wall.
  const TempDir dir;
  const std::string path = dir.file("big.json");
  rockwatch::test::write_file(path, R"({"wall": {"b": 3, "h1": 40, "h2": 40}})");
  expect_rejected({"--config", path, "--print-config"},
                  {"the wall (paper wall with wall.b, wall.h1, wall.h2)", "formats"});
}

TEST(MonitorConfigFile, ChannelsMustBePrintableAndAllDifferent) {
  expect_config_rejected(R"({"channels": {"accel": ""}})", {"channels.accel must be 1 to 63 printable"});
  expect_config_rejected(R"({"channels": {"accel": "A B"}})", {"channels.accel must be", "'A B'"});
  expect_config_rejected("{\"channels\": {\"status\": \"" + std::string(64, 'S') + "\"}}", {"channels.status must be"});
  expect_config_rejected(R"({"channels": {"alarm": "ROCKWATCH_ACCEL"}})",
                         {"channels.alarm is 'ROCKWATCH_ACCEL'", "same as channels.accel", "every channel"});
}

TEST(MonitorConfigFile, MalformedFilesAreRefused) {
  expect_config_rejected("{\"kappa\": 2,\n \"r\": }", {"not valid JSON", "line 2"});
  // A number beyond double: nlohmann throws out_of_range, not parse_error (was an "internal error"; found by fuzzing).
  expect_config_rejected(R"({"kappa": 1e400})", {"not valid JSON", "number overflow parsing '1e400'"});
  expect_config_rejected(R"({"kappa": 2, "kappa": 3})", {"kappa:", "appears twice"});
  expect_config_rejected(R"({"wall": {"b": 0.1, "b": 0.2}})", {"wall.b:", "appears twice"});
  expect_rejected({"--config", "/nonexistent/monitor.json"}, {"--config /nonexistent/monitor.json", "it does not exist"});
  expect_rejected({"--config", ""}, {"--config needs a file name"});
}

TEST(MonitorConfigFile, AFullFileIsReadBackNormalised) {
  const json j = printed_config(R"({
    "wall": {"b": 0.12, "h1": 1.5, "h2": 1.6, "rho": 1900, "fp": 100, "a": 0.1, "a_prime": 0.2, "g": 9.81},
    "r": 0.8, "model": "linear", "kappa": 1.8,
    "alarm": {"lambda_w": 0.5, "hold_s": 2, "energy_margin": 1.25},
    "sample_rate_hz": 250, "max_bridge_samples": 4, "sensor_range_mps2": 40, "late_limit_s": 0.2,
    "channels": {"accel": "A", "accel_batch": "AB", "wall_state": "W", "alarm": "AL", "status": "S"},
    "lcm_url": "udpm://239.255.76.67:7670?ttl=0"})",
                                  {});
  const json& s = j.at("settings");
  DOUBLES_EQUAL(0.12, s.at("wall").at("b").get<double>(), 0.0);
  DOUBLES_EQUAL(1.6, s.at("wall").at("h2").get<double>(), 0.0);
  DOUBLES_EQUAL(100.0, s.at("wall").at("fp").get<double>(), 0.0);
  DOUBLES_EQUAL(0.8, s.at("r").get<double>(), 0.0);
  DOUBLES_EQUAL(0.8, s.at("r_energy_ratio").get<double>(), 0.0);
  DOUBLES_EQUAL(1.8, s.at("kappa").get<double>(), 0.0);
  DOUBLES_EQUAL(0.5, s.at("alarm").at("lambda_w").get<double>(), 0.0);
  DOUBLES_EQUAL(2.0, s.at("alarm").at("hold_s").get<double>(), 0.0);
  DOUBLES_EQUAL(1.25, s.at("alarm").at("energy_margin").get<double>(), 0.0);
  DOUBLES_EQUAL(250.0, s.at("sample_rate_hz").get<double>(), 0.0);
  LONGS_EQUAL(4, s.at("max_bridge_samples").get<int>());
  DOUBLES_EQUAL(40.0, s.at("sensor_range_mps2").get<double>(), 0.0);
  DOUBLES_EQUAL(0.2, s.at("late_limit_s").get<double>(), 0.0);
  STRCMP_EQUAL("AB", s.at("channels").at("accel_batch").get<std::string>().c_str());
  STRCMP_EQUAL("S", s.at("channels").at("status").get<std::string>().c_str());
  STRCMP_EQUAL("udpm://239.255.76.67:7670?ttl=0", j.at("lcm_url").get<std::string>().c_str());
  CHECK(j.at("lcm_url_origin").get<std::string>().find("lcm_url") != std::string::npos);
  const std::string digest = j.at("config_digest").get<std::string>();
  LONGS_EQUAL(18, digest.size());
  // The digest is FNV-1a 64 of the normalised settings' compact dump.
  const std::uint64_t expected = rockwatch::monitor::fnv1a64(s.dump());
  STRCMP_EQUAL(rockwatch::monitor::digest_hex(static_cast<std::int64_t>(expected)).c_str(), digest.c_str());
}

TEST_GROUP(MonitorCommandLine){};

TEST(MonitorCommandLine, OptionsOverrideTheFile) {
  const std::string file = R"({"wall": {"h1": 2.0, "h2": 2.0}, "r": "ana", "kappa": 3, "alarm": {"lambda_w": 0.5},
                               "sample_rate_hz": 100, "lcm_url": "udpm://239.255.76.67:7671?ttl=0"})";
  const json base = printed_config(file, {});
  DOUBLES_EQUAL(2.0, base.at("settings").at("wall").at("h1").get<double>(), 0.0);
  DOUBLES_EQUAL(3.0, base.at("settings").at("kappa").get<double>(), 0.0);
  STRCMP_EQUAL("ana", base.at("settings").at("r").get<std::string>().c_str());

  const json j = printed_config(file, {"--h1", "1.5", "--r", "0.5", "--kappa", "2.5", "--lambda-w", "0.6", "--rate",
                                       "250", "--lcm-url", "udpm://239.255.76.67:7672?ttl=0"});
  const json& s = j.at("settings");
  DOUBLES_EQUAL(1.5, s.at("wall").at("h1").get<double>(), 0.0);  // the option
  DOUBLES_EQUAL(2.0, s.at("wall").at("h2").get<double>(), 0.0);  // the file
  DOUBLES_EQUAL(0.1, s.at("wall").at("b").get<double>(), 0.0);   // the paper wall
  DOUBLES_EQUAL(0.5, s.at("r").get<double>(), 0.0);
  DOUBLES_EQUAL(2.5, s.at("kappa").get<double>(), 0.0);
  DOUBLES_EQUAL(0.6, s.at("alarm").at("lambda_w").get<double>(), 0.0);
  DOUBLES_EQUAL(250.0, s.at("sample_rate_hz").get<double>(), 0.0);
  STRCMP_EQUAL("udpm://239.255.76.67:7672?ttl=0", j.at("lcm_url").get<std::string>().c_str());
  STRCMP_EQUAL("--lcm-url", j.at("lcm_url_origin").get<std::string>().c_str());
  CHECK(j.at("config_digest") != base.at("config_digest"));

  // --wall paper on the command line replaces the file's wall altogether.
  const json paper = printed_config(file, {"--wall", "paper"});
  DOUBLES_EQUAL(1.75, paper.at("settings").at("wall").at("h1").get<double>(), 0.0);
}

TEST(MonitorCommandLine, EquivalentSettingsHaveOneDigest) {
  const json defaults = printed_config("", {});
  const json spelled_out = printed_config(R"({"r": "exp", "kappa": 2, "sample_rate_hz": 200, "wall": {"b": 0.1}})", {});
  const json by_options = printed_config("", {"--kappa", "2.0", "--r", "exp", "--rate", "200"});
  CHECK(defaults.at("config_digest") == spelled_out.at("config_digest"));
  CHECK(defaults.at("config_digest") == by_options.at("config_digest"));
  const json other = printed_config("", {"--kappa", "2.01"});
  CHECK(defaults.at("config_digest") != other.at("config_digest"));
  // The URL is how messages travel, not what the monitor computes: not in the digest.
  const json url = printed_config("", {"--lcm-url", "udpm://239.255.76.67:7673?ttl=0"});
  CHECK(defaults.at("config_digest") == url.at("config_digest"));
}

// The energy rule's displacement (issue 40; `simulate --energy-min-x`; 0.5 by default since 2026-12-01): the file's
// alarm.energy_min_x, the option over it, echoed and in the digest only when on (0, the value before, is absent: a
// configuration written before that says 0 keeps its digest, and the default is named); out of [0, 1] rejected naming
// the file's key or the option.
TEST(MonitorCommandLine, TheEnergyRulesDisplacementIsReadEchoedAndInTheDigestOnlyWhenOn) {
  const json defaults = printed_config("", {});
  DOUBLES_EQUAL(0.5, defaults.at("settings").at("alarm").at("energy_min_x").get<double>(), 0.0);
  const json off = printed_config(R"({"alarm": {"energy_min_x": 0}})", {"--energy-min-x", "0"});
  CHECK_FALSE(off.at("settings").at("alarm").contains("energy_min_x"));
  CHECK(off.at("config_digest") != defaults.at("config_digest"));
  const json file = printed_config(R"({"alarm": {"energy_min_x": 0.5}})", {});
  DOUBLES_EQUAL(0.5, file.at("settings").at("alarm").at("energy_min_x").get<double>(), 0.0);
  CHECK(file.at("config_digest") == defaults.at("config_digest"));
  const json other = printed_config(R"({"alarm": {"energy_min_x": 0.4}})", {});
  CHECK(other.at("config_digest") != defaults.at("config_digest"));
  const json option = printed_config("", {"--energy-min-x", "0.5"});
  CHECK(option.at("config_digest") == file.at("config_digest"));
  const json over = printed_config(R"({"alarm": {"energy_min_x": 0.5}})", {"--energy-min-x", "0.6"});
  DOUBLES_EQUAL(0.6, over.at("settings").at("alarm").at("energy_min_x").get<double>(), 0.0);
  expect_config_rejected(R"({"alarm": {"energy_min_x": 1.2}})", {"alarm.energy_min_x must be in [0, 1]", "got 1.2"});
  expect_config_rejected(R"({"alarm": {"energy_min_x": "0.5"}})", {"alarm.energy_min_x:", "expected a number"});
  expect_config_rejected("{}", {"--energy-min-x must be in [0, 1]"}, {"--energy-min-x", "-0.1"});
}

// The look-ahead (issue 40; `simulate --imminent-horizon`; 0.13 s by default since 2026-12-01): the file's
// alarm.imminent_horizon_s, the option over it, echoed in the settings and in the digest only when on (0, the value
// before, is absent: a configuration that says 0 keeps the digest it had; the default is named and moves it).
TEST(MonitorCommandLine, TheImminentHorizonIsReadEchoedAndInTheDigestOnlyWhenOn) {
  const json defaults = printed_config("", {});
  DOUBLES_EQUAL(0.13, defaults.at("settings").at("alarm").at("imminent_horizon_s").get<double>(), 0.0);
  const json off = printed_config(R"({"alarm": {"imminent_horizon_s": 0}})", {"--imminent-horizon", "0"});
  CHECK(off.at("config_digest") != defaults.at("config_digest"));
  CHECK_FALSE(off.at("settings").at("alarm").contains("imminent_horizon_s"));

  const json file = printed_config(R"({"alarm": {"hold_s": 2, "imminent_horizon_s": 0.17}})", {});
  DOUBLES_EQUAL(0.17, file.at("settings").at("alarm").at("imminent_horizon_s").get<double>(), 0.0);
  DOUBLES_EQUAL(2.0, file.at("settings").at("alarm").at("hold_s").get<double>(), 0.0);
  CHECK(file.at("config_digest") != defaults.at("config_digest"));
  const json option = printed_config("", {"--imminent-horizon", "0.17", "--alarm-hold", "2"});
  CHECK(option.at("config_digest") == file.at("config_digest"));
  // The command line overrides the file (the message names whichever is at fault: ValuesOutOfRange..., above).
  const json over = printed_config(R"({"alarm": {"imminent_horizon_s": 0.17}})", {"--imminent-horizon", "0.25"});
  DOUBLES_EQUAL(0.25, over.at("settings").at("alarm").at("imminent_horizon_s").get<double>(), 0.0);
  expect_config_rejected(R"({"alarm": {"imminent_horizon_s": 0.17}})", {"--imminent-horizon must be in [0, 10] s"},
                         {"--imminent-horizon", "-1"});
  // Both engines run it (the fixed-point one in the firmware's indicators): accepted with either arithmetic. Walls
  // have no alarm of their own (`walls` entries: name, wall, r, channels): every wall runs the top-level one.
  const json dbl = printed_config(R"({"alarm": {"imminent_horizon_s": 0.17}})", {"--arith", "double"});
  DOUBLES_EQUAL(0.17, dbl.at("settings").at("alarm").at("imminent_horizon_s").get<double>(), 0.0);
  const json walls =
      printed_config(R"({"alarm": {"imminent_horizon_s": 0.17}, "walls": [{"name": "a"}, {"name": "b"}]})", {});
  DOUBLES_EQUAL(0.17, walls.at("settings").at("alarm").at("imminent_horizon_s").get<double>(), 0.0);
  expect_config_rejected(R"({"walls": [{"name": "a", "alarm": {"imminent_horizon_s": 0.17}}]})",
                         {"walls[0]", "unknown key 'alarm'"});
}

TEST(MonitorCommandLine, LcmDefaultUrlFromTheEnvironment) {
  const rockwatch::test::EnvOverride env("LCM_DEFAULT_URL", "udpm://239.255.76.67:7674?ttl=0");
  const json j = printed_config("", {});
  STRCMP_EQUAL("udpm://239.255.76.67:7674?ttl=0", j.at("lcm_url").get<std::string>().c_str());
  STRCMP_EQUAL("$LCM_DEFAULT_URL", j.at("lcm_url_origin").get<std::string>().c_str());
}

TEST(MonitorCommandLine, BadOptionValuesNameTheOption) {
  // The wall/--r/--model/--kappa options are `rockwatch simulate`'s, with its messages.
  expect_rejected({"--h1", "0.05"}, {"--h1 must be greater than b (got 0.05"});
  expect_rejected({"--b", "abc"}, {"--b expects a finite number", "'abc'"});
  expect_rejected({"--wall", "brick"}, {"--wall must be paper"});
  expect_rejected({"--r", "2"}, {"--r must be ana, exp, impulse or an energy ratio in [0, 1]"});
  expect_rejected({"--model", "full"}, {"--model full needs --arith double", "linear model only"});
  expect_rejected({"--model", "full", "--arith", "fixed"}, {"--model full needs --arith double", "(arith fixed from --arith)"});
  expect_rejected({"--model", "cubic"}, {"--model must be linear or full", "'cubic'"});
  expect_rejected({"--kappa", "0.9"}, {"--kappa must be >= 1"});
  expect_rejected({"--lambda-w", "0"}, {"--lambda-w must be in (0, 1]"});
  expect_rejected({"--alarm-hold", "nan"}, {"--alarm-hold expects a finite number"});
  expect_rejected({"--energy-margin", "200"}, {"--energy-margin must be in [1, 100]"});
  expect_rejected({"--imminent-horizon", "10.5"}, {"--imminent-horizon must be in [0, 10] s (got 10.5)"});
  expect_rejected({"--imminent-horizon", "soon"}, {"--imminent-horizon expects a finite number", "'soon'"});
  expect_rejected({"--rate", "0"}, {"--rate must be > 0 Hz"});
  expect_rejected({"--rate", "20"}, {"--rate must be in (0, 10000] Hz", "got 20"});
  expect_rejected({"--lcm-url", ""}, {"--lcm-url needs a URL"});
  expect_rejected({"--frobnicate"}, {"unknown option '--frobnicate'", "rockwatch-monitor --help"});
  // An option that overrides a valid file value is named when it is the one at fault.
  expect_config_rejected(R"({"kappa": 3})", {"--kappa must be >= 1"}, {"--kappa", "0.5"});
  expect_config_rejected(R"({"wall": {"b": 0.2}})", {"--h1 must be greater than b (got 0.15; b = 0.2 from", "wall.b"},
                         {"--h1", "0.15"});
}

TEST(MonitorCommandLine, ArithSelectsTheEngineAndTheModel) {
  expect_rejected({"--arith", "float"}, {"--arith must be fixed or double", "'float'"});
  const json fixed = printed_config("", {"--arith", "fixed"});
  STRCMP_EQUAL("fixed", fixed.at("settings").at("arith").get<std::string>().c_str());
  const json dbl = printed_config("", {"--arith", "double"});
  STRCMP_EQUAL("double", dbl.at("settings").at("arith").get<std::string>().c_str());
  STRCMP_EQUAL("linear", dbl.at("settings").at("model").get<std::string>().c_str());
  const json full = printed_config(R"({"arith": "double"})", {"--model", "full"});
  STRCMP_EQUAL("double", full.at("settings").at("arith").get<std::string>().c_str());
  STRCMP_EQUAL("full", full.at("settings").at("model").get<std::string>().c_str());
  // The command line overrides the file's arith; the digest tells the engines apart.
  const json over = printed_config(R"({"arith": "double"})", {"--arith", "fixed"});
  STRCMP_EQUAL("fixed", over.at("settings").at("arith").get<std::string>().c_str());
  CHECK(fixed.at("config_digest") == over.at("config_digest"));
  CHECK(fixed.at("config_digest") != dbl.at("config_digest"));
}

TEST(MonitorCommandLine, OfflineOptionsGoTogether) {
  expect_rejected({"--offline-in", "a.lcmlog"}, {"--offline-in needs --offline-out"});
  expect_rejected({"--offline-out", "b.lcmlog"}, {"--offline-out needs --offline-in"});
  expect_rejected({"--offline-in", "a.lcmlog", "--offline-out", "a.lcmlog"}, {"--offline-out must differ"});
  expect_rejected({"--offline-in", "a.lcmlog", "--offline-out", "b.lcmlog", "--lcm-url", "udpm://239.255.76.67:7667"},
                  {"--lcm-url has no effect in offline mode"});
  const TempDir dir;
  expect_rejected({"--offline-in", dir.file("missing.lcmlog"), "--offline-out", dir.file("out.lcmlog")},
                  {"--offline-in", "No such file or directory"});
  rockwatch::test::write_file(dir.file("text.lcmlog"), "this is not an LCM log\n");
  expect_rejected({"--offline-in", dir.file("text.lcmlog"), "--offline-out", dir.file("out.lcmlog")},
                  {"not an LCM log"});
  expect_rejected({"--offline-in", rockwatch::test::monitor_data_path(rockwatch::test::kShippedLog), "--offline-out", dir.file("no/such/dir/out.lcmlog")},
                  {"--offline-out", "cannot create"});
}

TEST(MonitorCommandLine, HelpAndVersion) {
  const ProcessResult help = run_monitor({"--help"});
  LONGS_EQUAL(0, help.exit_status);
  CHECK(help.out.find("--config FILE") != std::string::npos);
  CHECK(help.out.find("--offline-in") != std::string::npos);
  CHECK(help.out.find("--kappa") != std::string::npos);
  CHECK(help.out.find("--imminent-horizon S") != std::string::npos);
  CHECK(help.out.find("imminent_horizon_s") != std::string::npos);   // the footer's alarm keys
  CHECK(help.out.find("doubt_capacity_min_x") != std::string::npos);  // and observer keys
  const ProcessResult version = run_monitor({"--version"});
  LONGS_EQUAL(0, version.exit_status);
  CHECK(version.out.rfind("rockwatch-monitor ", 0) == 0);
}

TEST_GROUP(MonitorAdapterHelpers){};

TEST(MonitorAdapterHelpers, ExactChannelRegexEscapesEveryMetacharacter) {
  using rockwatch::monitor::exact_channel_regex;
  STRCMP_EQUAL("ROCKWATCH_ACCEL", exact_channel_regex("ROCKWATCH_ACCEL").c_str());
  STRCMP_EQUAL("A\\.B\\*C\\+\\?\\(\\)\\[\\]\\{\\}\\|\\^\\$\\\\", exact_channel_regex("A.B*C+?()[]{}|^$\\").c_str());
}

TEST(MonitorAdapterHelpers, Fnv1a64KnownValues) {
  using rockwatch::monitor::fnv1a64;
  CHECK(fnv1a64("") == 0xcbf29ce484222325ull);
  CHECK(fnv1a64("a") == 0xaf63dc4c8601ec8cull);
  CHECK(fnv1a64("foobar") == 0x85944171f73967e8ull);
  STRCMP_EQUAL("0x85944171f73967e8",
               rockwatch::monitor::digest_hex(static_cast<std::int64_t>(0x85944171f73967e8ull)).c_str());
}

// The high-rate knobs of the adapter (host_tools/monitor/README.md, "Not losing samples at high rates").
TEST(MonitorAdapterHelpers, InputQueueHoldsTwoSecondsAndAtLeastAThousandMessages) {
  using rockwatch::monitor::input_queue_capacity;
  LONGS_EQUAL(1000, input_queue_capacity(200.0));
  LONGS_EQUAL(1000, input_queue_capacity(500.0));
  LONGS_EQUAL(2000, input_queue_capacity(1000.0));
  LONGS_EQUAL(20000, input_queue_capacity(10000.0));
  LONGS_EQUAL(2001, input_queue_capacity(1000.4));  // rounded up
  LONGS_EQUAL(1000, input_queue_capacity(std::nan("")));
}

TEST(MonitorAdapterHelpers, ReceiveBufferIsAddedToUdpmUrlsThatNameNone) {
  using rockwatch::monitor::requested_receive_buffer;
  using rockwatch::monitor::with_receive_buffer;
  STRCMP_EQUAL("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=2097152",
               with_receive_buffer("udpm://239.255.76.67:7667?ttl=0").c_str());
  STRCMP_EQUAL("udpm://239.255.76.67:7667?recv_buf_size=2097152", with_receive_buffer("udpm://239.255.76.67:7667").c_str());
  STRCMP_EQUAL("udpm://239.255.76.67:7667?recv_buf_size=4096",
               with_receive_buffer("udpm://239.255.76.67:7667?recv_buf_size=4096").c_str());  // the user's choice kept
  STRCMP_EQUAL("memq://", with_receive_buffer("memq://").c_str());
  LONGS_EQUAL(2097152, static_cast<long>(requested_receive_buffer(with_receive_buffer("udpm://239.255.76.67:7667?ttl=0"))));
  LONGS_EQUAL(0, static_cast<long>(requested_receive_buffer("udpm://239.255.76.67:7667?ttl=0")));
  LONGS_EQUAL(0, static_cast<long>(requested_receive_buffer("memq://")));
}

// Invalid values and hangs (docs/RELIABILITY.md): the options the groups above do not reach.
TEST_GROUP(MonitorInvalidValues){};

TEST(MonitorInvalidValues, RateArithAndLogValuesNameTheOption) {
  expect_rejected({"--rate", "abc"}, {"--rate", "'abc'"});
  expect_rejected({"--rate", "nan"}, {"--rate", "'nan'"});
  expect_rejected({"--rate", "inf"}, {"--rate", "'inf'"});
  expect_rejected({"--rate", "-200"}, {"--rate", "> 0"});
  expect_rejected({"--rate", "1e6"}, {"--rate", "10000"});
  expect_rejected({"--arith", ""}, {"--arith must be fixed or double", "''"});
  expect_rejected({"--log", ""}, {"--log needs a file name"});
  const TempDir dir;
  expect_rejected({"--log", dir.file("x.lcmlog"), "--offline-in", dir.file("in.lcmlog"), "--offline-out",
                   dir.file("out.lcmlog")},
                  {"--log is for live mode"});
}

// Waits at most 20 s for the monitor: a hang fails the test (wait_status kills it) instead of blocking the suite.
namespace {
rockwatch::test::ProcessResult run_monitor_briefly(const std::vector<std::string>& args) {
  const TempDir capture;
  const int status = rockwatch::test::wait_status(
      rockwatch::test::spawn_monitor(args, capture.file("out"), capture.file("err")), 20.0);
  rockwatch::test::ProcessResult r;
  if (WIFEXITED(status)) r.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.out = rockwatch::test::read_file(capture.file("out"));
  r.err = rockwatch::test::read_file(capture.file("err"));
  return r;
}
}  // namespace

// A FIFO would block in open() for ever, /dev/zero would be read until memory runs out, a directory was an
// "internal error": each is refused before reading, naming --config.
TEST(MonitorInvalidValues, ConfigThatIsNotARegularFileIsRefusedAtOnce) {
  const TempDir dir;
  const std::string fifo = dir.file("monitor.json");
  CHECK(mkfifo(fifo.c_str(), 0600) == 0);
  for (const std::string& path : {fifo, std::string("/dev/zero"), dir.path()}) {
    const rockwatch::test::ProcessResult r = run_monitor_briefly({"--config", path});
    const std::string what = describe(r);
    CHECK_EQUAL_TEXT(2, r.exit_status, what.c_str());
    CHECK_TEXT(r.out.empty(), what.c_str());
    CHECK_TEXT(r.err.find("--config") != std::string::npos, what.c_str());
  }
}

// open(O_WRONLY) on a FIFO blocks until a reader comes: refused when the options are parsed.
TEST(MonitorInvalidValues, LogThatIsAFifoIsRefusedAtOnce) {
  const TempDir dir;
  const std::string fifo = dir.file("traffic.lcmlog");
  CHECK(mkfifo(fifo.c_str(), 0600) == 0);
  const rockwatch::test::ProcessResult r = run_monitor_briefly({"--log", fifo, "--lcm-url", "memq://"});
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(2, r.exit_status, what.c_str());
  CHECK_TEXT(r.err.find("--log") != std::string::npos, what.c_str());
}

TEST(MonitorInvalidValues, AConfigLargerThanOneMebibyteIsRefused) {
  const TempDir dir;
  const std::string path = dir.file("huge.json");
  rockwatch::test::write_file(path, "{" + std::string(std::size_t{1} << 21, ' ') + "}");
  expect_rejected({"--config", path}, {"--config " + path, "larger than 1 MiB"});
}

// --accept-from / accept_from: the sources of input datagrams (the live test is MonitorDatagrams).
TEST_GROUP(MonitorAcceptFrom){};

TEST(MonitorAcceptFrom, BadValuesNameTheOptionOrKeyAndWhatIsExpected) {
  expect_rejected({"--accept-from", "10.0.0.256"}, {"--accept-from", "IPv4 address or network", "10.0.0.256"});
  expect_rejected({"--accept-from", "10.0.0.0/33"}, {"--accept-from", "10.0.0.0/33"});
  expect_rejected({"--accept-from", "host.example"}, {"--accept-from"});
  expect_config_rejected(R"({"accept_from": "10.0.0.1"})", {"accept_from", "expected an array"});
  expect_config_rejected(R"({"accept_from": ["10.0.0.1", "10.0.0"]})", {"accept_from[1]", "\"10.0.0\""});
  expect_config_rejected(R"({"accept_from": [7]})", {"accept_from[0]", "expected a string"});
  expect_rejected({"--receive-path", "kernel"}, {"--receive-path", "own or liblcm"});
  expect_rejected({"--receive-path", "liblcm", "--accept-from", "10.0.0.1"}, {"--accept-from", "--receive-path own"});
  expect_rejected({"--offline-in", "a.lcmlog", "--offline-out", "b.lcmlog", "--accept-from", "10.0.0.1"},
                  {"--accept-from", "live mode"});
}

TEST(MonitorAcceptFrom, InTheSettingsAndTheDigestOnlyWhenGiven) {
  const json none = printed_config("", {});
  CHECK_FALSE(none.at("settings").contains("accept_from"));
  const json given = printed_config(R"({"accept_from": ["192.168.1.20"]})", {"--accept-from", "10.0.0.0/24"});
  // The command line replaces the file's list; a bare address is a /32.
  const json expected = json::array({"10.0.0.0/24"});
  CHECK_TEXT(given.at("settings").at("accept_from") == expected, given.dump().c_str());
  CHECK(given.at("config_digest") != none.at("config_digest"));
  const json file_only = printed_config(R"({"accept_from": ["192.168.1.20"]})", {});
  CHECK(file_only.at("settings").at("accept_from") == json::array({"192.168.1.20/32"}));
}

TEST_GROUP(MonitorObserverSettings){};

TEST(MonitorObserverSettings, BadValuesNameTheKeyAndTheRange) {
  expect_config_rejected(R"({"observer": {"enabled": true, "x_noise_m": 0}})", {"observer.x_noise_m", "noise", "got 0"});
  expect_config_rejected(R"({"observer": {"gate_chi2": 2000}})", {"observer.gate_chi2", "[1, 1000]"});
  expect_config_rejected(R"({"observer": {"capacity_correlation": 1}})",
                         {"observer.capacity_correlation", "capacity_correlation in [0, 0.99]"});
  expect_config_rejected(R"({"observer": {"noise_learn_readings": 4}})",
                         {"observer.noise_learn_readings", "noise_learn_readings 0 or in [8, 100000]"});
  for (const char* beyond : {"-3", "100001", "3000000000", "18446744073709551615", "-9223372036854775808"}) {
    expect_config_rejected(std::string(R"({"observer": {"noise_learn_readings": )") + beyond + "}}",
                           {"observer.noise_learn_readings", "noise_learn_readings 0 or in [8, 100000]", beyond});
  }
  expect_config_rejected(R"({"observer": {"noise_learn_readings": 64.5}})",
                         {"observer.noise_learn_readings", "expected a whole number of readings"});
  expect_config_rejected(R"({"observer": {"dropout_s": -1}})", {"observer.dropout_s", "(0, 60]"});
  expect_config_rejected(R"({"observer": {"max_age_s": 11}})", {"observer.max_age_s", "[0, 10]"});
  expect_config_rejected(R"({"observer": {"capacity_sigmas": 11}})",
                         {"observer.capacity_sigmas", "alarm_capacity_sigmas in [0, 10]"});
  expect_config_rejected(R"({"observer": {"accel_inform_peak_noises": -1}})",
                         {"observer.accel_inform_peak_noises", "accel_inform_peak_noises in [0, 1000]"});
  expect_config_rejected(R"({"observer": {"doubt_nis": 0.5}})", {"observer.doubt_nis", "doubt_nis"});
  expect_config_rejected(R"({"observer": {"quiet_motion_spread_noises": 2000}})",
                         {"observer.quiet_motion_spread_noises", "quiet_motion_spread_noises"});
  expect_config_rejected(R"({"observer": {"model_form_sigma": 2}})", {"observer.model_form_sigma", "model_form_sigma"});
  expect_config_rejected(R"({"observer": {"doubt_model_form_sigma": -1}})",
                         {"observer.doubt_model_form_sigma", "doubt_model_form_sigma"});
  expect_config_rejected(R"({"observer": {"capacity_min_x": 1.5}})",
                         {"observer.capacity_min_x:", "capacity_min_x_fraction in [0, 1]", "got 1.5"});
  expect_config_rejected(R"({"observer": {"enabled": true, "doubt_capacity_min_x": -0.1}})",
                         {"observer.doubt_capacity_min_x:", "doubt_capacity_min_x_fraction in [0, 1]", "got -0.1"});
  expect_config_rejected(R"({"observer": {"capacity_min_x": true}})", {"observer.capacity_min_x", "a boolean"});
  expect_config_rejected(R"({"observer": {"a_noise_mps2": 50}})", {"observer.a_noise_mps2"});
  expect_config_rejected(R"({"observer": {"process_accel_mps2": "1"}})", {"observer.process_accel_mps2", "a string"});
  expect_config_rejected(R"({"observer": {"enabled": 1}})", {"observer.enabled", "true or false"});
  expect_config_rejected(R"({"observer": {"gain": 1}})", {"observer.gain", "unknown key"});
  expect_config_rejected(R"({"observer": true})", {"observer", "an object"});
  // With the observer, the sensor channel is an input: it must differ from every other channel.
  expect_config_rejected(R"({"observer": {"enabled": true}, "channels": {"wall_sensor": "ROCKWATCH_ACCEL"}})",
                         {"channels.wall_sensor", "the same as channels.accel"});
}

TEST(MonitorObserverSettings, InTheSettingsAndTheDigestOnlyWhenEnabled) {
  const json none = printed_config("", {});
  CHECK_FALSE(none.at("settings").contains("observer"));
  CHECK_FALSE(none.at("settings").at("channels").contains("wall_sensor"));
  // Settings given but not enabled change nothing (the digest of existing configurations stays).
  const json off = printed_config(R"({"observer": {"enabled": false, "gate_chi2": 25}})", {});
  CHECK(off.at("config_digest") == none.at("config_digest"));
  const json flag = printed_config("", {"--observer"});
  const json& o = flag.at("settings").at("observer");
  CHECK(o.at("enabled").get<bool>());
  DOUBLES_EQUAL(0.5e-3, o.at("x_noise_m").get<double>(), 0.0);
  DOUBLES_EQUAL(16.0, o.at("gate_chi2").get<double>(), 0.0);
  STRCMP_EQUAL("ROCKWATCH_WALL_SENSOR", flag.at("settings").at("channels").at("wall_sensor").get<std::string>().c_str());
  STRCMP_EQUAL("ROCKWATCH_WALL_ESTIMATE",
               flag.at("settings").at("channels").at("wall_estimate").get<std::string>().c_str());
  CHECK(flag.at("config_digest") != none.at("config_digest"));
  // The file's values with --observer; the file enabling it is the same as the flag.
  const json file = printed_config(R"({"observer": {"gate_chi2": 25, "dropout_s": 0.5}})", {"--observer"});
  DOUBLES_EQUAL(25.0, file.at("settings").at("observer").at("gate_chi2").get<double>(), 0.0);
  DOUBLES_EQUAL(0.5, file.at("settings").at("observer").at("dropout_s").get<double>(), 0.0);
  const json enabled = printed_config(R"({"observer": {"enabled": true}})", {});
  CHECK(enabled.at("config_digest") == flag.at("config_digest"));
  // Model doubt and motion on a quiet ground (SPEC §11): in the settings and the digest only when not the defaults.
  CHECK_FALSE(flag.at("settings").at("observer").contains("doubt_nis"));
  const json doubt = printed_config(R"({"observer": {"enabled": true, "doubt_nis": 0, "quiet_motion_spread_noises": 30}})", {});
  DOUBLES_EQUAL(0.0, doubt.at("settings").at("observer").at("doubt_nis").get<double>(), 0.0);
  DOUBLES_EQUAL(30.0, doubt.at("settings").at("observer").at("quiet_motion_spread_noises").get<double>(), 0.0);
  CHECK(doubt.at("config_digest") != flag.at("config_digest"));
}

// The capacity from the decline of the restoring force (SPEC §11; `simulate --observer-capacity-min-x`,
// `--observer-doubt-capacity-min-x`): file keys only, as the monitor's other observer settings; in the settings and
// the digest only when not their defaults (capacity_min_x 0, doubt_capacity_min_x 0.25).
TEST(MonitorObserverSettings, TheCapacityMinimumsAreEchoedAndInTheDigestOnlyWhenOn) {
  const json flag = printed_config("", {"--observer"});
  CHECK_FALSE(flag.at("settings").at("observer").contains("capacity_min_x"));
  CHECK_FALSE(flag.at("settings").at("observer").contains("doubt_capacity_min_x"));
  const json defaults =
      printed_config(R"({"observer": {"capacity_min_x": 0, "doubt_capacity_min_x": 0.25}})", {"--observer"});
  CHECK(defaults.at("config_digest") == flag.at("config_digest"));
  const json zero = printed_config(R"({"observer": {"capacity_min_x": 0, "doubt_capacity_min_x": 0}})", {"--observer"});
  DOUBLES_EQUAL(0.0, zero.at("settings").at("observer").at("doubt_capacity_min_x").get<double>(), 0.0);
  CHECK(zero.at("config_digest") != flag.at("config_digest"));
  const json on =
      printed_config(R"({"observer": {"enabled": true, "capacity_min_x": 0.1, "doubt_capacity_min_x": 0.2}})", {});
  DOUBLES_EQUAL(0.1, on.at("settings").at("observer").at("capacity_min_x").get<double>(), 0.0);
  DOUBLES_EQUAL(0.2, on.at("settings").at("observer").at("doubt_capacity_min_x").get<double>(), 0.0);
  CHECK(on.at("config_digest") != flag.at("config_digest"));
  const json one = printed_config(R"({"observer": {"enabled": true, "doubt_capacity_min_x": 0.2}})", {});
  CHECK_FALSE(one.at("settings").at("observer").contains("capacity_min_x"));
  CHECK(one.at("config_digest") != on.at("config_digest"));
  // Without the observer they change nothing (the digest of the configuration without them).
  const json none = printed_config("", {});
  const json unused = printed_config(R"({"observer": {"capacity_min_x": 0.1}})", {});
  CHECK(unused.at("config_digest") == none.at("config_digest"));
}
