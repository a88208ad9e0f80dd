// The record options every tool shares (host_tools/src/cli/record_selection.*): a record of a suite directory
// (--suite DIR --set N --component X|Y|Z) is the same input as its set file given as --record, the suite's Z is
// the same vertical as a third column, the reports say where the record came from, and every wrong combination is
// refused with a message naming the option (exit 2). The suite is written by hand here, so these tests do not
// depend on the generator. --channel, --vertical-channel and --gain are checked on a real miniSEED file.
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "common/records_in/align.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/response_spectrum.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::test::describe;
using rockwatch::test::kG;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
using rockwatch::test::write_text;
namespace records = rockwatch::records;
namespace sim = rockwatch::sim;

namespace {

constexpr double kPi = 3.14159265358979323846;
// NL.BGAR's InstrumentSensitivity (tests/data/records/SOURCES.md).
const char* const kBgarGain = "213867.4766";
constexpr double kDt = 0.01;
constexpr int kSamples = 301;  // 0 to 3 s

// Three distinct motions that make the paper's wall rock: X the project's G7 pulse (it collapses the wall), Y a
// weaker pulse of the other sign, Z a vertical shake of 0.3 g.
double x_mps2(double t) { return rockwatch::test::g7_ug_mps2(t); }
double y_mps2(double t) { return -0.7 * rockwatch::test::g7_ug_mps2(t); }
double z_mps2(double t) { return 0.3 * kG * std::sin(2.0 * kPi * 2.0 * t); }

// A value as the suite writer prints it (10 significant digits), so the set file and the plain file written from
// the same text hold the same doubles.
std::string value_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9e", value);
  return buffer;
}

std::string time_text(int k) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6f", k * kDt);
  return buffer;
}

// A suite directory as records/suite_format.hpp documents it: manifest.json listing set 1, and set01.txt.
class HandMadeSuite {
 public:
  HandMadeSuite() {
    write_text(dir_.file("manifest.json"),
               R"({"format": "rockwatch-suite-manifest", "version": 1, "suite": "test",)"
               R"( "sets": [{"set": 1, "file": "set01.txt"}]})");
    std::string text =
        "# rockwatch-suite-record: 1\n# suite: test\n# set: 1\n# units: m/s2\n# dt_s: 0.01\n# g_mps2: 9.81\n"
        "# ag_mps2: 1.962\n# avg_mps2: 2.943\n"
        "# horizontal_target: npr9998-2015 p=2.5 tb_s=0.15 tc_s=0.4 td_s=0.67\n"
        "# vertical_target: vertical-default p=3 tb_s=0.05 tc_s=0.15 td_s=1\n# seed: 1\n"
        "# generator: written by hand in test_record_selection.cpp\n# columns: time_s x_mps2 y_mps2 z_mps2\n";
    std::string three = "# units: mps2\n";  // the plain (time, X, Z) file
    for (int k = 0; k < kSamples; ++k) {
      const double t = k * kDt;
      text += time_text(k) + " " + value_text(x_mps2(t)) + " " + value_text(y_mps2(t)) + " " + value_text(z_mps2(t)) +
              "\n";
      three += time_text(k) + " " + value_text(x_mps2(t)) + " " + value_text(z_mps2(t)) + "\n";
    }
    write_text(set_file(), text);
    write_text(three_column_file(), three);
  }
  const std::string& dir() const { return dir_.path(); }
  std::string set_file() const { return dir_.file("set01.txt"); }
  std::string three_column_file() const { return dir_.file("x_and_z.txt"); }

 private:
  TempDir dir_;
};

nlohmann::json run_json(const std::vector<std::string>& args, std::string* err = nullptr) {
  const ProcessResult r = run_rockwatch(args);
  CHECK_EQUAL_TEXT(0, r.signal, describe(r).c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  if (err != nullptr) *err = r.err;
  return nlohmann::json::parse(r.out);
}

// The result without the keys that say where the record came from.
nlohmann::json without_selection(nlohmann::json j) {
  for (const char* key : {"suite", "component", "channel", "vertical_channel", "gain_counts_per_mps2"}) j.erase(key);
  return j;
}

}  // namespace

