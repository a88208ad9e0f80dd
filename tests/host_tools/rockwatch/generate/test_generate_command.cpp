// `rockwatch generate` end to end: one one-set suite written into a temporary directory and checked against itself
// (the manifest's measures recomputed from the set file read back, the CSV and the --json output equal to the
// manifest, the plots when matplotlib is there, the suite usable by simulate), the refusal to overwrite a suite and
// the complete replacement of an old one with --force, and
// every invalid option value (exit 2, a message naming the option, nothing written). One generation only: it is
// the slow part.
#include <cmath>
#include <cstddef>
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
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
namespace records = rockwatch::records;
namespace sim = rockwatch::sim;
namespace synthesis = rockwatch::sim::synthesis;
namespace fs = std::filesystem;

namespace {

const char* const kComponents[] = {"X", "Y", "Z"};
const char* const kPlots[] = {"spectra_horizontal.png", "spectra_vertical.png", "spectra_X.png", "spectra_Y.png",
                              "spectra_Z.png"};
const std::set<std::string> kComponentKeys{
    "seed",      "pga_mps2",          "pga_g",           "pgv_mps",     "pgd_m",  "d5_75_s",   "d5_95_s",
    "arias_mps", "spectral_ratio_min", "spectral_ratio_max", "spectrum_accepted", "durations_accepted", "accepted",
    "attempts",  "final_velocity_mps", "final_displacement_m"};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::set<std::string> keys_of(const nlohmann::json& j) {
  std::set<std::string> keys;
  for (const auto& item : j.items()) keys.insert(item.key());
  return keys;
}

// Values written with 10 significant digits, measured again: equal to about 1e-8 relative.
void check_close(double expected, const nlohmann::json& actual, double scale, const std::string& what) {
  CHECK_TEXT(actual.is_number(), what.c_str());
  DOUBLES_EQUAL_TEXT(expected, actual.get<double>(), 1e-7 * std::fmax(scale, std::fabs(expected)), what.c_str());
}

void check_files(const std::string& dir, bool plotted) {
  for (const char* name : {"set01.txt", "manifest.json", "manifest.csv"}) {
    CHECK_TEXT(fs::file_size(dir + "/" + name) > 100, name);
  }
  for (const char* name : kPlots) {
    if (plotted) {
      CHECK_TEXT(fs::file_size(dir + "/" + name) > 10 * 1024, name);
    } else {
      CHECK_TEXT(!fs::exists(dir + "/" + name), name);
    }
  }
  CHECK_FALSE(fs::exists(dir + "/set02.txt"));  // of the old suite
}

void check_manifest_keys(const nlohmann::json& m, const std::string& dir) {
  STRCMP_EQUAL(records::kSuiteManifestFormat, m["format"].get<std::string>().c_str());
  CHECK_EQUAL(1, m["version"].get<int>());
  STRCMP_EQUAL("npr9998-2015", m["suite"].get<std::string>().c_str());
  const std::string command = m["command"].get<std::string>();
  STRCMP_CONTAINS(("rockwatch generate --out " + dir + " --sets 1 --seed 9998 --target npr9998-2015").c_str(),
                  command.c_str());
  STRCMP_CONTAINS("--pga 0.2 --vertical-ratio 1 --dt 0.005 --duration 20 --iterations", command.c_str());
  const nlohmann::json& s = m["settings"];
  for (const char* key : {"dt_s", "duration_s", "pga_g", "seed", "horizontal_target", "vertical_target",
                          "check_from_s", "check_to_s", "accept_min", "accept_max", "suite_mean_tolerance"}) {
    CHECK_TEXT(s.contains(key), key);
  }
  DOUBLES_EQUAL(0.005, s["dt_s"].get<double>(), 0.0);
  CHECK_EQUAL(9998u, s["seed"].get<unsigned long long>());
  STRCMP_CONTAINS("back-calculated", s["horizontal_target"]["provenance"].get<std::string>().c_str());
  DOUBLES_EQUAL(3.0, s["vertical_target"]["p"].get<double>(), 0.0);
  LONGS_EQUAL(1, m["sets"].size());
  CHECK_EQUAL(1, m["sets"][0]["set"].get<int>());
  STRCMP_EQUAL("set01.txt", m["sets"][0]["file"].get<std::string>().c_str());
  for (const char* c : kComponents) CHECK_TEXT(keys_of(m["sets"][0]["components"][c]) == kComponentKeys, c);
  for (const char* direction : {"horizontal", "vertical"}) {
    CHECK_TEXT(keys_of(m["suite_mean"][direction]) == (std::set<std::string>{"ratio_min", "ratio_max", "accepted"}),
               direction);
  }
}

// The manifest says what the set file holds: every measure again from the file as read back.
void check_manifest_against_set_file(const nlohmann::json& m, const std::string& dir) {
  const records::SuiteRecordFile file = records::read_suite_record(dir + "/set01.txt");
  STRCMP_EQUAL("npr9998-2015", file.suite.c_str());
  CHECK_EQUAL(1, file.set);
  CHECK_EQUAL(9998u, file.seed);
  DOUBLES_EQUAL(0.005, file.dt_s, 0.0);
  DOUBLES_EQUAL(0.2 * kG, file.ag_mps2, 1e-12);
  DOUBLES_EQUAL(0.2 * kG, file.avg_mps2, 1e-12);
  CHECK_TRUE(file.generator.rfind("rockwatch ", 0) == 0);
  STRCMP_CONTAINS("generate --sets 1 --seed 9998", file.generator.c_str());
  CHECK_TRUE(file.generator.find("--out") == std::string::npos);  // the same settings give the same files

  const synthesis::GeneratorSettings settings;  // the defaults the run used
  bool all_accepted = true;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string c = kComponents[i];
    const nlohmann::json& j = m["sets"][0]["components"][c];
    const std::vector<double>& a = file.components_mps2[i];
    LONGS_EQUAL(4001, a.size());
    const sim::IntensityMeasures im = sim::intensity_measures(a, file.dt_s, kG);
    check_close(im.pga_mps2, j["pga_mps2"], 1.0, c + " pga_mps2");
    check_close(0.2 * kG, j["pga_mps2"], 1.0, c + " pga anchored to a_g");
    check_close(im.pga_mps2 / kG, j["pga_g"], 0.1, c + " pga_g");
    check_close(im.pgv_mps, j["pgv_mps"], 0.01, c + " pgv_mps");
    check_close(im.pgd_m, j["pgd_m"], 0.001, c + " pgd_m");
    check_close(im.arias_mps, j["arias_mps"], 0.01, c + " arias_mps");
    check_close(*im.d5_75_s, j["d5_75_s"], 1.0, c + " d5_75_s");
    check_close(*im.d5_95_s, j["d5_95_s"], 1.0, c + " d5_95_s");
    const synthesis::BandRatio ratio = synthesis::spectral_ratio(
        a, file.dt_s, i == 2 ? settings.vertical_target : settings.horizontal_target, 0.2 * kG, settings.check_from_s,
        settings.check_to_s, settings.check_periods, settings.damping);
    check_close(ratio.min, j["spectral_ratio_min"], 1.0, c + " spectral_ratio_min");
    check_close(ratio.max, j["spectral_ratio_max"], 1.0, c + " spectral_ratio_max");
    const bool spectrum_ok = ratio.min >= settings.accept_min && ratio.max <= settings.accept_max;
    CHECK_EQUAL_TEXT(spectrum_ok, j["spectrum_accepted"].get<bool>(), c.c_str());
    CHECK_EQUAL_TEXT(j["spectrum_accepted"].get<bool>() && j["durations_accepted"].get<bool>(),
                     j["accepted"].get<bool>(), c.c_str());
    all_accepted = all_accepted && j["accepted"].get<bool>();
    CHECK_TEXT(std::fabs(j["final_velocity_mps"].get<double>()) < 1e-9, c.c_str());
    CHECK_TEXT(std::fabs(j["final_displacement_m"].get<double>()) < 1e-9, c.c_str());
    CHECK_EQUAL_TEXT(synthesis::component_seed(9998, 1, static_cast<synthesis::Component>(i)),
                     j["seed"].get<unsigned long long>(), c.c_str());
  }
  const bool suite_accepted =
      all_accepted && m["suite_mean"]["horizontal"]["accepted"].get<bool>() && m["suite_mean"]["vertical"]["accepted"].get<bool>();
  CHECK_EQUAL(suite_accepted, m["accepted"].get<bool>());
}

