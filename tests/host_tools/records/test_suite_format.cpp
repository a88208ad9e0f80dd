// The rockwatch suite format (suite_format.hpp): set files written and read back, read as records through
// read_record with a component choice, every rejection path of the reader and the writer, and the directory
// manifest with hand-made manifest.json files.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "rockwatch/records/record.hpp"
#include "record_test_support.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/records/suite_format.hpp"

// After the standard headers: CppUTest's leak-detector macros redefine new/malloc.
#include <CppUTest/TestHarness.h>

namespace fs = std::filesystem;
using rockwatch::records::AccelUnit;
using rockwatch::records::looks_like_peer_at2;
using rockwatch::records::looks_like_suite_record;
using rockwatch::records::read_record;
using rockwatch::records::read_suite_record;
using rockwatch::records::ReadOptions;
using rockwatch::records::Record;
using rockwatch::records::RecordError;
using rockwatch::test::check_rejection;
using rockwatch::test::failure_of;
using rockwatch::test::Failure;
using rockwatch::test::has_note_with;
using rockwatch::records::suite_set_path;
using rockwatch::records::suite_sets;
using rockwatch::records::SuiteRecordFile;
using rockwatch::records::write_suite_record;

namespace {

// A set whose values span the magnitudes a generated motion has (1e-9 to 10 m/s², both signs).
SuiteRecordFile sample_set(std::size_t rows = 400) {
  SuiteRecordFile set;
  set.suite = "npr9998-2015";
  set.set = 3;
  set.dt_s = 0.005;
  set.g_mps2 = 9.81;
  set.ag_mps2 = 1.962;
  set.avg_mps2 = 1.4715;
  set.horizontal_target = "npr9998-2015 p=2.5 tb_s=0.15 tc_s=0.4 td_s=0.67";
  set.vertical_target = "vertical-default p=3 tb_s=0.05 tc_s=0.15 td_s=1";
  set.seed = 18446744073709551557ULL;  // a seed beyond 2^63 must survive
  set.generator = "rockwatch 0.4.0 generate --sets 11 --seed 9998";
  for (std::size_t k = 0; k < rows; ++k) {
    const double t = static_cast<double>(k) * set.dt_s;
    set.components_mps2[0].push_back(3.7 * std::sin(7.1 * t) * std::exp(-0.3 * t));
    set.components_mps2[1].push_back(-1.234567890123e-9 * static_cast<double>(k % 17) + 1e-3 * std::cos(3.3 * t));
    set.components_mps2[2].push_back(k % 50 == 0 ? 0.0 : 9.87654321098765 * std::sin(1.3 * t + 0.2));
  }
  return set;
}

// The header lines write_suite_record writes, for hand-made variants.
const char* const kHeader =
    "# rockwatch-suite-record: 1\n"
    "# suite: npr9998-2015\n"
    "# set: 3\n"
    "# units: m/s2\n"
    "# dt_s: 0.005\n"
    "# g_mps2: 9.81\n"
    "# ag_mps2: 1.962\n"
    "# avg_mps2: 1.962\n"
    "# horizontal_target: npr9998-2015 p=2.5 tb_s=0.15 tc_s=0.4 td_s=0.67\n"
    "# vertical_target: vertical-default p=3 tb_s=0.05 tc_s=0.15 td_s=1\n"
    "# seed: 9998\n"
    "# generator: rockwatch 0.4.0 generate --sets 11 --seed 9998\n"
    "# columns: time_s x_mps2 y_mps2 z_mps2\n";
constexpr int kHeaderLines = 13;
const char* const kRows =
    "0.000000 1.000000000e-02 -2.000000000e-02 3.000000000e-03\n"
    "0.005000 1.500000000e-02 -2.500000000e-02 3.500000000e-03\n"
    "0.010000 2.000000000e-02 -3.000000000e-02 4.000000000e-03\n";

std::string header_without(const std::string& key) {
  std::string header = kHeader;
  const std::size_t at = header.find("# " + key + ":");
  header.erase(at, header.find('\n', at) - at + 1);
  return header;
}

std::string header_with(const std::string& key, const std::string& value) {
  std::string header = kHeader;
  const std::size_t at = header.find("# " + key + ":");
  const std::size_t end = header.find('\n', at);
  header.replace(at, end - at, "# " + key + ": " + value);
  return header;
}

ReadOptions component(const std::string& name) {
  ReadOptions options;
  options.channel = name;
  return options;
}

}  // namespace