TEST_GROUP(RecordSelection) {
  std::unique_ptr<HandMadeSuite> suite;
  void setup() override { suite = std::make_unique<HandMadeSuite>(); }
  void teardown() override { suite.reset(); }
};

TEST(RecordSelection, SuiteRecordEqualsItsSetFileAsRecord) {
  for (const char* component : {"X", "Y", "Z"}) {
    const nlohmann::json from_suite =
        run_json({"simulate", "--suite", suite->dir(), "--set", "1", "--component", component, "--json"});
    const nlohmann::json from_file =
        run_json({"simulate", "--record", suite->set_file(), "--component", component, "--json"});
    CHECK_TEXT(without_selection(from_suite) == without_selection(from_file), component);
    STRCMP_EQUAL(component, from_file["component"].get<std::string>().c_str());
  }
  // The component is used: X (G7) collapses the wall, Y (0.7 of it, reversed) does not.
  const nlohmann::json x = run_json({"simulate", "--suite", suite->dir(), "--set", "1", "--component", "X", "--json"});
  const nlohmann::json y = run_json({"simulate", "--suite", suite->dir(), "--set", "1", "--component", "y", "--json"});
  CHECK_TRUE(x["collapsed"].get<bool>());
  DOUBLES_EQUAL(0.20 * kG, x["pga_mps2"].get<double>(), 1e-9);
  DOUBLES_EQUAL(0.14 * kG, y["pga_mps2"].get<double>(), 1e-9);
}

TEST(RecordSelection, JsonSaysWhichSuiteRecordRan) {
  const nlohmann::json j = run_json({"simulate", "--suite", suite->dir(), "--set", "1", "--component", "X",
                                     "--vertical-from-suite", "--json"});
  const nlohmann::json& s = j["suite"];
  STRCMP_EQUAL(suite->dir().c_str(), s["dir"].get<std::string>().c_str());
  STRCMP_EQUAL("test", s["name"].get<std::string>().c_str());
  CHECK_EQUAL(1, s["set"].get<int>());
  STRCMP_EQUAL("X", s["component"].get<std::string>().c_str());
  STRCMP_EQUAL(suite->set_file().c_str(), s["file"].get<std::string>().c_str());
  STRCMP_EQUAL("Z", s["vertical_component"].get<std::string>().c_str());
  // The documented keys are all still there, unchanged.
  for (const char* key : {"max_abs_x_m", "collapsed", "t_collapse_s", "pga_mps2", "dt_s", "duration_s", "kappa"}) {
    CHECK_TEXT(j.contains(key), key);
  }
}

// The Z component of the same set is the vertical on the same grid: exactly the run of a (time, X, Z) file.
TEST(RecordSelection, VerticalFromSuiteEqualsAThreeColumnFile) {
  std::string err;
  const nlohmann::json from_suite = run_json({"simulate", "--suite", suite->dir(), "--set", "1", "--component", "X",
                                              "--vertical-from-suite", "--scale-pga", "0.18", "--json"},
                                             &err);
  const nlohmann::json from_columns =
      run_json({"simulate", "--record", suite->three_column_file(), "--scale-pga", "0.18", "--json"});
  CHECK_TRUE(without_selection(from_suite) == from_columns);
  CHECK_TEXT(err.find("resampled") == std::string::npos, err.c_str());  // same grid: nothing to note
  // The vertical changes the answer, so it was used.
  const nlohmann::json horizontal_only = run_json(
      {"simulate", "--suite", suite->dir(), "--set", "1", "--component", "X", "--scale-pga", "0.18", "--json"});
  CHECK_FALSE(without_selection(horizontal_only) == from_columns);
}