void check_csv(const nlohmann::json& m, const std::string& dir) {
  std::ifstream in(dir + "/manifest.csv");
  std::string header;
  std::getline(in, header);
  STRCMP_EQUAL("set,component,seed,pga_mps2,pga_g,pgv_mps,pgd_m,d5_75_s,d5_95_s,arias_mps,spectral_ratio_min,"
               "spectral_ratio_max,spectrum_accepted,durations_accepted,accepted,attempts,final_velocity_mps,"
               "final_displacement_m",
               header.c_str());
  std::vector<std::string> rows;
  for (std::string row; std::getline(in, row);) rows.push_back(row);
  LONGS_EQUAL(3, rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const nlohmann::json& j = m["sets"][0]["components"][kComponents[i]];
    std::vector<std::string> fields;
    std::string field;
    for (std::size_t start = 0;;) {
      const std::size_t comma = rows[i].find(',', start);
      fields.push_back(rows[i].substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    LONGS_EQUAL(18, fields.size());
    STRCMP_EQUAL("1", fields[0].c_str());
    STRCMP_EQUAL(kComponents[i], fields[1].c_str());
    STRCMP_EQUAL(std::to_string(j["seed"].get<unsigned long long>()).c_str(), fields[2].c_str());
    DOUBLES_EQUAL(j["pga_mps2"].get<double>(), std::stod(fields[3]), 0.0);
    DOUBLES_EQUAL(j["d5_95_s"].get<double>(), std::stod(fields[8]), 0.0);
    DOUBLES_EQUAL(j["spectral_ratio_max"].get<double>(), std::stod(fields[11]), 0.0);
    STRCMP_EQUAL(j["accepted"].get<bool>() ? "true" : "false", fields[14].c_str());
  }
}

}  // namespace

TEST_GROUP(GenerateCommand){};

// One generation, checked from every side (a TEST per check would generate the suite again for each).
TEST(GenerateCommand, OneSetSuiteIsWrittenConsistentAndUsable) {
  const TempDir tmp;
  const std::string dir = tmp.file("suite");
  // An older two-set suite is there: refused without --force, replaced completely with it.
  fs::create_directory(dir);
  rockwatch::test::write_text(dir + "/manifest.json", R"({"format": "rockwatch-suite-manifest", "version": 1,)"
                                                      R"( "sets": [{"set": 1, "file": "set01.txt"},)"
                                                      R"( {"set": 2, "file": "set02.txt"}]})");
  for (const char* old : {"set01.txt", "set02.txt", "spectra_X.png"}) rockwatch::test::write_text(dir + "/" + old, "old");
  rockwatch::test::expect_command_rejected("generate", {"--out", dir, "--sets", "1"},
                                           {dir + "/manifest.json", "already holds a suite", "--force"});
  STRCMP_EQUAL("old", slurp(dir + "/set02.txt").c_str());

  const bool plot = rockwatch::cli::find_matplotlib_python().has_value();
  if (!plot) std::printf("\nnote: no Python with matplotlib on this machine: generate runs with --no-plots\n");
  std::vector<std::string> args{"generate", "--out", dir, "--sets", "1", "--duration", "20", "--json", "--force"};
  if (!plot) args.emplace_back("--no-plots");
  const ProcessResult r = run_rockwatch(args);
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());

  const nlohmann::json manifest = nlohmann::json::parse(slurp(dir + "/manifest.json"));
  // Exit 0 exactly when the whole suite is accepted; otherwise 1, with the failures listed.
  const bool accepted = manifest["accepted"].get<bool>();
  CHECK_EQUAL_TEXT(accepted ? 0 : 1, r.exit_status, what.c_str());
  if (!accepted) STRCMP_CONTAINS("rockwatch generate: error: the suite is not accepted", r.err.c_str());
  STRCMP_CONTAINS("set 1/1", r.err.c_str());  // progress, one line per set when stderr is not a terminal
  CHECK_TEXT(nlohmann::json::parse(r.out) == manifest, what.c_str());  // --json prints the manifest

  check_files(dir, plot);
  check_manifest_keys(manifest, dir);
  check_manifest_against_set_file(manifest, dir);
  check_csv(manifest, dir);

  // The suite runs through the other tools.
  const ProcessResult simulate = run_rockwatch(
      {"simulate", "--suite", dir, "--set", "1", "--component", "Y", "--vertical-from-suite", "--json"});
  CHECK_EQUAL_TEXT(0, simulate.exit_status, describe(simulate).c_str());
  DOUBLES_EQUAL(0.2 * kG, nlohmann::json::parse(simulate.out)["pga_mps2"].get<double>(), 1e-8);

  // A run into the new suite's directory is refused before any work, and leaves the suite as it was.
  const std::string before = slurp(dir + "/manifest.json");
  rockwatch::test::expect_command_rejected("generate", {"--out", dir, "--sets", "1"}, {"manifest.json", "--force"});
  STRCMP_EQUAL(before.c_str(), slurp(dir + "/manifest.json").c_str());
}

