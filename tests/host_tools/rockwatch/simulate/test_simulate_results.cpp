// `rockwatch simulate` end to end: real processes, results checked against the project's reference values and
// against sim::analyse called in-process with the same inputs (the CLI must add nothing to the engine).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::g7_ug_mps2;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace sim = rockwatch::sim;
namespace records = rockwatch::records;

namespace {

constexpr double kPi = 3.14159265358979323846;
const char* const kElCentro180 = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2";
const char* const kElCentroUp = "RSN6_IMPVALL.I_I-ELC-UP.AT2";

const std::set<std::string> kJsonKeys{"max_abs_x_m", "t_max_abs_x_s",   "collapsed",      "t_collapse_s",
                                      "t_exceed_s",  "collapse_after_end", "n_impacts",    "t_first_motion_s",
                                      "x_inst_m",    "threshold_mps2",  "r",              "pga_mps2",
                                      "dt_s",        "duration_s",      "model",          "kappa"};

nlohmann::json run_json(const std::vector<std::string>& args) {
  const ProcessResult r = run_rockwatch(args);
  CHECK_EQUAL_TEXT(0, r.signal, describe(r).c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  return nlohmann::json::parse(r.out);
}

void check_time(const std::optional<double>& expected, const nlohmann::json& actual, const char* key) {
  if (!expected) {
    CHECK_TEXT(actual.is_null(), key);
    return;
  }
  CHECK_TEXT(actual.is_number(), key);
  DOUBLES_EQUAL(*expected, actual.get<double>(), 1e-12 * std::max(1.0, std::fabs(*expected)));
}

void check_same_double(double expected, const nlohmann::json& actual) {
  DOUBLES_EQUAL(expected, actual.get<double>(), 1e-12 * std::max(1.0, std::fabs(expected)));
}

// The in-process run: what the CLI's JSON must equal.
void check_equals_engine(const sim::AnalysisResult& e, const nlohmann::json& j) {
  check_same_double(e.max_abs_x_m, j["max_abs_x_m"]);
  check_time(e.max_abs_x_m > 0.0 ? std::optional<double>(e.t_max_abs_x_s) : std::nullopt, j["t_max_abs_x_s"],
             "t_max_abs_x_s");
  CHECK_EQUAL(e.collapsed, j["collapsed"].get<bool>());
  check_time(e.t_collapse_s, j["t_collapse_s"], "t_collapse_s");
  check_time(e.t_exceed_s, j["t_exceed_s"], "t_exceed_s");
  CHECK_EQUAL(e.collapse_after_end, j["collapse_after_end"].get<bool>());
  CHECK_EQUAL(e.n_impacts, j["n_impacts"].get<int>());
  check_time(e.t_first_motion_s, j["t_first_motion_s"], "t_first_motion_s");
  check_same_double(e.x_inst_m, j["x_inst_m"]);
  check_same_double(e.threshold_mps2, j["threshold_mps2"]);
  check_same_double(e.r, j["r"]);
  check_same_double(e.pga_mps2, j["pga_mps2"]);
  check_same_double(e.dt_s, j["dt_s"]);
  check_same_double(e.duration_s, j["duration_s"]);
}

// El Centro 180 scaled to `pga_g`, optionally with the UP component, as the CLI documents it: one factor for both,
// the UP record on the horizontal grid (same t0 and dt here, so its first samples).
sim::GroundMotion el_centro_scaled(double pga_g, bool with_vertical, double* factor_out = nullptr) {
  const records::Record h = records::read_record(record_path(kElCentro180));
  sim::GroundMotion m;
  m.dt_s = h.dt_s;
  m.ug_mps2 = h.horizontal_mps2;
  const double factor = pga_g * kG / sim::peak_abs(m.ug_mps2);
  for (double& u : m.ug_mps2) u *= factor;
  if (with_vertical) {
    const records::Record v = records::read_record(record_path(kElCentroUp));
    m.vg_mps2.assign(v.horizontal_mps2.begin(),
                     v.horizontal_mps2.begin() + static_cast<std::ptrdiff_t>(m.ug_mps2.size()));
    for (double& a : m.vg_mps2) a *= factor;
  }
  if (factor_out != nullptr) *factor_out = factor;
  return m;
}

}  // namespace

TEST_GROUP(SimulateElCentro){};

TEST(SimulateElCentro, JsonHasExactlyTheDocumentedKeysAndValues) {
  const nlohmann::json j = run_json(
      {"simulate", "--record", record_path(kElCentro180), "--scale-pga", "0.25", "--max-step", "0.005", "--json"});
  CHECK_TRUE(j.is_object());
  std::set<std::string> keys;
  for (const auto& item : j.items()) keys.insert(item.key());
  CHECK_TRUE(keys == kJsonKeys);

  DOUBLES_EQUAL(0.25 * kG, j["pga_mps2"].get<double>(), 1e-9 * 0.25 * kG);
  DOUBLES_EQUAL(0.005, j["dt_s"].get<double>(), 1e-15);  // record dt 0.01 s, sub-stepped
  DOUBLES_EQUAL(53.71, j["duration_s"].get<double>(), 1e-9);
  DOUBLES_EQUAL(0.1003276, j["x_inst_m"].get<double>(), 1e-6);
  DOUBLES_EQUAL(1.121143, j["threshold_mps2"].get<double>(), 1e-6);
  DOUBLES_EQUAL(0.894141578519, j["r"].get<double>(), 1e-9);
  DOUBLES_EQUAL(2.0, j["kappa"].get<double>(), 0.0);
  STRCMP_EQUAL("linear", j["model"].get<std::string>().c_str());
  CHECK_TRUE(j["collapsed"].is_boolean());
  CHECK_TRUE(j["collapse_after_end"].is_boolean());
  CHECK_TRUE(j["n_impacts"].is_number_integer());
}

TEST(SimulateElCentro, JsonEqualsTheEngineCalledInProcess) {
  const nlohmann::json j = run_json({"simulate", "--record", record_path(kElCentro180), "--scale-pga", "0.25", "--json"});
  const sim::AnalysisResult expected =
      sim::analyse(rockwatch::core::paper_wall(), el_centro_scaled(0.25, false), sim::AnalysisOptions{});
  check_equals_engine(expected, j);
}

TEST(SimulateElCentro, OptionsReachTheEngine) {
  const nlohmann::json j =
      run_json({"simulate", "--record", record_path(kElCentro180), "--scale-pga", "0.3", "--r", "ana", "--model", "full",
                "--kappa", "1.5", "--max-step", "0.002", "--t-end", "20", "--b", "0.12", "--h1", "1.6", "--fp", "500",
                "--a", "0.3", "--a-prime", "0.7", "--json"});
  rockwatch::core::WallParameters wall = rockwatch::core::paper_wall();
  wall.b_m = 0.12;
  wall.h1_m = 1.6;
  wall.fp_npm = 500.0;
  wall.a = 0.3;
  wall.a_prime = 0.7;
  sim::AnalysisOptions o;
  o.restitution.kind = rockwatch::core::RestitutionKind::ana;
  o.model = rockwatch::core::ModelKind::full;
  o.kappa = 1.5;
  o.max_step_s = 0.002;
  o.t_end_s = 20.0;
  check_equals_engine(sim::analyse(wall, el_centro_scaled(0.3, false), o), j);
  STRCMP_EQUAL("full", j["model"].get<std::string>().c_str());
  DOUBLES_EQUAL(1.5, j["kappa"].get<double>(), 0.0);
}

TEST(SimulateElCentro, NumericRIsUsedAsGiven) {
  const nlohmann::json j =
      run_json({"simulate", "--record", record_path(kElCentro180), "--scale-pga", "0.2", "--r", "0.8", "--json"});
  DOUBLES_EQUAL(0.8, j["r"].get<double>(), 0.0);
}

TEST(SimulateElCentro, VerticalRecordRunsAndEqualsTheEngine) {
  const nlohmann::json j = run_json({"simulate", "--record", record_path(kElCentro180), "--vertical",
                                     record_path(kElCentroUp), "--scale-pga", "0.25", "--json"});
  const sim::AnalysisResult expected =
      sim::analyse(rockwatch::core::paper_wall(), el_centro_scaled(0.25, true), sim::AnalysisOptions{});
  check_equals_engine(expected, j);
}

// At 0.1 g the wall stays at rest (below the threshold even with the vertical), so the history covers the whole
// record and shows both inputs as run.
TEST(SimulateElCentro, VerticalIsScaledByTheHorizontalFactor) {
  const TempDir dir;
  const std::string csv_path = dir.file("history.csv");
  const ProcessResult r = run_rockwatch({"simulate", "--record", record_path(kElCentro180), "--vertical",
                                         record_path(kElCentroUp), "--scale-pga", "0.1", "--max-step", "0.005", "--out", csv_path});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  double factor = 0.0;
  const sim::GroundMotion expected = el_centro_scaled(0.1, true, &factor);
  const rockwatch::test::Csv csv = rockwatch::test::read_csv(csv_path);
  const std::vector<double> ug = csv.column(1), vg = csv.column(2);
  DOUBLES_EQUAL(0.1 * kG, sim::peak_abs(ug), 1e-12);
  DOUBLES_EQUAL(sim::peak_abs(expected.vg_mps2), sim::peak_abs(vg), 1e-12);
  // ... and that peak is the UP record's own peak (over the horizontal's span) times the horizontal's factor.
  const records::Record up = records::read_record(record_path(kElCentroUp));
  const std::vector<double> up_span(up.horizontal_mps2.begin(),
                                    up.horizontal_mps2.begin() + static_cast<std::ptrdiff_t>(expected.ug_mps2.size()));
  DOUBLES_EQUAL(sim::peak_abs(up_span) * factor, sim::peak_abs(vg), 1e-12);
  CHECK_EQUAL(2 * (expected.ug_mps2.size() - 1) + 1, csv.rows.size());
}

TEST(SimulateElCentro, HumanReadableSummary) {
  const ProcessResult collapsed =
      run_rockwatch({"simulate", "--record", record_path(kElCentro180), "--scale-pga", "0.25", "--max-step", "0.005"});
  CHECK_EQUAL_TEXT(0, collapsed.exit_status, describe(collapsed).c_str());
  STRCMP_CONTAINS("VERDICT                  COLLAPSED at t = ", collapsed.out.c_str());
  STRCMP_CONTAINS("per metre of wall", collapsed.out.c_str());
  STRCMP_CONTAINS(kElCentro180, collapsed.out.c_str());
  STRCMP_CONTAINS("r = 0.894142 (exp", collapsed.out.c_str());
  STRCMP_CONTAINS("0.2500 g = 2.4525 m/s2", collapsed.out.c_str());

  const ProcessResult survived =
      run_rockwatch({"simulate", "--record", record_path(kElCentro180), "--scale-pga", "0.13", "--max-step", "0.005"});
  CHECK_EQUAL_TEXT(0, survived.exit_status, describe(survived).c_str());
  STRCMP_CONTAINS("VERDICT                  SURVIVED", survived.out.c_str());
  CHECK_TRUE(survived.err.empty());
}

// Reader notes go to stderr, prefixed, and never into the JSON on stdout.
TEST(SimulateElCentro, ReaderNotesGoToStderr) {
  const ProcessResult r = run_rockwatch({"simulate", "--record", record_path("RSN960_NORTHR_LOS270.AT2"), "--json"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  CHECK_TEXT(r.err.rfind("note: RSN960_NORTHR_LOS270.AT2: NPTS=1999", 0) == 0, describe(r).c_str());
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK_EQUAL(kJsonKeys.size(), j.size());
  CHECK_TRUE(r.out.find("note") == std::string::npos);
}

TEST_GROUP(SimulateG7) {
  std::unique_ptr<TempDir> dir;
  std::string record;
  void setup() override {
    dir = std::make_unique<TempDir>();
    record = dir->file("g7.txt");
    rockwatch::test::write_plain_record(record, rockwatch::test::g7_ug_mps2, 0.005, 5.0);
  }
  void teardown() override { dir.reset(); }
};

// The project's verified reference (tests/data/reference, responses/G7 newmark_paper_linear_substep_dt0.005), at its
// step (one step per 5 ms sample).
TEST(SimulateG7, CollapsesAtTheReferenceTime) {
  const nlohmann::json j = run_json({"simulate", "--record", record, "--max-step", "0.005", "--json"});
  CHECK_TRUE(j["collapsed"].get<bool>());
  CHECK_FALSE(j["collapse_after_end"].get<bool>());
  DOUBLES_EQUAL(0.951268486137, j["t_collapse_s"].get<double>(), 1e-9);
  DOUBLES_EQUAL(0.285714285714, j["t_first_motion_s"].get<double>(), 1e-9);
  DOUBLES_EQUAL(0.200655200655, j["max_abs_x_m"].get<double>(), 1e-9);
  DOUBLES_EQUAL(j["t_collapse_s"].get<double>(), j["t_max_abs_x_s"].get<double>(), 0.0);
  CHECK_EQUAL(0, j["n_impacts"].get<int>());
  DOUBLES_EQUAL(0.20 * kG, j["pga_mps2"].get<double>(), 1e-12);
  DOUBLES_EQUAL(5.0, j["duration_s"].get<double>(), 1e-12);
}

TEST(SimulateG7, OutWritesTheTimeHistory) {
  const std::string csv_path = dir->file("g7.csv");
  const ProcessResult r = run_rockwatch({"simulate", "--record", record, "--max-step", "0.005", "--out", csv_path, "--json"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const rockwatch::test::Csv csv = rockwatch::test::read_csv(csv_path);
  STRCMP_EQUAL("t_s,ug_mps2,vg_mps2,x_m,xd_mps,xdd_mps2,alpha1_rad,alpha2_rad,side", csv.header.c_str());
  for (const auto& row : csv.rows) CHECK_EQUAL(9U, row.size());

  const double dt_s = 0.005, t_collapse_s = j["t_collapse_s"].get<double>();
  const auto steps = static_cast<std::size_t>(std::ceil(t_collapse_s / dt_s));  // the last step ends in the collapse
  CHECK_EQUAL(steps + 1, csv.rows.size());
  DOUBLES_EQUAL(0.0, csv.rows.front()[0], 0.0);
  DOUBLES_EQUAL(0.0, csv.rows.front()[3], 0.0);
  DOUBLES_EQUAL(dt_s, csv.rows[1][0], 1e-15);
  DOUBLES_EQUAL(g7_ug_mps2(dt_s), csv.rows[1][1], 1e-15);

  const std::vector<double>& last = csv.rows.back();
  DOUBLES_EQUAL(t_collapse_s, last[0], 0.0);
  // ü < 0 drives the wall towards x > 0; it stops at kappa x_inst.
  DOUBLES_EQUAL(2.0 * j["x_inst_m"].get<double>(), last[3], 1e-15);
  DOUBLES_EQUAL(j["max_abs_x_m"].get<double>(), last[3], 0.0);
  DOUBLES_EQUAL(1.0, last[8], 0.0);
  DOUBLES_EQUAL(-last[3] / 1.75, last[6], 1e-15);  // alpha1 = -x/h1
  DOUBLES_EQUAL(last[3] / 1.75, last[7], 1e-15);   // alpha2 = x/h2
}

TEST(SimulateG7, HumanReadableVerdict) {
  const ProcessResult r = run_rockwatch({"simulate", "--record", record});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  STRCMP_CONTAINS("VERDICT                  COLLAPSED at t = 0.9513 s", r.out.c_str());
  STRCMP_CONTAINS("first motion             t = 0.2857 s", r.out.c_str());
}

// A third column is the vertical on the same grid: the same run as the two columns given as two files.
TEST(SimulateG7, ThirdColumnEqualsVerticalFile) {
  const std::function<double(double)> vg = [](double t) { return 0.3 * kG * std::sin(2.0 * kPi * 2.0 * t); };
  const std::string three = dir->file("three.txt"), vertical = dir->file("vertical.txt");
  rockwatch::test::write_plain_record(three, rockwatch::test::g7_ug_mps2, 0.005, 5.0, &vg);
  rockwatch::test::write_plain_record(vertical, vg, 0.005, 5.0);
  const nlohmann::json from_column = run_json({"simulate", "--record", three, "--json"});
  const nlohmann::json from_file = run_json({"simulate", "--record", record, "--vertical", vertical, "--json"});
  CHECK_TRUE(from_column == from_file);
  // The vertical changes the answer, so it was used.
  const nlohmann::json without = run_json({"simulate", "--record", record, "--json"});
  CHECK_FALSE(from_column == without);
}

// The vertical file on a coarser grid starting later: resampled onto the record's grid, zero outside its span.
TEST(SimulateG7, VerticalOnAnotherGridIsResampled) {
  const std::string vertical = dir->file("vertical_shifted.txt");
  const double t0_s = 0.2, dt_s = 0.01;
  std::vector<double> samples;
  std::string text = "# units: mps2\n";
  for (int k = 0; k <= 100; ++k) {  // 0.2 .. 1.2 s
    char line[64];
    std::snprintf(line, sizeof line, "%.2f %.6f\n", t0_s + dt_s * k, 0.5 * std::sin(3.0 * (t0_s + dt_s * k)));
    text += line;
    samples.push_back(std::strtod(std::strchr(line, ' '), nullptr));
  }
  rockwatch::test::write_text(vertical, text);
  const std::string csv_path = dir->file("shifted.csv");
  const ProcessResult r = run_rockwatch({"simulate", "--record", record, "--vertical", vertical, "--out", csv_path});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  STRCMP_CONTAINS("note: vertical record", r.err.c_str());
  const rockwatch::test::Csv csv = rockwatch::test::read_csv(csv_path);
  std::size_t inside = 0, outside = 0;
  for (const auto& row : csv.rows) {
    const double t = row[0];
    if (std::fabs(t - std::round(t / 0.005) * 0.005) > 1e-12) continue;  // a collapse row is not on the grid
    const double position = (t - t0_s) / dt_s;
    if (position < -1e-6 || position > 100.0 + 1e-6) {
      DOUBLES_EQUAL(0.0, row[2], 0.0);
      ++outside;
    } else {
      const auto i = static_cast<std::size_t>(std::min(99.0, std::floor(position + 1e-6)));
      const double fraction = std::max(0.0, position - static_cast<double>(i));
      DOUBLES_EQUAL(samples[i] + (samples[i + 1] - samples[i]) * fraction, row[2], 1e-12);
      ++inside;
    }
  }
  CHECK_TRUE(inside > 100);
  CHECK_TRUE(outside > 10);
}