TEST(RecordSelection, HumanSummaryNamesTheSuiteRecordAndItsVertical) {
  const ProcessResult r =
      run_rockwatch({"simulate", "--suite", suite->dir(), "--set", "1", "--component", "Y", "--vertical-from-suite"});
  CHECK_EQUAL_TEXT(0, r.exit_status, describe(r).c_str());
  STRCMP_CONTAINS(("suite test set 1 component Y, " + suite->set_file()).c_str(), r.out.c_str());
  STRCMP_CONTAINS(("suite test set 1 component Z, " + suite->set_file()).c_str(), r.out.c_str());
}

TEST(RecordSelection, SpectrumOfASuiteRecordEqualsItsColumn) {
  const nlohmann::json from_suite = run_json({"spectrum", "--suite", suite->dir(), "--set", "1", "--component", "Z",
                                              "--periods", "0.05:2:20", "--json"});
  // The Z column alone, as a plain two-column file.
  std::string text = "# units: mps2\n";
  for (int k = 0; k < kSamples; ++k) text += time_text(k) + " " + value_text(z_mps2(k * kDt)) + "\n";
  const std::string z_file = suite->dir() + "/z.txt";
  write_text(z_file, text);
  const nlohmann::json from_column = run_json({"spectrum", "--record", z_file, "--periods", "0.05:2:20", "--json"});
  CHECK_TRUE(without_selection(from_suite) == from_column);
  STRCMP_EQUAL("Z", from_suite["suite"]["component"].get<std::string>().c_str());

  const ProcessResult human = run_rockwatch({"spectrum", "--suite", suite->dir(), "--set", "1", "--component", "Z"});
  CHECK_EQUAL_TEXT(0, human.exit_status, describe(human).c_str());
  STRCMP_CONTAINS("suite test set 1 component Z", human.out.c_str());
}

// --channel, --gain and --vertical-channel reach the reader: a three-channel miniSEED file of a Groningen station.
TEST(RecordSelection, SpectrumOfAMiniseedChannelEqualsTheReader) {
  const std::string mseed = rockwatch::test::record_path("NL.BGAR.mseed");
  const nlohmann::json j = run_json({"spectrum", "--record", mseed, "--channel", "HGN", "--gain", kBgarGain,
                                     "--periods", "0.05:2:10", "--json"});
  records::ReadOptions options;
  options.channel = "HGN";
  options.gain_counts_per_mps2 = std::stod(kBgarGain);
  const records::Record r = records::read_record(mseed, options);
  const sim::ResponseSpectrum expected =
      sim::response_spectrum(r.horizontal_mps2, r.dt_s, sim::log_spaced_periods(0.05, 2.0, 10));
  LONGS_EQUAL(expected.psa_mps2.size(), j["sa_mps2"].size());
  for (std::size_t i = 0; i < expected.psa_mps2.size(); ++i) {
    DOUBLES_EQUAL(expected.psa_mps2[i], j["sa_mps2"][i].get<double>(), 1e-12 * expected.psa_mps2[i]);
  }
  STRCMP_EQUAL("HGN", j["channel"].get<std::string>().c_str());
  DOUBLES_EQUAL(std::stod(kBgarGain), j["gain_counts_per_mps2"].get<double>(), 0.0);
}