TEST_GROUP_BASE(SuiteFormat, rockwatch::test::HandMadeFileTest) {
  // Hides the base's read_record version: read_suite_record's RecordError names the file, the line (":N:", or none when line == 0) and each fragment.
  void expect_rejected(const std::string& name, const std::string& content, int line,
                       const std::vector<std::string>& fragments) {
    const std::string path = write(name, content);
    const Failure f = failure_of([&] { read_suite_record(path); });
    check_rejection(f, name, line, fragments);
  }

  void expect_write_rejected(const SuiteRecordFile& set, const std::vector<std::string>& fragments) {
    const std::string path = (dir / "rejected.txt").string();
    const Failure f = failure_of([&] { write_suite_record(path, set); });
    STRCMP_CONTAINS("rejected.txt: ", f.message.c_str());
    for (const std::string& fragment : fragments) STRCMP_CONTAINS(fragment.c_str(), f.message.c_str());
    CHECK_FALSE(fs::exists(path));
    CHECK_FALSE(fs::exists(path + ".partial"));
  }

  std::string manifest(const std::string& json) { return write("suite/manifest.json", json); }
  std::string suite_dir() const { return (dir / "suite").string(); }

  void expect_manifest_rejected(int set, const std::vector<std::string>& fragments, int line = 0) {
    const Failure f = failure_of([&] { suite_set_path(suite_dir(), set); });
    const std::string located = "manifest.json" + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": ";
    STRCMP_CONTAINS(located.c_str(), f.message.c_str());
    LONGS_EQUAL(line, f.line);
    for (const std::string& fragment : fragments) STRCMP_CONTAINS(fragment.c_str(), f.message.c_str());
  }
};

// --- writing and reading back ----------------------------------------------------------------------------------

TEST(SuiteFormat, RoundTripKeepsHeaderAndTenSignificantDigits) {
  const SuiteRecordFile written = sample_set();
  const std::string path = (dir / "set03.txt").string();
  write_suite_record(path, written);
  CHECK_TRUE(looks_like_suite_record(path));
  CHECK_FALSE(looks_like_peer_at2(path));
  CHECK_FALSE(fs::exists(path + ".partial"));

  const SuiteRecordFile read = read_suite_record(path);
  STRCMP_EQUAL(written.suite.c_str(), read.suite.c_str());
  LONGS_EQUAL(written.set, read.set);
  DOUBLES_EQUAL(written.dt_s, read.dt_s, 0.0);
  DOUBLES_EQUAL(written.g_mps2, read.g_mps2, 0.0);
  DOUBLES_EQUAL(written.ag_mps2, read.ag_mps2, 0.0);
  DOUBLES_EQUAL(written.avg_mps2, read.avg_mps2, 0.0);
  STRCMP_EQUAL(written.horizontal_target.c_str(), read.horizontal_target.c_str());
  STRCMP_EQUAL(written.vertical_target.c_str(), read.vertical_target.c_str());
  CHECK(written.seed == read.seed);
  STRCMP_EQUAL(written.generator.c_str(), read.generator.c_str());
  for (std::size_t c = 0; c < 3; ++c) {
    LONGS_EQUAL(written.components_mps2[c].size(), read.components_mps2[c].size());
    for (std::size_t k = 0; k < written.components_mps2[c].size(); ++k) {
      const double expected = written.components_mps2[c][k];
      DOUBLES_EQUAL(expected, read.components_mps2[c][k], 5e-10 * std::fabs(expected));
    }
  }
}