TEST(GenerateCommand, HelpListsTheOptionsAndTheFiles) {
  const ProcessResult r = run_rockwatch({"generate", "--help"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  for (const char* text : {"--out", "--sets", "--seed", "--target", "--vertical-target", "--pga", "--vertical-ratio",
                           "--dt", "--duration", "--iterations", "--no-plots", "--json", "--force", "custom:P,TB,TC,TD",
                           "manifest.json", "manifest.csv", "spectra_horizontal.png", "BACK-CALCULATED",
                           "(default 11)", "(default 9998)"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
  const ProcessResult top = run_rockwatch({"--help"});
  STRCMP_CONTAINS("generate", top.out.c_str());
}

namespace {

// Every rejection names the option, and nothing is written: the directory is not even created.
void expect_rejected(const std::vector<std::string>& options, const std::vector<std::string>& mentions) {
  const TempDir tmp;
  const std::string dir = tmp.file("suite");
  std::vector<std::string> args{"--out", dir};
  args.insert(args.end(), options.begin(), options.end());
  rockwatch::test::expect_command_rejected("generate", args, mentions);
  CHECK_TEXT(!fs::exists(dir), dir.c_str());
}

}  // namespace

TEST_GROUP(GenerateRejects){};

TEST(GenerateRejects, MissingOut) { rockwatch::test::expect_command_rejected("generate", {"--sets", "1"}, {"--out"}); }
TEST(GenerateRejects, OutIsAFile) {
  const TempDir tmp;
  rockwatch::test::write_text(tmp.file("file"), "x");
  rockwatch::test::expect_command_rejected("generate", {"--out", tmp.file("file")}, {"--out", "not a directory"});
}
TEST(GenerateRejects, UnknownOption) { expect_rejected({"--frobnicate"}, {"--frobnicate"}); }
TEST(GenerateRejects, SetsZero) { expect_rejected({"--sets", "0"}, {"--sets", "whole number from 1 to 100", "'0'"}); }
TEST(GenerateRejects, SetsTooMany) { expect_rejected({"--sets", "101"}, {"--sets", "'101'"}); }
TEST(GenerateRejects, SetsNotWhole) { expect_rejected({"--sets", "1.5"}, {"--sets", "'1.5'"}); }
TEST(GenerateRejects, SeedNegative) { expect_rejected({"--seed", "-1"}, {"--seed", "2^64-1", "'-1'"}); }
TEST(GenerateRejects, SeedBeyond64Bits) { expect_rejected({"--seed", "18446744073709551616"}, {"--seed", "2^64-1"}); }
TEST(GenerateRejects, SeedNotANumber) { expect_rejected({"--seed", "abc"}, {"--seed", "'abc'"}); }
TEST(GenerateRejects, PgaNegative) { expect_rejected({"--pga", "-1"}, {"--pga", "> 0", "-1"}); }
TEST(GenerateRejects, PgaZero) { expect_rejected({"--pga", "0"}, {"--pga", "> 0"}); }
TEST(GenerateRejects, PgaNan) { expect_rejected({"--pga", "nan"}, {"--pga", "finite"}); }
TEST(GenerateRejects, VerticalRatioZero) { expect_rejected({"--vertical-ratio", "0"}, {"--vertical-ratio", "> 0"}); }
TEST(GenerateRejects, TargetBogus) {
  expect_rejected({"--target", "bogus"}, {"--target", "npr9998-2015, ec8-1A, ec8-2A", "custom:P,TB,TC,TD", "'bogus'"});
}
TEST(GenerateRejects, VerticalTargetBogus) { expect_rejected({"--vertical-target", "ec8"}, {"--vertical-target", "'ec8'"}); }
TEST(GenerateRejects, CustomWithThreeNumbers) {
  expect_rejected({"--target", "custom:2.5,0.1,0.3"}, {"--target", "four numbers", "'custom:2.5,0.1,0.3'"});
}
TEST(GenerateRejects, CustomWithFiveNumbers) { expect_rejected({"--target", "custom:2.5,0.1,0.3,0.8,1"}, {"four numbers"}); }
TEST(GenerateRejects, CustomNotNumbers) { expect_rejected({"--target", "custom:a,b,c,d"}, {"--target", "four numbers"}); }
TEST(GenerateRejects, CustomWithoutColon) { expect_rejected({"--target", "custom"}, {"--target", "custom:P,TB,TC,TD"}); }
TEST(GenerateRejects, CustomPlateauBelowOne) { expect_rejected({"--target", "custom:0.5,0.1,0.3,0.8"}, {"--target", ">= 1"}); }
TEST(GenerateRejects, CustomCornersOutOfOrder) {
  expect_rejected({"--vertical-target", "custom:2.5,0.3,0.1,0.8"}, {"--vertical-target", "TC must be greater than TB"});
}
TEST(GenerateRejects, DtZero) { expect_rejected({"--dt", "0"}, {"--dt", "> 0"}); }
TEST(GenerateRejects, DtNegative) { expect_rejected({"--dt", "-0.005"}, {"--dt", "> 0"}); }
TEST(GenerateRejects, DurationZero) { expect_rejected({"--duration", "0"}, {"--duration", "> 0"}); }
TEST(GenerateRejects, DurationTooShortForTheGenerator) { expect_rejected({"--duration", "2"}, {"--duration 2 s"}); }
TEST(GenerateRejects, TooManySamples) { expect_rejected({"--dt", "1e-6"}, {"--dt", "--duration", "samples"}); }
TEST(GenerateRejects, IterationsZero) { expect_rejected({"--iterations", "0"}, {"--iterations", "'0'"}); }
TEST(GenerateRejects, IterationsTooMany) { expect_rejected({"--iterations", "1001"}, {"--iterations", "1000"}); }
TEST(GenerateRejects, OptionGivenTwice) { expect_rejected({"--sets", "1", "--sets", "2"}, {"--sets"}); }