// Two channels of one station start a fraction of a second apart: the vertical is put on the horizontal's clock by
// the files' start times, then run exactly as the engine would run it.
TEST(RecordSelection, VerticalChannelIsAlignedByStartTime) {
  const std::string mseed = rockwatch::test::record_path("NL.BGAR.mseed");
  std::string err;
  const nlohmann::json j = run_json({"simulate", "--record", mseed, "--channel", "HGE", "--gain", kBgarGain,
                                     "--vertical", mseed, "--vertical-channel", "HGZ", "--scale-pga", "0.3", "--json"},
                                    &err);
  STRCMP_CONTAINS("aligned on that clock", err.c_str());
  STRCMP_EQUAL("HGE", j["channel"].get<std::string>().c_str());
  STRCMP_EQUAL("HGZ", j["vertical_channel"].get<std::string>().c_str());

  records::ReadOptions options;
  options.gain_counts_per_mps2 = std::stod(kBgarGain);
  options.channel = "HGE";
  const records::Record h = records::read_record(mseed, options);
  options.channel = "HGZ";
  const records::Record v = records::read_record(mseed, options);
  const double offset_s = static_cast<double>(*v.start_time_ns - *h.start_time_ns) * 1e-9;
  CHECK_TRUE(offset_s != 0.0);
  sim::GroundMotion motion;
  motion.dt_s = h.dt_s;
  const double factor = 0.3 * kG / sim::peak_abs(h.horizontal_mps2);
  for (const double u : h.horizontal_mps2) motion.ug_mps2.push_back(u * factor);
  motion.vg_mps2 = rockwatch::cli::resample_linear(v.horizontal_mps2, {v.t0_s + offset_s, v.dt_s, 0},
                                                   {h.t0_s, h.dt_s, h.horizontal_mps2.size()});
  for (double& a : motion.vg_mps2) a *= factor;
  const sim::AnalysisResult e = sim::analyse(rockwatch::core::paper_wall(), motion, sim::AnalysisOptions{});
  DOUBLES_EQUAL(e.max_abs_x_m, j["max_abs_x_m"].get<double>(), 1e-12);
  CHECK_EQUAL(e.n_impacts, j["n_impacts"].get<int>());
  CHECK_EQUAL(e.collapsed, j["collapsed"].get<bool>());
}

TEST(RecordSelection, HelpListsTheOptions) {
  const ProcessResult simulate = run_rockwatch({"simulate", "--help"});
  for (const char* option : {"--suite", "--set", "--component", "--channel", "--vertical-channel",
                             "--vertical-from-suite", "--gain", "--units", "--dt"}) {
    STRCMP_CONTAINS(option, simulate.out.c_str());
  }
  const ProcessResult spectrum = run_rockwatch({"spectrum", "--help"});
  for (const char* option : {"--suite", "--set", "--component", "--channel", "--gain"}) {
    STRCMP_CONTAINS(option, spectrum.out.c_str());
  }
  // spectrum measures one record: no vertical options.
  CHECK_TRUE(spectrum.out.find("--vertical") == std::string::npos);
}

namespace {

void expect_rejected(const std::vector<std::string>& args, const std::vector<std::string>& mentions,
                     const std::string& command = "simulate") {
  rockwatch::test::expect_command_rejected(command, args, mentions);
}

}  // namespace

TEST_GROUP(RecordSelectionRejects) {
  std::unique_ptr<HandMadeSuite> suite;
  std::vector<std::string> from_suite;  // --suite DIR
  void setup() override {
    suite = std::make_unique<HandMadeSuite>();
    from_suite = {"--suite", suite->dir()};
  }
  void teardown() override { suite.reset(); }
  std::vector<std::string> with(std::vector<std::string> more) const {
    std::vector<std::string> args = from_suite;
    args.insert(args.end(), more.begin(), more.end());
    return args;
  }
};