TEST(SuiteFormat, WrittenTextIsAsDocumented) {
  SuiteRecordFile set = sample_set(2);
  set.components_mps2 = {{{1.23456789012e-05, -2.0}, {0.0, 3.0}, {-4.5, 1e-300}}};
  const std::string path = (dir / "doc.txt").string();
  write_suite_record(path, set);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  STRCMP_CONTAINS("# rockwatch-suite-record: 1\n# suite: npr9998-2015\n# set: 3\n# units: m/s2\n# dt_s: 0.005\n",
                  text.c_str());
  STRCMP_CONTAINS("# seed: 18446744073709551557\n", text.c_str());
  STRCMP_CONTAINS(
      "# columns: time_s x_mps2 y_mps2 z_mps2\n"
      "0.000000 1.234567890e-05 0.000000000e+00 -4.500000000e+00\n"
      "0.005000 -2.000000000e+00 3.000000000e+00 1.000000000e-300\n",
      text.c_str());
}

TEST(SuiteFormat, ReadRecordTakesTheChosenComponent) {
  const SuiteRecordFile written = sample_set();
  const std::string path = (dir / "any-name.dat").string();
  write_suite_record(path, written);
  const char* const names[] = {"X", "y", "Z"};
  for (std::size_t c = 0; c < 3; ++c) {
    const Record r = read_record(path, component(names[c]));
    STRCMP_EQUAL("rockwatch-suite", r.format.c_str());
    const std::string description = std::string("suite npr9998-2015 set 3 component ") + "XYZ"[c];
    STRCMP_EQUAL(description.c_str(), r.description.c_str());
    CHECK(r.units_in_file == AccelUnit::mps2);
    DOUBLES_EQUAL(0.005, r.dt_s, 0.0);
    DOUBLES_EQUAL(0.0, r.t0_s, 0.0);
    CHECK_FALSE(r.start_time_ns);
    CHECK(r.vertical_mps2.empty());
    LONGS_EQUAL(written.components_mps2[c].size(), r.horizontal_mps2.size());
    DOUBLES_EQUAL(written.components_mps2[c][7], r.horizontal_mps2[7],
                  5e-10 * std::fabs(written.components_mps2[c][7]));
    CHECK(r.notes.empty());
  }
  // --units mps2 is what the file holds; a --dt is noted and ignored.
  ReadOptions same = component("X");
  same.units = AccelUnit::mps2;
  same.dt_s = 0.01;
  const Record r = read_record(path, same);
  DOUBLES_EQUAL(0.005, r.dt_s, 0.0);
  CHECK(has_note_with(r, {"--dt 0.01 s ignored", "dt_s"}));
}

TEST(SuiteFormat, ComponentChoiceAndOptionsAreChecked) {
  const std::string path = (dir / "set01.txt").string();
  write_suite_record(path, sample_set(10));
  const Failure none = failure_of([&] { read_record(path); });
  STRCMP_CONTAINS("set01.txt: the file holds 3 components (X, Y, Z", none.message.c_str());
  STRCMP_CONTAINS("choose one with --component X|Y|Z", none.message.c_str());
  const Failure bad = failure_of([&] { read_record(path, component("HGE")); });
  STRCMP_CONTAINS("component 'HGE': expected X, Y or Z", bad.message.c_str());
  ReadOptions g = component("X");
  g.units = AccelUnit::g;
  STRCMP_CONTAINS("always in m/s²; --units g does not apply",
                  failure_of([&] { read_record(path, g); }).message.c_str());
  ReadOptions gain = component("X");
  gain.gain_counts_per_mps2 = 10.0;
  STRCMP_CONTAINS("--gain does not apply", failure_of([&] { read_record(path, gain); }).message.c_str());
}

TEST(SuiteFormat, HandWrittenFileWithCommentsAndOnlyTheRequiredKeys) {
  const std::string path = write("minimal.txt",
                                 "# rockwatch-suite-record: 1\n"
                                 "# a set made by hand\n"
                                 "# units: m/s^2\n"
                                 "# dt_s: 0.01\n"
                                 "# columns: time_s  x_mps2  y_mps2  z_mps2\n"
                                 "\n"
                                 "0 1 2 3\r\n"
                                 "0.01 4 5 6\n");
  const SuiteRecordFile set = read_suite_record(path);
  STRCMP_EQUAL("", set.suite.c_str());
  LONGS_EQUAL(0, set.set);
  LONGS_EQUAL(2, set.components_mps2[2].size());
  DOUBLES_EQUAL(6.0, set.components_mps2[2][1], 0.0);
  STRCMP_EQUAL("suite component Y", read_record(path, component("Y")).description.c_str());
}

