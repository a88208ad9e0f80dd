// `rockwatch identify` and the wall file as a user runs them: a snap-back test made by `simulate --x0
// --sensors-out`, identified (text, --json, --wall-out, --plot), the wall file read back by simulate (its answers those
// of the identified wall's fields given as options), study and rockwatch-monitor; the records that do not identify a
// wall and the wall files that are wrong refused with exit 2, naming why or the field.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/sim/identification.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::expect_command_rejected;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_program;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
using rockwatch::test::write_text;
namespace core = rockwatch::core;
using nlohmann::json;

namespace {

void check_ok(const ProcessResult& r) {
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}


// A wall 10 % thinner than the paper's with r = 0.85, released from 50 mm, its transducer with an offset of 2 mm.
std::string make_snap_back(const TempDir& dir) {
  const std::string path = dir.file("snap.csv");
  check_ok(run_rockwatch({"simulate", "--x0", "0.05", "--b", "0.09", "--r", "0.85", "--t-end", "6", "--sensors-out",
                          path, "--sensor-bias-m", "0.002", "--sensor-rate-hz", "200"}));
  return path;
}

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace

TEST_GROUP(IdentifyCommand){};

TEST(IdentifyCommand, SimulateX0MakesASnapBackTestThatStartsAtX0AndSettles) {
  const ProcessResult r = run_rockwatch({"simulate", "--x0", "0.05", "--b", "0.09", "--r", "0.85", "--json"});
  check_ok(r);
  const json j = json::parse(r.out);
  DOUBLES_EQUAL(0.05, j.at("x0_m").get<double>(), 0.0);
  DOUBLES_EQUAL(0.05, j.at("max_abs_x_m").get<double>(), 1e-12);  // released from rest: x0 is the largest
  CHECK_FALSE(j.at("collapsed").get<bool>());
  CHECK(j.at("n_impacts").get<int>() > 20);
  // Beyond x_inst with no ground motion it falls.
  const ProcessResult fall = run_rockwatch({"simulate", "--x0", "0.101", "--json"});
  check_ok(fall);
  CHECK(json::parse(fall.out).at("collapse_after_end").get<bool>());
  expect_command_rejected("simulate", {"--x0", "2"}, {"--x0", "[-1, 1]"});
  expect_command_rejected("simulate", {"--x0", "0.05", "--scale-pga", "0.2"}, {"--scale-pga", "needs a record"});
}

TEST(IdentifyCommand, ASnapBackTestGivesTheWallAndItsFileReproducesIt) {
  TempDir dir;
  const std::string sensors = make_snap_back(dir);
  const std::string wall_out = dir.file("wall.json"), png = dir.file("fit.png");
  const ProcessResult r =
      run_rockwatch({"identify", "--wall-sensors", sensors, "--json", "--wall-out", wall_out, "--plot", png});
  check_ok(r);
  const json j = json::parse(r.out);
  CHECK_EQUAL("snap-back", j.at("test").get<std::string>());
  core::WallParameters truth = core::paper_wall();
  truth.b_m = 0.09;
  const double x_inst_true = rockwatch::sim::reduced_parameters(truth).x_inst_m;
  const double r_hat = j.at("r").get<double>(), x_inst = j.at("x_inst_m").get<double>();
  CHECK(std::fabs(r_hat - 0.85) < 0.005);
  CHECK(std::fabs(x_inst - x_inst_true) < 0.01 * x_inst_true);
  CHECK(std::fabs(x_inst - x_inst_true) < 4.0 * j.at("sigma_x_inst_m").get<double>());
  CHECK(std::fabs(j.at("offset_m").get<double>() - 0.002) < 4.0 * j.at("sigma_offset_m").get<double>());
  CHECK(j.at("residual_rms_m").get<double>() > 4e-4 && j.at("residual_rms_m").get<double>() < 6e-4);
  CHECK(j.at("fit_explains_record").get<bool>());
  CHECK(j.at("x0_m").is_number());
  for (const char* key : {"sigma_r", "omega_radps", "sigma_omega_radps", "k_ps2", "c_mps2", "gamma", "wall",
                          "wall_sigma", "identified", "held", "n_impacts"}) {
    CHECK_TEXT(j.contains(key), key);
  }
  // The plot is a PNG.
  CHECK(read_text(png).rfind("\x89PNG", 0) == 0);
  // The wall file: the identified wall and r.
  const json w = json::parse(read_text(wall_out));
  CHECK_EQUAL("rockwatch-wall", w.at("format").get<std::string>());
  DOUBLES_EQUAL(r_hat, w.at("r").get<double>(), 0.0);
  DOUBLES_EQUAL(j.at("wall").at("b_m").get<double>(), w.at("b_m").get<double>(), 0.0);
  DOUBLES_EQUAL(x_inst, w.at("reduced").at("x_inst_m").get<double>(), 1e-15);
  // simulate --wall-file alone predicts with the identified wall: the same answers as its fields and r as options.
  const std::vector<std::string> record{"--record", rockwatch::test::record_path("RSN6_IMPVALL.I_I-ELC180-hor1.AT2"),
                                        "--scale-pga", "0.2", "--json"};
  std::vector<std::string> from_file{"simulate", "--wall-file", wall_out};
  from_file.insert(from_file.end(), record.begin(), record.end());
  std::vector<std::string> from_options{"simulate", "--b", num(w.at("b_m").get<double>()), "--h1",
                                        num(w.at("h1_m").get<double>()), "--h2", num(w.at("h2_m").get<double>()),
                                        "--r", num(r_hat)};
  from_options.insert(from_options.end(), record.begin(), record.end());
  const ProcessResult a = run_rockwatch(from_file), b = run_rockwatch(from_options);
  check_ok(a);
  check_ok(b);
  json ja = json::parse(a.out), jb = json::parse(b.out);
  CHECK_EQUAL(wall_out, ja.at("wall_file").get<std::string>());
  ja.erase("wall_file");
  CHECK_EQUAL(jb.dump(), ja.dump());
  // --r overrides the file's r.
  std::vector<std::string> with_r = from_file;
  with_r.insert(with_r.end(), {"--r", "ana"});
  const ProcessResult c = run_rockwatch(with_r);
  check_ok(c);
  CHECK(std::fabs(json::parse(c.out).at("r").get<double>() - r_hat) > 0.1);
  // The monitor reads it (option and configuration key) into its settings.
  const ProcessResult m = run_program(ROCKWATCH_MONITOR_PATH, {"--wall-file", wall_out, "--print-config"});
  check_ok(m);
  const json settings = json::parse(m.out).at("settings");
  DOUBLES_EQUAL(w.at("b_m").get<double>(), settings.at("wall").at("b").get<double>(), 0.0);
  DOUBLES_EQUAL(r_hat, settings.at("r_energy_ratio").get<double>(), 0.0);
  write_text(dir.file("monitor.json"), "{\"wall_file\": \"wall.json\"}");
  const ProcessResult mc = run_program(ROCKWATCH_MONITOR_PATH, {"--config", dir.file("monitor.json"), "--print-config"});
  check_ok(mc);
  CHECK_EQUAL(settings.dump(), json::parse(mc.out).at("settings").dump());
  // study: the file's r is the one restitution case.
  const ProcessResult s = run_rockwatch({"study", "--wall-file", wall_out, "--out", dir.file("study"), "--sets", "1",
                                         "--pga", "0.2:0.2:0.01", "--vertical", "without"});
  check_ok(s);
  CHECK(read_text(dir.file("study") + "/runs.csv").find(num(r_hat).substr(0, 6)) != std::string::npos);
}

TEST(IdentifyCommand, ABootstrapReplacesTheStandardErrorsAndSaysSo) {
  TempDir dir;
  const std::string sensors = make_snap_back(dir);
  const ProcessResult plain = run_rockwatch({"identify", "--wall-sensors", sensors, "--json"});
  check_ok(plain);
  const json p = json::parse(plain.out);
  CHECK_EQUAL("curvature", p.at("sigma_method").get<std::string>());
  CHECK(p.at("bootstrap").is_null());
  const std::string wall_out = dir.file("wall.json");
  const ProcessResult boot = run_rockwatch(
      {"identify", "--wall-sensors", sensors, "--json", "--bootstrap", "3", "--jobs", "2", "--wall-out", wall_out});
  check_ok(boot);
  const json j = json::parse(boot.out);
  CHECK_EQUAL("bootstrap", j.at("sigma_method").get<std::string>());
  const json& b = j.at("bootstrap");
  CHECK_EQUAL(3, b.at("replicates").get<int>());
  CHECK_EQUAL(1, b.at("seed").get<int>());
  CHECK_EQUAL(3, b.at("used").get<int>() + b.at("flagged").get<int>() + b.at("refused").get<int>());
  // The point estimates are the record's own fit; the curvature's errors are kept beside the bootstrap's.
  CHECK(j.at("x_inst_m").get<double>() == p.at("x_inst_m").get<double>());
  CHECK(j.at("r").get<double>() == p.at("r").get<double>());
  CHECK(b.at("curvature_sigma_x_inst_m").get<double>() == p.at("sigma_x_inst_m").get<double>());
  CHECK(j.at("sigma_x_inst_m").get<double>() != p.at("sigma_x_inst_m").get<double>());
  CHECK(j.at("sigma_x_inst_m").get<double>() > 0.0);
  // Values, not only `!=` (issue 42): on a snap-back test the bootstrap's spread is the curvature's error (the sim
  // suite's IdentificationBootstrap), here from 3 refits: their ratio within [0.1, 4] (the SD of 3 draws is within
  // 0.1–2 of σ with probability > 0.99; 4 leaves the curvature's own error room).
  for (const char* k : {"x_inst_m", "r"}) {
    const double ratio = j.at(std::string("sigma_") + k).get<double>() / p.at(std::string("sigma_") + k).get<double>();
    CHECK_TEXT(ratio > 0.1 && ratio < 4.0, (std::string(k) + ": bootstrap / curvature sigma " + std::to_string(ratio)).c_str());
  }
  CHECK_EQUAL("bootstrap", json::parse(read_text(wall_out)).at("identified").at("sigma_method").get<std::string>());
  const ProcessResult text = run_rockwatch({"identify", "--wall-sensors", sensors, "--bootstrap", "3"});
  check_ok(text);
  CHECK(text.out.find("the spread of") != std::string::npos);
  CHECK(text.out.find("3 refits (seed 1)") != std::string::npos);
#ifndef ROCKWATCH_TEST_SANITIZED
  // Release only: two more whole identifications with bootstraps (the debug entry took 46 s of its 150 with a build
  // beside it, issue 42). The sanitizers have seen the bootstrap's threads above; what follows compares numbers, which
  // the release build does.
  // --bootstrap-seed: another seed, other refits and another σ, said in the JSON; seed 1 given is the default, and the
  // thread count changes nothing (bit for bit).
  const ProcessResult seeded = run_rockwatch(
      {"identify", "--wall-sensors", sensors, "--json", "--bootstrap", "3", "--jobs", "2", "--bootstrap-seed", "2"});
  check_ok(seeded);
  const json s2 = json::parse(seeded.out);
  CHECK_EQUAL(2, s2.at("bootstrap").at("seed").get<int>());
  CHECK(s2.at("x_inst_m").get<double>() == j.at("x_inst_m").get<double>());
  CHECK(s2.at("sigma_x_inst_m").get<double>() != j.at("sigma_x_inst_m").get<double>());
  CHECK(s2.at("sigma_r").get<double>() != j.at("sigma_r").get<double>());
  const ProcessResult seed1 = run_rockwatch(
      {"identify", "--wall-sensors", sensors, "--json", "--bootstrap", "3", "--jobs", "1", "--bootstrap-seed", "1"});
  check_ok(seed1);
  const json s1 = json::parse(seed1.out);
  CHECK(s1.at("sigma_x_inst_m").get<double>() == j.at("sigma_x_inst_m").get<double>());
  CHECK(s1.at("sigma_r").get<double>() == j.at("sigma_r").get<double>());
#endif
}

TEST(IdentifyCommand, ARecordThatDoesNotIdentifyTheWallExitsTwoSayingWhy) {
  TempDir dir;
  std::string rest = "t_s,x_mid_m\n";
  for (int i = 0; i < 400; ++i) rest += num(0.005 * i) + "," + num(0.002 + 0.0003 * std::sin(1.7 * i)) + "\n";
  write_text(dir.file("rest.csv"), rest);
  expect_command_rejected("identify", {"--wall-sensors", dir.file("rest.csv")}, {"does not identify", "at rest"});
  write_text(dir.file("short.csv"), "t_s,x_mid_m\n0,0.05\n0.005,0.049\n0.01,0.048\n");
  expect_command_rejected("identify", {"--wall-sensors", dir.file("short.csv")}, {"does not identify", "too short"});
  write_text(dir.file("accel.csv"), "t_s,a_mid_mps2\n0,0.1\n0.005,0.2\n");
  expect_command_rejected("identify", {"--wall-sensors", dir.file("accel.csv")}, {"no displacement samples"});
  expect_command_rejected("identify", {}, {"--wall-sensors"});
  expect_command_rejected("identify", {"--wall-sensors", dir.file("rest.csv"), "--scale-pga", "0.2"},
                          {"--scale-pga", "needs a record"});
  // The bootstrap's options.
  expect_command_rejected("identify", {"--wall-sensors", dir.file("rest.csv"), "--bootstrap", "10001"},
                          {"--bootstrap", "0 to 10000", "10001"});
  expect_command_rejected("identify", {"--wall-sensors", dir.file("rest.csv"), "--bootstrap", "2.5"},
                          {"--bootstrap", "whole number"});
  expect_command_rejected("identify", {"--wall-sensors", dir.file("rest.csv"), "--bootstrap", "3", "--jobs", "x"},
                          {"--jobs", "whole number"});
  expect_command_rejected("identify", {"--wall-sensors", dir.file("rest.csv"), "--bootstrap-seed", "7"},
                          {"--bootstrap-seed", "needs --bootstrap"});
  expect_command_rejected("identify", {"--wall-sensors", dir.file("rest.csv"), "--jobs", "2"},
                          {"--jobs", "needs --bootstrap"});
}

TEST(IdentifyCommand, AWrongWallFileIsRefusedNamingTheField) {
  TempDir dir;
  const std::string good =
      "{\"format\": \"rockwatch-wall\", \"version\": 1, \"b_m\": 0.1, \"h1_m\": 1.75, \"h2_m\": 1.75, "
      "\"rho_kgpm3\": 1800, \"fp_npm\": 0, \"a\": 0, \"a_prime\": 0, \"g_mps2\": 9.81, \"r\": 0.9}";
  write_text(dir.file("good.json"), good);
  check_ok(run_rockwatch({"simulate", "--wall-file", dir.file("good.json"), "--x0", "0.02"}));
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {replaced("\"h1_m\": 1.75, ", ""), {"'h1_m'", "missing"}},
      {replaced("\"r\": 0.9", "\"r\": 1.5"), {"'r'", "[0, 1]"}},
      {replaced("\"r\": 0.9", "\"r\": 0.9, \"thickness\": 1"), {"unknown field", "'thickness'"}},
      {replaced("\"b_m\": 0.1", "\"b_m\": -0.1"), {"'b_m'", "> 0"}},
      {replaced("\"h2_m\": 1.75", "\"h2_m\": 0.05"), {"'h2_m'", "greater than b"}},
      {replaced("\"b_m\": 0.1", "\"b_m\": \"0.1\""), {"'b_m'", "number"}},
      {replaced("\"version\": 1", "\"version\": 2"), {"'version'"}},
      {replaced("\"r\": 0.9", "\"r\": 0.9, \"reduced\": {\"x_inst_m\": 0.2}"), {"'reduced.x_inst_m'", "disagrees"}},
      {"{\"b_m\": ", {"not valid JSON"}},
  };
  for (const auto& [text, mentions] : cases) {
    write_text(dir.file("bad.json"), text);
    expect_command_rejected("simulate", {"--wall-file", dir.file("bad.json"), "--x0", "0.02"}, mentions);
  }
  expect_command_rejected("simulate", {"--wall-file", dir.file("missing.json"), "--x0", "0.02"}, {"missing.json"});
  // Every tool that reads a wall file refuses a wrong one the same way.
  write_text(dir.file("bad.json"), replaced("\"h1_m\": 1.75, ", ""));
  for (const char* command : {"demo", "study", "identify", "dashboard"}) {
    std::vector<std::string> args{"--wall-file", dir.file("bad.json")};
    if (std::string(command) == "study") args.insert(args.end(), {"--out", dir.file("s")});
    if (std::string(command) == "identify") args.insert(args.end(), {"--wall-sensors", dir.file("good.json")});
    expect_command_rejected(command, args, {"'h1_m'", "missing"});
  }
  const ProcessResult m = run_program(ROCKWATCH_MONITOR_PATH, {"--wall-file", dir.file("bad.json"), "--print-config"});
  CHECK_EQUAL_TEXT(2, m.exit_status, describe(m).c_str());
  CHECK_TEXT(m.err.find("'h1_m'") != std::string::npos, describe(m).c_str());
}
