// `rockwatch static` end to end: real processes, values checked against SPEC §5's regression table and against
// core::run_static_check called in-process (the CLI must add nothing to core); every invalid input refused with
// exit status 2 and a message naming the option; the --sweep CSV and PNG.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "common/plots/python_plot.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/core/static_check.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::Csv;
using rockwatch::test::describe;
using rockwatch::test::ProcessResult;
using rockwatch::test::read_csv;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
using rockwatch::test::write_text;
namespace core = rockwatch::core;

namespace {

const std::vector<std::string> kJsonKeys{"T_s", "x_eq_max_m", "allowable_pga_g", "K", "X_m", "lambda", "spectrum"};

ProcessResult run_static(const std::vector<std::string>& args) {
  std::vector<std::string> full{"static"};
  full.insert(full.end(), args.begin(), args.end());
  return run_rockwatch(full);
}

nlohmann::json run_json(const std::vector<std::string>& args, std::string* err = nullptr) {
  const ProcessResult r = run_static(args);
  CHECK_EQUAL_TEXT(0, r.signal, describe(r).c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  if (err != nullptr) *err = r.err;
  return nlohmann::json::parse(r.out);
}

// Exactly the documented keys, in the documented order.
void check_keys(const nlohmann::json& object) {
  CHECK_TRUE(object.is_object());
  std::vector<std::string> keys;
  for (const auto& item : object.items()) keys.push_back(item.key());
  std::set<std::string> sorted_keys(keys.begin(), keys.end()), expected(kJsonKeys.begin(), kJsonKeys.end());
  CHECK_TRUE(sorted_keys == expected);
  CHECK_EQUAL(kJsonKeys.size(), keys.size());
}

// The JSON object of one case against core called in-process with the same inputs.
void check_against_core(const nlohmann::json& j, const core::StaticInputs& in) {
  check_keys(j);
  core::StaticResult r;
  CHECK_TRUE(core::run_static_check(in, r).ok());
  DOUBLES_EQUAL(r.period_s, j.at("T_s").get<double>(), 0.0);
  DOUBLES_EQUAL(r.x_eq_max_m, j.at("x_eq_max_m").get<double>(), 0.0);
  DOUBLES_EQUAL(r.allowable_pga_g, j.at("allowable_pga_g").get<double>(), 0.0);
  DOUBLES_EQUAL(r.k, j.at("K").get<double>(), 0.0);
  DOUBLES_EQUAL(r.x_m, j.at("X_m").get<double>(), 0.0);
  DOUBLES_EQUAL(in.lambda, j.at("lambda").get<double>(), 0.0);
  STRCMP_EQUAL(core::spectrum_name(in.spectrum.kind), j.at("spectrum").get<std::string>().c_str());
}

core::StaticInputs paper(double lambda) {
  core::StaticInputs in = core::paper_static_inputs();
  in.lambda = lambda;
  return in;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_GROUP(StaticCommand){};

TEST(StaticCommand, DefaultJsonIsBothCodesWithTheSpecValues) {
  std::string err;
  const nlohmann::json j = run_json({"--json"}, &err);
  CHECK_TRUE(j.is_array());
  CHECK_EQUAL(2u, j.size());
  // ntc2008 first, then nzsee2016 (SPEC §5 table, six decimals).
  DOUBLES_EQUAL(0.579102, j[0].at("T_s").get<double>(), 1e-6);
  DOUBLES_EQUAL(0.138984, j[0].at("allowable_pga_g").get<double>(), 1e-6);
  DOUBLES_EQUAL(0.4, j[0].at("lambda").get<double>(), 0.0);
  DOUBLES_EQUAL(0.995166, j[1].at("T_s").get<double>(), 1e-6);
  DOUBLES_EQUAL(0.180193, j[1].at("allowable_pga_g").get<double>(), 1e-6);
  DOUBLES_EQUAL(0.6, j[1].at("lambda").get<double>(), 0.0);
  check_against_core(j[0], paper(0.4));
  check_against_core(j[1], paper(0.6));
  STRCMP_EQUAL("npr9998-2015", j[0].at("spectrum").get<std::string>().c_str());
  // The label goes to stderr as a note, never into the JSON.
  STRCMP_CONTAINS("note: ", err.c_str());
  STRCMP_CONTAINS("back-calculated", err.c_str());
  CHECK_TRUE(err.find("virtual work") == std::string::npos);
}

TEST(StaticCommand, BothIsTheDefault) {
  const ProcessResult implicit = run_static({"--json"});
  const ProcessResult explicit_both = run_static({"--code", "both", "--json"});
  CHECK_EQUAL_TEXT(0, explicit_both.exit_status, describe(explicit_both).c_str());
  STRCMP_EQUAL(implicit.out.c_str(), explicit_both.out.c_str());
}

TEST(StaticCommand, OneCodeIsOneObjectWithExactlyTheDocumentedKeys) {
  const nlohmann::json ntc = run_json({"--code", "ntc2008", "--json"});
  check_keys(ntc);
  // nlohmann::json sorts the keys it parses: the documented order is checked on the printed text.
  const ProcessResult raw = run_static({"--code", "ntc2008", "--json"});
  std::size_t at = 0;
  for (const std::string& key : kJsonKeys) {
    const std::size_t found = raw.out.find("\"" + key + "\"", at);
    CHECK_TEXT(found != std::string::npos, key.c_str());
    at = found;
  }
  check_against_core(ntc, paper(0.4));
  const nlohmann::json nzsee = run_json({"--code", "nzsee2016", "--json"});
  check_against_core(nzsee, paper(0.6));
}

TEST(StaticCommand, GivenLambdaAndWall) {
  // SPEC §5: h/b = 40, λ = 0.5 and h/b = 20, λ = 0.1.
  const nlohmann::json tall = run_json({"--lambda", "0.5", "--h", "4", "--b", "0.1", "--json"});
  DOUBLES_EQUAL(0.818973, tall.at("T_s").get<double>(), 1e-6);
  DOUBLES_EQUAL(0.150161, tall.at("allowable_pga_g").get<double>(), 1e-6);
  core::StaticInputs in = core::paper_static_inputs();
  core::set_total_height(in, 4.0);
  in.lambda = 0.5;
  check_against_core(tall, in);

  const nlohmann::json squat = run_json({"--h", "2", "--lambda", "0.1", "--json"});
  DOUBLES_EQUAL(0.100809, squat.at("T_s").get<double>(), 1e-6);
  DOUBLES_EQUAL(0.986013, squat.at("allowable_pga_g").get<double>(), 1e-6);

  // Blocks: only their sum matters.
  const nlohmann::json blocks = run_json({"--b", "0.1", "--h1", "1.5", "--h2", "2.5", "--lambda", "0.5", "--json"});
  DOUBLES_EQUAL(tall.at("T_s").get<double>(), blocks.at("T_s").get<double>(), 0.0);
  DOUBLES_EQUAL(tall.at("allowable_pga_g").get<double>(), blocks.at("allowable_pga_g").get<double>(), 0.0);
}

TEST(StaticCommand, HumanOutputIsATableWithTheLabels) {
  const ProcessResult r = run_static({});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  for (const char* text : {"NTC 2008", "NZSEE 2016", "lambda", "K [-]", "X [m]", "T [s]", "x_eq,max", "Se(T) [m/s2]",
                           "Sd(T) [m]", "allowable PGA [g]", "allowable PGA [m/s2]", "0.579102", "0.995166",
                           "0.138984", "0.180193", "back-calculated", "npr9998-2015", "simple case"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
  CHECK_TRUE(r.out.find("virtual work") == std::string::npos);
  CHECK_TRUE(r.err.empty());
}

TEST(StaticCommand, GeneralCaseIsLabelledDerivedByVirtualWork) {
  const std::vector<std::string> args{"--fp", "2000", "--a", "0.5", "--psi", "0.01", "--code", "ntc2008"};
  const ProcessResult human = run_static(args);
  CHECK_EQUAL_TEXT(0, human.exit_status, describe(human).c_str());
  STRCMP_CONTAINS("derived by virtual work", human.out.c_str());
  STRCMP_CONTAINS("0.151381", human.out.c_str());  // by hand in tests/core/test_static_check.cpp

  std::vector<std::string> json_args = args;
  json_args.emplace_back("--json");
  std::string err;
  const nlohmann::json j = run_json(json_args, &err);
  STRCMP_CONTAINS("derived by virtual work", err.c_str());
  STRCMP_CONTAINS("back-calculated", err.c_str());
  core::StaticInputs in = paper(0.4);
  in.fp_npm = 2000.0;
  in.a = 0.5;
  in.psi_rad = 0.01;
  check_against_core(j, in);
  DOUBLES_EQUAL(0.1513807733794034, j.at("allowable_pga_g").get<double>(), 1e-13);
}

TEST(StaticCommand, EccentricityWithoutOverburdenChangesNothingAndSaysSo) {
  std::string err;
  const nlohmann::json j = run_json({"--a", "0.7", "--code", "ntc2008", "--json"}, &err);
  check_against_core(j, paper(0.4));
  STRCMP_CONTAINS("--a has no effect without --fp", err.c_str());
  CHECK_TRUE(err.find("virtual work") == std::string::npos);
}

TEST(StaticCommand, CustomSpectrum) {
  const nlohmann::json j =
      run_json({"--spectrum", "custom", "--p", "3", "--tb", "0.1", "--tc", "0.3", "--td", "0.5", "--code", "ntc2008",
                "--json"});
  core::StaticInputs in = paper(0.4);
  in.spectrum = core::spectrum_custom(3.0, 0.1, 0.3, 0.5);
  check_against_core(j, in);
  STRCMP_EQUAL("custom", j.at("spectrum").get<std::string>().c_str());

  const ProcessResult human =
      run_static({"--spectrum", "custom", "--p", "3", "--tb", "0.1", "--tc", "0.3", "--td", "0.5"});
  CHECK_EQUAL_TEXT(0, human.exit_status, describe(human).c_str());
  STRCMP_CONTAINS("user-supplied", human.out.c_str());
  CHECK_TRUE(human.out.find("back-calculated") == std::string::npos);
}

TEST(StaticCommand, EurocodeSpectra) {
  for (const char* name : {"ec8-1A", "ec8-2A"}) {
    const nlohmann::json j = run_json({"--spectrum", name, "--json"});
    core::StaticInputs in = paper(0.4);
    CHECK_TRUE(core::parse_spectrum_name(name, in.spectrum));
    check_against_core(j[0], in);
    in.lambda = 0.6;
    check_against_core(j[1], in);
  }
}

TEST(StaticCommand, HelpDocumentsOptionsAndJson) {
  const ProcessResult r = run_static({"--help"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  for (const char* text : {"--wall", "--h", "--b", "--h1", "--h2", "--fp", "--a", "--psi", "--rho", "--g", "--lambda",
                           "--code", "--spectrum", "--p", "--tb", "--tc", "--td", "--json", "--sweep", "--out",
                           "array of two", "back-calculated", "derived by virtual work"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
  const ProcessResult top = run_rockwatch({"--help"});
  STRCMP_CONTAINS("static", top.out.c_str());
}

TEST_GROUP(StaticRejects){};

namespace {

void expect_rejected(const std::vector<std::string>& args, const std::vector<std::string>& mentions) {
  rockwatch::test::expect_command_rejected("static", args, mentions);
}

}  // namespace

TEST(StaticRejects, LambdaOutsideTheOpenUnitInterval) {
  expect_rejected({"--lambda", "1"}, {"--lambda", "(0, 1)", "got 1"});
  expect_rejected({"--lambda", "0"}, {"--lambda", "(0, 1)"});
  expect_rejected({"--lambda", "-0.2"}, {"--lambda", "(0, 1)"});
  expect_rejected({"--lambda", "1.5"}, {"--lambda", "(0, 1)"});
  expect_rejected({"--lambda", "nan"}, {"--lambda", "finite"});
  expect_rejected({"--lambda", "0.4x"}, {"--lambda", "'0.4x'"});
}

TEST(StaticRejects, LambdaWithCode) {
  expect_rejected({"--lambda", "0.5", "--code", "ntc2008"}, {"--lambda", "--code"});
}
TEST(StaticRejects, UnknownCode) { expect_rejected({"--code", "ec8"}, {"--code", "ntc2008", "nzsee2016", "'ec8'"}); }

TEST(StaticRejects, HeightNotAboveThickness) {
  expect_rejected({"--h", "0.1", "--b", "0.1"}, {"--h must be greater than b", "got 0.1"});
  expect_rejected({"--h", "0.05"}, {"--h must be greater than b"});
  expect_rejected({"--h1", "0.05"}, {"--h1 must be greater than b (got 0.05)"});
  expect_rejected({"--h2", "0.1"}, {"--h2 must be greater than b"});
  expect_rejected({"--b", "2"}, {"--h1 must be greater than b", "the paper wall's value", "--b 2"});
}

TEST(StaticRejects, HeightGivenTwoWays) {
  expect_rejected({"--h", "3", "--h1", "1.5"}, {"--h", "--h1"});
  expect_rejected({"--h", "3", "--h2", "1.5"}, {"--h", "--h2"});
}

TEST(StaticRejects, WallValues) {
  expect_rejected({"--b", "0"}, {"--b", "> 0"});
  expect_rejected({"--b", "abc"}, {"--b", "'abc'"});
  expect_rejected({"--fp", "-5"}, {"--fp", ">= 0", "got -5"});
  expect_rejected({"--a", "1.5"}, {"--a", "[0, 1]"});
  expect_rejected({"--a", "-0.1"}, {"--a", "[0, 1]"});
  expect_rejected({"--rho", "0"}, {"--rho", "> 0"});
  expect_rejected({"--g", "0"}, {"--g", "> 0"});
  expect_rejected({"--g", "inf"}, {"--g", "finite"});
  expect_rejected({"--psi", "0.2"}, {"--psi", "K > 0", "0.114285714"});
  expect_rejected({"--wall", "brick"}, {"--wall", "paper"});
  expect_rejected({"--b", "1e300", "--h", "1e305"}, {"too extreme", "--b", "--h"});
}

TEST(StaticRejects, SpectrumName) {
  expect_rejected({"--spectrum", "npr9998"}, {"--spectrum", "npr9998-2015, ec8-1A, ec8-2A or custom", "'npr9998'"});
  expect_rejected({"--spectrum", "vertical-default"}, {"--spectrum", "vertical"});
}

TEST(StaticRejects, CustomSpectrumParameters) {
  expect_rejected({"--spectrum", "custom"}, {"--spectrum custom needs", "--p", "--tb", "--tc", "--td"});
  expect_rejected({"--spectrum", "custom", "--p", "2.5", "--tb", "0.1", "--tc", "0.3"}, {"missing --td"});
  expect_rejected({"--spectrum", "custom", "--p", "2.5", "--tb", "0.4", "--tc", "0.3", "--td", "0.67"},
                  {"--tc must be greater than --tb", "TB < TC < TD"});
  expect_rejected({"--spectrum", "custom", "--p", "2.5", "--tb", "0.1", "--tc", "0.3", "--td", "0.3"},
                  {"--td must be greater than --tc"});
  expect_rejected({"--spectrum", "custom", "--p", "0.5", "--tb", "0.1", "--tc", "0.3", "--td", "0.6"},
                  {"--p must be >= 1"});
  expect_rejected({"--spectrum", "custom", "--p", "2.5", "--tb", "0", "--tc", "0.3", "--td", "0.6"},
                  {"--tb must be > 0"});
  expect_rejected({"--spectrum", "custom", "--p", "2.5", "--tb", "0.1", "--tc", "nan", "--td", "0.6"},
                  {"--tc", "finite"});
}

TEST(StaticRejects, CustomParametersWithoutCustomSpectrum) {
  expect_rejected({"--p", "2.5"}, {"--p", "--spectrum custom"});
  expect_rejected({"--spectrum", "ec8-1A", "--td", "1.5"}, {"--td", "--spectrum custom", "'ec8-1A'"});
}

TEST(StaticRejects, CommandLineShape) {
  expect_rejected({"--frobnicate"}, {"unknown option '--frobnicate'"});
  expect_rejected({"extra"}, {"unexpected argument 'extra'"});
  expect_rejected({"--lambda", "0.4", "--lambda", "0.6"}, {"--lambda"});
  expect_rejected({"--lambda"}, {"--lambda"});
}

TEST(StaticRejects, SweepCombinations) {
  const TempDir dir;
  const std::string out = dir.file("sweep");
  expect_rejected({"--sweep"}, {"--sweep needs --out"});
  expect_rejected({"--out", out}, {"--out", "--sweep"});
  expect_rejected({"--sweep", "--out", out, "--json"}, {"--json", "--sweep"});
  expect_rejected({"--sweep", "--out", out, "--lambda", "0.5"}, {"--lambda", "--sweep"});
  expect_rejected({"--sweep", "--out", out, "--code", "ntc2008"}, {"--code", "--sweep"});
  expect_rejected({"--sweep", "--out", out, "--h", "3"}, {"--h", "--sweep"});
  // ψ = 0.2 > 4b/h for every slenderness of the sweep.
  expect_rejected({"--sweep", "--out", out, "--psi", "0.2"}, {"--psi", "K > 0", "in the sweep at h/b = 20"});
  expect_rejected({"--sweep", "--out", out, "--spectrum", "custom"}, {"--spectrum custom needs"});
  CHECK_FALSE(std::filesystem::exists(out));  // nothing written on a refusal

  const std::string file = dir.file("a_file");
  write_text(file, "not a directory\n");
  expect_rejected({"--sweep", "--out", file}, {"--out", "not a directory"});
}

TEST_GROUP(StaticSweep){};

TEST(StaticSweep, WritesTheCsvAndThePng) {
  const TempDir dir;
  const std::string out = dir.file("figures/figure3");  // parents created too
  const ProcessResult r = run_static({"--sweep", "--out", out});
  const std::optional<std::string> python = rockwatch::cli::find_matplotlib_python();
  const std::string csv_path = out + "/static_sweep.csv", png_path = out + "/static_sweep.png";

  // The CSV is written whether or not a plot can be made.
  const Csv csv = read_csv(csv_path);
  STRCMP_EQUAL("h_over_b,h_m,lambda,T_s,x_eq_max_m,allowable_pga_g", csv.header.c_str());
  CHECK_EQUAL(5u * 81u, csv.rows.size());
  std::set<double> slenderness, lambdas;
  for (const std::vector<double>& row : csv.rows) {
    CHECK_EQUAL(6u, row.size());
    slenderness.insert(row[0]);
    lambdas.insert(row[2]);
    core::StaticInputs in = core::paper_static_inputs();
    core::set_total_height(in, row[1]);
    in.lambda = row[2];
    core::StaticResult expected;
    CHECK_TRUE(core::run_static_check(in, expected).ok());
    DOUBLES_EQUAL(row[0] * 0.1, row[1], 1e-15);
    DOUBLES_EQUAL(expected.period_s, row[3], 0.0);
    DOUBLES_EQUAL(expected.x_eq_max_m, row[4], 0.0);
    DOUBLES_EQUAL(expected.allowable_pga_g, row[5], 0.0);
  }
  CHECK_TRUE((slenderness == std::set<double>{20.0, 25.0, 30.0, 35.0, 40.0}));
  CHECK_EQUAL(81u, lambdas.size());
  DOUBLES_EQUAL(0.1, *lambdas.begin(), 0.0);
  DOUBLES_EQUAL(0.9, *lambdas.rbegin(), 0.0);
  // SPEC §5's rows, found in the table.
  struct Point {
    double h_over_b, lambda, period_s, pga_g;
  };
  for (const Point& p : {Point{35, 0.4, 0.579102, 0.138984}, Point{35, 0.6, 0.995166, 0.180193},
                         Point{20, 0.1, 0.100809, 0.986013}, Point{40, 0.5, 0.818973, 0.150161}}) {
    bool found = false;
    for (const std::vector<double>& row : csv.rows) {
      if (row[0] != p.h_over_b || std::fabs(row[2] - p.lambda) > 1e-12) continue;
      found = true;
      DOUBLES_EQUAL(p.period_s, row[3], 1e-6);
      DOUBLES_EQUAL(p.pga_g, row[5], 1e-6);
    }
    CHECK_TRUE(found);
  }

  if (!python) {
    // Only a machine without any Python that has matplotlib may get here (Debian: python3-matplotlib).
    std::printf("\nnote: no Python with matplotlib: the PNG half of StaticSweep was not checked\n");
    CHECK_EQUAL_TEXT(1, r.exit_status, describe(r).c_str());
    STRCMP_CONTAINS("rockwatch static: error: plot not written", r.err.c_str());
    return;
  }
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  STRCMP_CONTAINS("back-calculated", r.out.c_str());
  STRCMP_CONTAINS(csv_path.c_str(), r.out.c_str());
  STRCMP_CONTAINS(png_path.c_str(), r.out.c_str());
  const std::string png = slurp(png_path);
  CHECK_TEXT(png.size() > 10 * 1024, ("PNG of " + std::to_string(png.size()) + " bytes").c_str());
  CHECK_TRUE(png.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)) == 0);
}

TEST(StaticSweep, RunsAgainIntoAnExistingDirectoryWithAnotherSpectrum) {
  const TempDir dir;
  for (const char* spectrum : {"npr9998-2015", "ec8-1A"}) {
    const ProcessResult r = run_static({"--sweep", "--out", dir.path(), "--spectrum", spectrum});
    if (!rockwatch::cli::find_matplotlib_python()) {
      CHECK_EQUAL_TEXT(1, r.exit_status, describe(r).c_str());
      continue;
    }
    CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  }
  const Csv csv = read_csv(dir.file("static_sweep.csv"));
  CHECK_EQUAL(405u, csv.rows.size());
  core::StaticInputs in = core::paper_static_inputs();
  in.spectrum = core::spectrum_ec8_1A();
  core::set_total_height(in, csv.rows.back()[1]);
  in.lambda = csv.rows.back()[2];
  core::StaticResult expected;
  CHECK_TRUE(core::run_static_check(in, expected).ok());
  DOUBLES_EQUAL(expected.allowable_pga_g, csv.rows.back()[5], 0.0);
}