// --- reader rejections -----------------------------------------------------------------------------------------

TEST(SuiteFormat, BadMagicOrVersion) {
  expect_rejected("magic.txt", std::string("# rockwatch-suite: 1\n") + (kHeader + 28) + kRows, 1,
                  {"expected the first line '# rockwatch-suite-record: 1'", "'# rockwatch-suite: 1'"});
  expect_rejected("v2.txt", header_with("rockwatch-suite-record", "2") + kRows, 1,
                  {"format version 2: expected version 1"});
  expect_rejected("vword.txt", header_with("rockwatch-suite-record", "one") + kRows, 1, {"format version 'one'"});
  expect_rejected("empty.txt", "", 1, {"empty file"});
  // Without the magic line the file is not a suite record, so read_record does not read it as one.
  const std::string plain = write("plain.txt", std::string(kHeader + 28) + kRows);
  CHECK_FALSE(looks_like_suite_record(plain));
}

TEST(SuiteFormat, MissingRequiredKeys) {
  expect_rejected("nodt.txt", header_without("dt_s") + kRows, kHeaderLines, {"no 'dt_s' header line", "# dt_s: "});
  expect_rejected("nounits.txt", header_without("units") + kRows, kHeaderLines, {"no 'units' header line"});
  expect_rejected("nocolumns.txt", header_without("columns") + kRows, kHeaderLines, {"no 'columns' header line"});
}

TEST(SuiteFormat, BadHeaderValues) {
  expect_rejected("units.txt", header_with("units", "g") + kRows, 4, {"units: 'g'", "expected m/s2"});
  expect_rejected("dt0.txt", header_with("dt_s", "0") + kRows, 5, {"dt_s: '0'", "expected a positive number"});
  expect_rejected("dtnan.txt", header_with("dt_s", "nan") + kRows, 5, {"dt_s: 'nan'"});
  expect_rejected("columns.txt", header_with("columns", "time_s x_mps2 z_mps2 y_mps2") + kRows, 13,
                  {"columns: 'time_s x_mps2 z_mps2 y_mps2'", "expected 'time_s x_mps2 y_mps2 z_mps2'"});
  expect_rejected("set0.txt", header_with("set", "0") + kRows, 3,
                  {"set: '0'", "expected a whole number of at least 1"});
  expect_rejected("seed.txt", header_with("seed", "-1") + kRows, 11, {"seed: '-1'"});
  expect_rejected("g.txt", header_with("g_mps2", "-9.81") + kRows, 6, {"g_mps2: '-9.81'"});
  expect_rejected("twice.txt", std::string(kHeader) + "# dt_s: 0.01\n" + kRows, 14,
                  {"'dt_s' appears twice (also on line 5)"});
}

TEST(SuiteFormat, BadRows) {
  expect_rejected("three.txt", std::string(kHeader) + "0.000000 1 2 3\n0.005000 1 2\n", kHeaderLines + 2,
                  {"found 3 columns: expected 4 (time_s x_mps2 y_mps2 z_mps2)"});
  expect_rejected("five.txt", std::string(kHeader) + "0.000000 1 2 3 4\n", kHeaderLines + 1, {"found 5 columns"});
  expect_rejected("time.txt", std::string(kHeader) + "0.000000 1 2 3\n0.005000 1 2 3\n0.015000 1 2 3\n",
                  kHeaderLines + 3, {"time 0.015 s: expected 0.01 s, row 2 times dt_s 0.005"});
  expect_rejected("start.txt", std::string(kHeader) + "1.000000 1 2 3\n", kHeaderLines + 1, {"time 1 s: expected 0 s"});
  expect_rejected("nan.txt", std::string(kHeader) + "0.000000 1 nan 3\n", kHeaderLines + 1,
                  {"'nan'", "expected a finite number"});
  expect_rejected("inf.txt", std::string(kHeader) + "0.000000 1 2 -inf\n", kHeaderLines + 1, {"'-inf'"});
  expect_rejected("word.txt", std::string(kHeader) + "0.000000 1 two 3\n", kHeaderLines + 1,
                  {"'two'", "expected a decimal number"});
  expect_rejected("nodata.txt", kHeader, kHeaderLines, {"no data rows"});
  expect_rejected("latecomment.txt", std::string(kHeader) + "0.000000 1 2 3\n# dt_s: 0.01\n0.005000 1 2 3\n",
                  kHeaderLines + 2, {"a '#' line among the data"});
}

