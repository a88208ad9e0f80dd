// `rockwatch spectrum` end to end: real processes, results checked against sim::response_spectrum and
// sim::intensity_measures called in-process with the same inputs (the CLI must add nothing), the design-spectrum
// target, the CSV and PNG outputs, and every rejection (exit 2, a message naming the option).
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/response_spectrum.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::record_path;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace sim = rockwatch::sim;
namespace core = rockwatch::core;
namespace records = rockwatch::records;

namespace {

const std::string kElCentro180 = record_path("RSN6_IMPVALL.I_I-ELC180-hor1.AT2");
const std::string kRsn175 = record_path("RSN175_IMPVALL.H_H-E12140.AT2");

const std::set<std::string> kJsonKeys{"periods_s", "sa_mps2",   "pga_mps2", "pgv_mps",
                                      "pgd_m",     "arias_mps", "d5_75_s",  "d5_95_s"};

std::set<std::string> keys_of(const nlohmann::json& j) {
  std::set<std::string> keys;
  for (const auto& item : j.items()) keys.insert(item.key());
  return keys;
}

nlohmann::json run_json(const std::vector<std::string>& args, std::string* err = nullptr) {
  const ProcessResult r = run_rockwatch(args);
  CHECK_EQUAL_TEXT(0, r.signal, describe(r).c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  if (err != nullptr) *err = r.err;
  return nlohmann::json::parse(r.out);
}

void check_same(double expected, const nlohmann::json& actual, const char* what) {
  CHECK_TEXT(actual.is_number(), what);
  DOUBLES_EQUAL_TEXT(expected, actual.get<double>(), 1e-12 * std::fmax(1e-12, std::fabs(expected)), what);
}

void check_same_list(const std::vector<double>& expected, const nlohmann::json& actual, const char* what) {
  CHECK_TEXT(actual.is_array(), what);
  LONGS_EQUAL_TEXT(expected.size(), actual.size(), what);
  for (std::size_t i = 0; i < expected.size(); ++i) check_same(expected[i], actual[i], what);
}

// What the CLI must print: the sim functions on the record as records::read_record gives it.
void check_equals_in_process(const nlohmann::json& j, const std::string& path, const std::vector<double>& periods,
                             double damping, double g_mps2 = kG) {
  records::ReadOptions options;
  options.g_mps2 = g_mps2;
  const records::Record r = records::read_record(path, options);
  const sim::ResponseSpectrum s = sim::response_spectrum(r.horizontal_mps2, r.dt_s, periods, damping);
  const sim::IntensityMeasures m = sim::intensity_measures(r.horizontal_mps2, r.dt_s, g_mps2);
  check_same_list(periods, j["periods_s"], "periods_s");
  check_same_list(s.psa_mps2, j["sa_mps2"], "sa_mps2");
  check_same(m.pga_mps2, j["pga_mps2"], "pga_mps2");
  check_same(m.pgv_mps, j["pgv_mps"], "pgv_mps");
  check_same(m.pgd_m, j["pgd_m"], "pgd_m");
  check_same(m.arias_mps, j["arias_mps"], "arias_mps");
  check_same(*m.d5_75_s, j["d5_75_s"], "d5_75_s");
  check_same(*m.d5_95_s, j["d5_95_s"], "d5_95_s");
}

}  // namespace

TEST_GROUP(SpectrumCommand){};

TEST(SpectrumCommand, JsonHasExactlyTheDocumentedKeysAndTheEnginesValues) {
  const nlohmann::json j = run_json({"spectrum", "--record", kElCentro180, "--json"});
  CHECK_TRUE(keys_of(j) == kJsonKeys);
  check_equals_in_process(j, kElCentro180, sim::default_spectrum_periods(), 0.05);
  LONGS_EQUAL(100, j["periods_s"].size());
  DOUBLES_EQUAL(0.2808 * kG, j["pga_mps2"].get<double>(), 0.5e-4 * kG);
  DOUBLES_EQUAL(24.2, j["d5_95_s"].get<double>(), 0.1);
}

TEST(SpectrumCommand, DampingAndPeriodsAreUsed) {
  const nlohmann::json j =
      run_json({"spectrum", "--record", kRsn175, "--damping", "0.02", "--periods", "0.05:3:20", "--json"});
  CHECK_TRUE(keys_of(j) == kJsonKeys);
  check_equals_in_process(j, kRsn175, sim::log_spaced_periods(0.05, 3.0, 20), 0.02);
}

// Records in g are converted with --g, and the Arias intensity divides by the same g.
TEST(SpectrumCommand, GravityOptionConvertsTheRecordAndTheArias) {
  const nlohmann::json j = run_json({"spectrum", "--record", kElCentro180, "--g", "9.80665", "--json"});
  check_equals_in_process(j, kElCentro180, sim::default_spectrum_periods(), 0.05, 9.80665);
  DOUBLES_EQUAL(0.2808 * 9.80665, j["pga_mps2"].get<double>(), 0.5e-4 * 9.80665);
}

TEST(SpectrumCommand, TargetAddsItsKeysWithShapeTimesPgaTimesG) {
  std::string err;
  const nlohmann::json j =
      run_json({"spectrum", "--record", kElCentro180, "--target", "npr9998-2015", "--pga", "0.25", "--json"}, &err);
  std::set<std::string> expected_keys = kJsonKeys;
  expected_keys.insert("target_sa_mps2");
  expected_keys.insert("target");
  CHECK_TRUE(keys_of(j) == expected_keys);
  STRCMP_EQUAL("npr9998-2015", j["target"].get<std::string>().c_str());
  const std::vector<double> periods = sim::default_spectrum_periods();
  std::vector<double> expected;
  for (const double t : periods) expected.push_back(core::spectrum_shape(core::spectrum_npr9998_2015(), t) * 0.25 * kG);
  check_same_list(expected, j["target_sa_mps2"], "target_sa_mps2");
  DOUBLES_EQUAL(2.5 * 0.25 * kG, j["target_sa_mps2"][50].get<double>(), 1e-12);  // T = 0.29 s, on the plateau
  // The JSON keeps its keys; the provenance the specification asks for goes to stderr.
  STRCMP_CONTAINS("back-calculated", err.c_str());
  check_equals_in_process(j, kElCentro180, periods, 0.05);
}

TEST(SpectrumCommand, EveryNamedTargetAndCustom) {
  struct Case {
    std::vector<std::string> args;
    core::SpectrumShape shape;
  };
  const Case cases[] = {
      {{"--target", "ec8-1A"}, core::spectrum_ec8_1A()},
      {{"--target", "ec8-2A"}, core::spectrum_ec8_2A()},
      {{"--target", "vertical-default"}, core::spectrum_vertical_default()},
      {{"--target", "custom", "--p", "3", "--tb", "0.1", "--tc", "0.5", "--td", "2"}, core::spectrum_custom(3, 0.1, 0.5, 2)},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"spectrum", "--record", kRsn175, "--periods", "0.02:4:30", "--pga", "0.3", "--json"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const nlohmann::json j = run_json(args);
    STRCMP_EQUAL(core::spectrum_name(c.shape.kind), j["target"].get<std::string>().c_str());
    const std::vector<double> periods = sim::log_spaced_periods(0.02, 4.0, 30);
    std::vector<double> expected;
    for (const double t : periods) expected.push_back(core::spectrum_shape(c.shape, t) * 0.3 * kG);
    check_same_list(expected, j["target_sa_mps2"], core::spectrum_name(c.shape.kind));
  }
}

TEST(SpectrumCommand, HumanSummaryHasMeasuresTableAndProvenance) {
  const ProcessResult r =
      run_rockwatch({"spectrum", "--record", kElCentro180, "--target", "npr9998-2015", "--pga", "0.25"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  for (const char* text : {"PGA", "0.2808 g", "PGV", "PGD", "Arias intensity", "D5-75", "12.18 s", "D5-95", "24.19 s",
                           "damping 5 %", "Sa/Se", "back-calculated", "npr9998-2015 (p 2.5, TB 0.15 s, TC 0.4 s"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
  // The table's rows: Sa at the standard periods computed exactly, not read off the grid.
  const records::Record rec = records::read_record(kElCentro180);
  const sim::ResponseSpectrum s = sim::response_spectrum(rec.horizontal_mps2, rec.dt_s, {0.1, 0.2, 0.3, 0.5, 1.0, 2.0});
  for (std::size_t i = 0; i < s.periods_s.size(); ++i) {
    char cell[32];
    std::snprintf(cell, sizeof cell, "%12.4f", s.psa_mps2[i]);
    STRCMP_CONTAINS(cell, r.out.c_str());
  }
}

TEST(SpectrumCommand, PlainRecordWithUnitsAndDt) {
  TempDir dir;
  const std::string path = dir.file("bare.txt");
  std::string text;
  for (int k = 0; k < 400; ++k) text += std::to_string(50.0 * std::sin(0.1 * k)) + "\n";  // cm/s2
  rockwatch::test::write_text(path, text);
  const nlohmann::json j =
      run_json({"spectrum", "--record", path, "--units", "cmps2", "--dt", "0.01", "--periods", "0.1:2:5", "--json"});
  records::ReadOptions options;
  options.units = records::AccelUnit::cmps2;
  options.dt_s = 0.01;
  const records::Record r = records::read_record(path, options);
  const sim::ResponseSpectrum s = sim::response_spectrum(r.horizontal_mps2, 0.01, sim::log_spaced_periods(0.1, 2, 5));
  check_same_list(s.psa_mps2, j["sa_mps2"], "sa_mps2");
  DOUBLES_EQUAL(0.5, j["pga_mps2"].get<double>(), 1e-3);
}

// A record without motion has no significant duration: null, not a number.
TEST(SpectrumCommand, SilentRecordHasNullDurations) {
  TempDir dir;
  const std::string path = dir.file("zero.txt");
  rockwatch::test::write_plain_record(path, [](double) { return 0.0; }, 0.01, 2.0);
  const nlohmann::json j = run_json({"spectrum", "--record", path, "--json"});
  CHECK_TRUE(keys_of(j) == kJsonKeys);
  CHECK_TRUE(j["d5_75_s"].is_null());
  CHECK_TRUE(j["d5_95_s"].is_null());
  DOUBLES_EQUAL(0.0, j["sa_mps2"][10].get<double>(), 0.0);
}

TEST(SpectrumCommand, OutCsvHasTheSpectrum) {
  TempDir dir;
  const std::string out = dir.file("spectrum.csv");
  const nlohmann::json j = run_json({"spectrum", "--record", kElCentro180, "--out", out, "--json"});
  const rockwatch::test::Csv csv = rockwatch::test::read_csv(out);
  STRCMP_EQUAL("period_s,sa_mps2", csv.header.c_str());
  LONGS_EQUAL(100, csv.rows.size());
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    LONGS_EQUAL(2, csv.rows[i].size());
    DOUBLES_EQUAL(j["periods_s"][i].get<double>(), csv.rows[i][0], 0.0);  // shortest round-trip text both ways
    DOUBLES_EQUAL(j["sa_mps2"][i].get<double>(), csv.rows[i][1], 0.0);
  }

  const std::string out_target = dir.file("target.csv");
  const nlohmann::json jt = run_json(
      {"spectrum", "--record", kElCentro180, "--target", "ec8-1A", "--pga", "0.2", "--out", out_target, "--json"});
  const rockwatch::test::Csv csv_t = rockwatch::test::read_csv(out_target);
  STRCMP_EQUAL("period_s,sa_mps2,target_sa_mps2", csv_t.header.c_str());
  LONGS_EQUAL(100, csv_t.rows.size());
  for (std::size_t i = 0; i < csv_t.rows.size(); ++i) {
    DOUBLES_EQUAL(jt["target_sa_mps2"][i].get<double>(), csv_t.rows[i][2], 0.0);
  }
}

TEST(SpectrumCommand, PlotWritesAPng) {
  TempDir dir;
  const std::string png = dir.file("spectrum.png");
  const ProcessResult r = run_rockwatch(
      {"spectrum", "--record", kElCentro180, "--target", "npr9998-2015", "--pga", "0.25", "--plot", png});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  STRCMP_CONTAINS(png.c_str(), r.out.c_str());
  std::ifstream in(png, std::ios::binary);
  char signature[8] = {};
  in.read(signature, 8);
  const unsigned char expected[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  for (int i = 0; i < 8; ++i) LONGS_EQUAL(expected[i], static_cast<unsigned char>(signature[i]));
  CHECK(std::filesystem::file_size(png) > 10 * 1024);
}

TEST(SpectrumCommand, HelpNamesTheKeysAndSaysWhenTargetKeysAppear) {
  const ProcessResult r = run_rockwatch({"spectrum", "--help"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  for (const char* text : {"--record", "--damping", "--periods", "--target", "--pga", "--plot", "periods_s",
                           "d5_95_s", "only with --target also target_sa_mps2"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
  const ProcessResult top = run_rockwatch({"--help"});
  STRCMP_CONTAINS("spectrum", top.out.c_str());
}

namespace {

void expect_rejected(const std::vector<std::string>& args, const std::vector<std::string>& mentions) {
  rockwatch::test::expect_command_rejected("spectrum", args, mentions);
}

void expect_rejected_option(const std::string& option, const std::string& value, const std::string& mention) {
  expect_rejected({"--record", kElCentro180, option, value}, {option, mention});
}

}  // namespace

TEST_GROUP(SpectrumRejects){};

TEST(SpectrumRejects, MissingRecord) { expect_rejected({"--json"}, {"--record"}); }
TEST(SpectrumRejects, UnknownOption) { expect_rejected({"--record", kElCentro180, "--frobnicate"}, {"--frobnicate"}); }
TEST(SpectrumRejects, DampingOne) { expect_rejected_option("--damping", "1", "[0, 1)"); }
TEST(SpectrumRejects, DampingAboveOne) { expect_rejected_option("--damping", "5", "[0, 1)"); }
TEST(SpectrumRejects, DampingNegative) { expect_rejected_option("--damping", "-0.05", "[0, 1)"); }
TEST(SpectrumRejects, DampingNotANumber) { expect_rejected_option("--damping", "5%", "'5%'"); }
TEST(SpectrumRejects, DampingNan) { expect_rejected_option("--damping", "nan", "finite"); }
TEST(SpectrumRejects, PeriodsFromZero) { expect_rejected_option("--periods", "0:4:100", "FROM must be > 0"); }
TEST(SpectrumRejects, PeriodsFromNegative) { expect_rejected_option("--periods", "-1:4:100", "FROM must be > 0"); }
TEST(SpectrumRejects, PeriodsToNotAboveFrom) { expect_rejected_option("--periods", "2:1:100", "TO must be greater"); }
TEST(SpectrumRejects, PeriodsToEqualsFrom) { expect_rejected_option("--periods", "1:1:100", "TO must be greater"); }
TEST(SpectrumRejects, PeriodsOnlyOne) { expect_rejected_option("--periods", "0.1:4:1", "N must be >= 2"); }
TEST(SpectrumRejects, PeriodsNotAWholeNumber) { expect_rejected_option("--periods", "0.1:4:1e2", "whole number"); }
TEST(SpectrumRejects, PeriodsTooMany) { expect_rejected_option("--periods", "0.1:4:100000", "N must be <="); }
TEST(SpectrumRejects, PeriodsMalformed) { expect_rejected_option("--periods", "a:b:c", "FROM:TO:N"); }
TEST(SpectrumRejects, PeriodsTwoFields) { expect_rejected_option("--periods", "0.1:4", "FROM:TO:N"); }
TEST(SpectrumRejects, PeriodsFourFields) { expect_rejected_option("--periods", "0.1:4:10:2", "FROM:TO:N"); }
TEST(SpectrumRejects, PeriodsInfinite) { expect_rejected_option("--periods", "0.1:inf:10", "FROM:TO:N"); }
TEST(SpectrumRejects, TargetWithoutPga) {
  expect_rejected({"--record", kElCentro180, "--target", "ec8-1A"}, {"--target", "--pga"});
}
TEST(SpectrumRejects, PgaWithoutTarget) { expect_rejected_option("--pga", "0.2", "--target"); }
TEST(SpectrumRejects, PgaZero) {
  expect_rejected({"--record", kElCentro180, "--target", "ec8-1A", "--pga", "0"}, {"--pga", "> 0"});
}
TEST(SpectrumRejects, PgaNegative) {
  expect_rejected({"--record", kElCentro180, "--target", "ec8-1A", "--pga", "-0.2"}, {"--pga", "> 0"});
}
TEST(SpectrumRejects, UnknownTarget) {
  expect_rejected({"--record", kElCentro180, "--target", "ec8-3B", "--pga", "0.2"}, {"--target", "'ec8-3B'"});
}
TEST(SpectrumRejects, CustomWithoutParameters) {
  expect_rejected({"--record", kElCentro180, "--target", "custom", "--pga", "0.2"},
                  {"--target custom", "--p, --tb, --tc, --td"});
}
TEST(SpectrumRejects, CustomMissingOneParameter) {
  expect_rejected(
      {"--record", kElCentro180, "--target", "custom", "--pga", "0.2", "--p", "2.5", "--tb", "0.1", "--tc", "0.4"},
      {"missing --td"});
}
TEST(SpectrumRejects, CustomPlateauBelowOne) {
  expect_rejected({"--record", kElCentro180, "--target", "custom", "--pga", "0.2", "--p", "0.5", "--tb", "0.1", "--tc",
                   "0.4", "--td", "2"},
                  {"--p", ">= 1"});
}
TEST(SpectrumRejects, CustomCornersOutOfOrder) {
  expect_rejected({"--record", kElCentro180, "--target", "custom", "--pga", "0.2", "--p", "2.5", "--tb", "0.5", "--tc",
                   "0.4", "--td", "2"},
                  {"--tc", "--tb"});
  expect_rejected({"--record", kElCentro180, "--target", "custom", "--pga", "0.2", "--p", "2.5", "--tb", "0.1", "--tc",
                   "0.4", "--td", "0.3"},
                  {"--td", "--tc"});
}
TEST(SpectrumRejects, CustomParameterWithANamedTarget) {
  expect_rejected({"--record", kElCentro180, "--target", "ec8-1A", "--pga", "0.2", "--tb", "0.1"},
                  {"--target custom only"});
}
TEST(SpectrumRejects, CustomParameterWithoutTarget) { expect_rejected_option("--tc", "0.5", "--target custom"); }
TEST(SpectrumRejects, GravityNotPositive) { expect_rejected_option("--g", "0", "> 0"); }
TEST(SpectrumRejects, DtNotPositive) { expect_rejected_option("--dt", "0", "> 0"); }
TEST(SpectrumRejects, UnknownUnits) { expect_rejected_option("--units", "furlongs", "g, mps2, cmps2 or mmps2"); }

TEST(SpectrumRejects, BadRecordFiles) {
  TempDir dir;
  const std::string missing = dir.file("no_such_record.AT2");
  expect_rejected({"--record", missing}, {missing, "does not exist"});
  const std::string bad = dir.file("bad.txt");
  rockwatch::test::write_text(bad, "# units: g\n0.00 0.1\n0.01 zero\n");
  expect_rejected({"--record", bad}, {bad + ":3"});
  const std::string no_units = dir.file("no_units.txt");
  rockwatch::test::write_text(no_units, "0.00 0.1\n0.01 0.2\n0.02 -0.1\n");
  expect_rejected({"--record", no_units}, {no_units, "--units"});
  const std::string one_column = dir.file("one_column.txt");
  rockwatch::test::write_text(one_column, "# units: g\n0.1\n0.2\n-0.1\n");
  expect_rejected({"--record", one_column}, {one_column, "--dt"});
}

TEST(SpectrumRejects, OutputFiles) {
  TempDir dir;
  const std::string out = dir.file("no_such_dir/spectrum.csv");
  expect_rejected({"--record", kElCentro180, "--out", out}, {"--out", out});
  CHECK_FALSE(std::filesystem::exists(out));
  const std::string copy = dir.file("copy.AT2");
  std::filesystem::copy_file(kElCentro180, copy);
  const auto size = std::filesystem::file_size(copy);
  expect_rejected({"--record", copy, "--out", copy}, {"--out"});
  expect_rejected({"--record", copy, "--plot", copy}, {"--plot"});
  CHECK_EQUAL(size, std::filesystem::file_size(copy));
  expect_rejected({"--record", kElCentro180, "--out", "", "--json"}, {"--out"});
}