TEST(RecordSelectionRejects, NoRecordAtAll) { expect_rejected({"--json"}, {"--record", "--suite"}); }
TEST(RecordSelectionRejects, RecordAndSuiteTogether) {
  expect_rejected(with({"--set", "1", "--component", "X", "--record", suite->set_file()}), {"--record", "--suite"});
}
TEST(RecordSelectionRejects, SuiteWithoutSet) { expect_rejected(with({"--component", "X"}), {"--suite", "missing --set"}); }
TEST(RecordSelectionRejects, SuiteWithoutComponent) {
  expect_rejected(with({"--set", "1"}), {"--suite", "missing --component"});
}
TEST(RecordSelectionRejects, SuiteWithoutSetAndComponent) {
  expect_rejected(from_suite, {"missing --set and --component"});
}
TEST(RecordSelectionRejects, ComponentW) {
  expect_rejected(with({"--set", "1", "--component", "W"}), {"--component", "X or Y", "Z", "'W'"});
}
TEST(RecordSelectionRejects, SetZero) { expect_rejected(with({"--set", "0", "--component", "X"}), {"--set", ">= 1", "'0'"}); }
TEST(RecordSelectionRejects, SetNotAWholeNumber) {
  expect_rejected(with({"--set", "1.5", "--component", "X"}), {"--set", "whole number", "'1.5'"});
}
TEST(RecordSelectionRejects, SetNotInTheManifestListsItsSets) {
  expect_rejected(with({"--set", "99", "--component", "X"}), {"manifest.json", "no set 99", "it has sets 1"});
}
TEST(RecordSelectionRejects, SuiteDirectoryWithoutManifest) {
  const TempDir empty;
  expect_rejected({"--suite", empty.path(), "--set", "1", "--component", "X"}, {empty.path(), "manifest.json"});
}
TEST(RecordSelectionRejects, SetWithoutSuite) {
  expect_rejected({"--record", suite->set_file(), "--component", "X", "--set", "1"}, {"--set", "--suite"});
}
TEST(RecordSelectionRejects, SuiteFileAsRecordWithoutComponent) {
  expect_rejected({"--record", suite->set_file()}, {suite->set_file(), "--component X|Y|Z"});
}
TEST(RecordSelectionRejects, VerticalFromSuiteWithoutSuite) {
  expect_rejected({"--record", suite->set_file(), "--component", "X", "--vertical-from-suite"},
                  {"--vertical-from-suite", "--suite"});
}
TEST(RecordSelectionRejects, VerticalFromSuiteWithVertical) {
  expect_rejected(with({"--set", "1", "--component", "X", "--vertical-from-suite", "--vertical",
                        suite->three_column_file()}),
                  {"--vertical-from-suite", "--vertical"});
}
TEST(RecordSelectionRejects, VerticalFromSuiteWithComponentZ) {
  expect_rejected(with({"--set", "1", "--component", "Z", "--vertical-from-suite"}),
                  {"--vertical-from-suite", "X or Y", "got Z"});
}
TEST(RecordSelectionRejects, ComponentAndChannelTogether) {
  expect_rejected({"--record", suite->set_file(), "--component", "X", "--channel", "HNE"}, {"--component", "--channel"});
}
TEST(RecordSelectionRejects, VerticalChannelWithoutVertical) {
  expect_rejected({"--record", suite->set_file(), "--component", "X", "--vertical-channel", "HNZ"},
                  {"--vertical-channel", "--vertical"});
}
TEST(RecordSelectionRejects, EmptyChannel) {
  expect_rejected({"--record", suite->three_column_file(), "--channel", ""}, {"--channel", "channel code"});
}
TEST(RecordSelectionRejects, GainNegative) {
  expect_rejected({"--record", suite->three_column_file(), "--gain", "-1"}, {"--gain", "> 0", "-1"});
}
TEST(RecordSelectionRejects, GainZero) { expect_rejected({"--record", suite->three_column_file(), "--gain", "0"}, {"--gain", "> 0"}); }
TEST(RecordSelectionRejects, GainNotFinite) {
  expect_rejected({"--record", suite->three_column_file(), "--gain", "inf"}, {"--gain", "finite"});
}
// --gain converts miniSEED counts: the readers of other formats refuse it rather than ignore it.
TEST(RecordSelectionRejects, GainOnASuiteRecord) {
  expect_rejected(with({"--set", "1", "--component", "X", "--gain", "1000"}), {"--gain"});
}
TEST(RecordSelectionRejects, SpectrumSuiteWithoutSet) {
  expect_rejected(with({"--component", "X"}), {"--suite", "missing --set"}, "spectrum");
}
TEST(RecordSelectionRejects, SpectrumHasNoVerticalFromSuite) {
  expect_rejected(with({"--set", "1", "--component", "X", "--vertical-from-suite"}), {"--vertical-from-suite"},
                  "spectrum");
}
TEST(RecordSelectionRejects, SpectrumGainNegative) {
  expect_rejected({"--record", suite->three_column_file(), "--gain", "-1"}, {"--gain", "> 0"}, "spectrum");
}