TEST(SuiteFormat, TimesToSixDecimalsAreExactEnough) {
  // dt = 1/3 ms is not a multiple of 1 µs: times are rounded to 6 decimals when written and accepted when read.
  SuiteRecordFile set = sample_set(3000);
  set.dt_s = 1.0 / 3000.0;
  const std::string path = (dir / "third.txt").string();
  write_suite_record(path, set);
  LONGS_EQUAL(3000, read_suite_record(path).components_mps2[0].size());
}

// --- writer rejections -----------------------------------------------------------------------------------------

TEST(SuiteFormat, WriterRejectsWhatCannotBeRead) {
  SuiteRecordFile unequal = sample_set(10);
  unequal.components_mps2[2].pop_back();
  expect_write_rejected(unequal, {"component Z has 9 samples, X has 10", "expected equal lengths"});
  SuiteRecordFile empty = sample_set(0);
  expect_write_rejected(empty, {"no samples"});
  SuiteRecordFile nan = sample_set(10);
  nan.components_mps2[1][4] = std::nan("");
  expect_write_rejected(nan, {"component Y sample 4", "expected finite accelerations"});
  SuiteRecordFile dt = sample_set(10);
  dt.dt_s = 0.0;
  expect_write_rejected(dt, {"dt_s 0", "expected a positive sample interval"});
  SuiteRecordFile set0 = sample_set(10);
  set0.set = 0;
  expect_write_rejected(set0, {"set 0"});
  SuiteRecordFile newline = sample_set(10);
  newline.generator = "rockwatch\ngenerate";
  expect_write_rejected(newline, {"generator", "no line breaks"});
  // A directory that does not exist cannot take the file.
  const std::string nowhere = (dir / "no" / "such" / "dir" / "set.txt").string();
  const Failure f = failure_of([&] { write_suite_record(nowhere, sample_set(10)); });
  STRCMP_CONTAINS("set.txt: cannot create the file", f.message.c_str());
}

// --- manifest ----------------------------------------------------------------------------------------------------

TEST(SuiteFormat, ManifestGivesTheSetFile) {
  manifest(R"({"format": "rockwatch-suite-manifest", "version": 1, "suite": "npr9998-2015",
  "sets": [{"set": 2, "file": "set02.txt", "pga_x_mps2": 1.9},
           {"set": 1, "file": "set01.txt"},
           {"set": 10, "file": "sets/set10.txt"}],
  "command": "rockwatch generate --sets 3"})");
  const std::vector<int> sets = suite_sets(suite_dir());
  LONGS_EQUAL(3, sets.size());
  LONGS_EQUAL(2, sets[0]);
  LONGS_EQUAL(1, sets[1]);
  LONGS_EQUAL(10, sets[2]);
  STRCMP_EQUAL((fs::path(suite_dir()) / "set01.txt").string().c_str(), suite_set_path(suite_dir(), 1).c_str());
  STRCMP_EQUAL((fs::path(suite_dir()) / "sets/set10.txt").string().c_str(), suite_set_path(suite_dir(), 10).c_str());
  // The path is usable: a set written there reads back.
  write_suite_record(suite_set_path(suite_dir(), 2), sample_set(5));
  LONGS_EQUAL(5, read_record(suite_set_path(suite_dir(), 2), component("Z")).horizontal_mps2.size());
}

TEST(SuiteFormat, MissingManifest) {
  fs::create_directories(suite_dir());
  expect_manifest_rejected(1, {"no suite manifest", "expected manifest.json in", "rockwatch generate"});
  const Failure f = failure_of([&] { suite_sets((dir / "nowhere").string()); });
  STRCMP_CONTAINS("no suite manifest", f.message.c_str());
}

TEST(SuiteFormat, MalformedManifest) {
  manifest("{\"format\": \"rockwatch-suite-manifest\",\n \"sets\": [\n  {\"set\": 1, \"file\": \"set01.txt\"\n]}\n");
  expect_manifest_rejected(1, {"malformed JSON", "expected the manifest written by rockwatch generate"}, 4);
  manifest("");
  expect_manifest_rejected(1, {"malformed JSON"}, 1);
  manifest("[1, 2]");
  expect_manifest_rejected(1, {"expected a JSON object"});
  manifest(R"({"format": "something-else", "sets": []})");
  expect_manifest_rejected(1, {"\"format\": expected \"rockwatch-suite-manifest\"", "'\"something-else\"'"});
  manifest(R"({"format": "rockwatch-suite-manifest", "version": 2, "sets": []})");
  expect_manifest_rejected(1, {"\"version\": '2': expected 1"});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": {"set": 1}})");
  expect_manifest_rejected(1, {"\"sets\": expected an array"});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": "1", "file": "a.txt"}]})");
  expect_manifest_rejected(1, {"sets[0]: \"set\": expected a whole number of 1 or more"});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": 1.5, "file": "a.txt"}]})");
  expect_manifest_rejected(1, {"sets[0]: \"set\""});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": 1}]})");
  expect_manifest_rejected(1, {"sets[0]: \"file\": expected the set file's name", "found none"});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": 1, "file": "a.txt"}, {"set": 1, "file": "b"}]})");
  expect_manifest_rejected(1, {"sets[1]: set 1 is listed twice"});
}

TEST(SuiteFormat, MissingSetListsTheAvailableOnes) {
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [
    {"set": 1, "file": "s1.txt"}, {"set": 2, "file": "s2.txt"}, {"set": 3, "file": "s3.txt"},
    {"set": 5, "file": "s5.txt"}, {"set": 8, "file": "s8.txt"}, {"set": 9, "file": "s9.txt"}]})");
  expect_manifest_rejected(4, {"no set 4 in the manifest", "it has sets 1-3, 5, 8-9"});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": []})");
  expect_manifest_rejected(1, {"no set 1 in the manifest: it lists no sets"});
}

TEST(SuiteFormat, SetFilesMustStayInTheDirectory) {
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": 1, "file": "../elsewhere/set01.txt"}]})");
  expect_manifest_rejected(1, {"sets[0]", "'../elsewhere/set01.txt' leaves the suite directory"});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": 1, "file": "sets/../../x.txt"}]})");
  expect_manifest_rejected(1, {"leaves the suite directory"});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": 1, "file": "/etc/passwd"}]})");
  expect_manifest_rejected(1, {"'/etc/passwd' is an absolute path"});
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": 1, "file": ""}]})");
  expect_manifest_rejected(1, {"empty \"file\""});
  // Even an escaping entry for another set makes the manifest unusable.
  manifest(R"({"format": "rockwatch-suite-manifest", "sets": [{"set": 1, "file": "ok.txt"},
    {"set": 2, "file": "../x.txt"}]})");
  expect_manifest_rejected(1, {"sets[1]", "leaves the suite directory"});
}

// Fuzzing regression (tests/fuzz/regressions/suite_manifest/number_overflow.json): nlohmann reports a number beyond
// double as json::out_of_range, not json::parse_error, so it escaped the reader as an unexpected exception.
TEST(SuiteFormat, ManifestNumberBeyondDoubleIsMalformedJson) {
  manifest(R"({"format": "rockwatch-suite-manifest", "version": 1e400, "sets": []})");
  expect_manifest_rejected(1, {"malformed JSON", "number overflow", "expected the manifest written by"});
}
