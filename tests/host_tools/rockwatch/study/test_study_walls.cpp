// `rockwatch study --walls FILE.csv` end to end on a mini plan (set 1, 5 PGA levels 0.2 to 0.4 g, r_exp, horizontal only: 10
// analyses per wall): each wall of a portfolio gets exactly the rows and statistics the single-wall study gives that
// wall (--b, --h1, ... on the command line), walls_summary.csv says what summary.json says, --resume after losing rows
// gives the same files, the shipped example portfolio is valid and spans the paper's range, the figure is drawn, and
// every bad row is refused naming the file and line (exit 2).
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/options/option_values.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_study_walls {

using rockwatch::options::split_fields;
using rockwatch::test::describe;
using rockwatch::test::expect_command_rejected;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;
using rockwatch::test::TempDir;
using rockwatch::test::write_text;
namespace fs = std::filesystem;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;
const std::string kExamplePortfolio = kSuite + "/../../portfolios/example_walls.csv";

std::vector<std::string> plan_args() {
  return {"--suite", kSuite, "--sets", "1", "--pga", "0.2:0.4:0.05", "--r", "exp", "--vertical", "without"};
}

std::vector<std::string> study_args(const std::string& out, const std::vector<std::string>& more) {
  std::vector<std::string> args{"study"};
  for (const std::string& a : plan_args()) args.push_back(a);
  args.emplace_back("--out");
  args.push_back(out);
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines = split_fields(text, '\n');
  if (!lines.empty() && lines.back().empty()) lines.pop_back();
  return lines;
}

void check_ok(const ProcessResult& r) {
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
}

// Three walls: the paper's (every field empty), a thicker and taller one, one with overburden and eccentricity.
const char* const kPortfolio =
    "# a comment line\n"
    "id,b,h1,h2,rho,fp,a,a_prime\n"
    "paper,,,,,,,\n"
    "thick,0.14,1.5,1.6,1900,,,\n"
    "loaded,0.1,1.75,1.75,,3000,0.5,0.25\n";
const std::vector<std::vector<std::string>> kWallOptions{
    {},
    {"--b", "0.14", "--h1", "1.5", "--h2", "1.6", "--rho", "1900"},
    {"--fp", "3000", "--a", "0.5", "--a-prime", "0.25"}};
const char* const kIds[] = {"paper", "thick", "loaded"};

}  // namespace

TEST_GROUP(StudyWalls){};

// The portfolio is the single-wall study run per wall: same rows (after the wall column), same cases and capacities.
TEST(StudyWalls, EachWallGetsTheRowsAndStatisticsOfItsOwnStudy) {
  const TempDir tmp;
  const std::string walls = tmp.file("walls.csv"), dir = tmp.file("portfolio");
  write_text(walls, kPortfolio);
  const ProcessResult r = run_rockwatch(study_args(dir, {"--walls", walls}));
  check_ok(r);
  STRCMP_CONTAINS("3 from", r.out.c_str());
  CHECK_FALSE(fs::exists(dir + "/table3.md"));
  const std::vector<std::string> rows = lines_of(read_all(dir + "/runs.csv"));
  STRCMP_EQUAL("wall,record,component,vertical,r,pga_g,collapsed,t_collapse_s,t_exceed_s,max_abs_x_m,n_impacts,run,"
               "error",
               rows.front().c_str());
  LONGS_EQUAL(1 + 3 * 10, rows.size());
  const nlohmann::json summary = nlohmann::json::parse(read_all(dir + "/summary.json"));
  LONGS_EQUAL(3, summary["walls"].size());
  LONGS_EQUAL(30, summary["runs"]["total"].get<int>());
  const std::vector<std::string> table = lines_of(read_all(dir + "/walls_summary.csv"));
  STRCMP_EQUAL("id,r,vertical,fit_mean_g,fit_std_g,lognormal_median_g,lognormal_beta,p_collapse_ntc2008,"
               "p_collapse_nzsee2016,allowable_pga_ntc2008_g,allowable_pga_nzsee2016_g",
               table.front().c_str());
  LONGS_EQUAL(1 + 3, table.size());  // one case per wall

  bool some_collapse = false;
  for (std::size_t w = 0; w < 3; ++w) {
    const std::string single = tmp.file(std::string("single_") + kIds[w]);
    const ProcessResult s = run_rockwatch(study_args(single, kWallOptions[w]));
    check_ok(s);
    const std::vector<std::string> single_rows = lines_of(read_all(single + "/runs.csv"));
    LONGS_EQUAL(11, single_rows.size());
    for (std::size_t i = 1; i < single_rows.size(); ++i) {
      STRCMP_EQUAL((std::string(kIds[w]) + "," + single_rows[i]).c_str(), rows[w * 10 + i].c_str());
      some_collapse = some_collapse || single_rows[i].find(",true,") != std::string::npos;
    }
    const nlohmann::json one = nlohmann::json::parse(read_all(single + "/summary.json"));
    const nlohmann::json& entry = summary["walls"][w];
    STRCMP_EQUAL(kIds[w], entry["id"].get<std::string>().c_str());
    CHECK_TEXT(entry["cases"] == one["cases"], entry["cases"].dump().c_str());
    CHECK_TEXT(entry["capacities"] == one["capacities"], entry["capacities"].dump().c_str());
    CHECK_TEXT(entry["wall"] == one["plan"]["wall"], entry["wall"].dump().c_str());
    DOUBLES_EQUAL((one["plan"]["wall"]["h1_m"].get<double>() + one["plan"]["wall"]["h2_m"].get<double>()) /
                      one["plan"]["wall"]["b_m"].get<double>(),
                  entry["h_over_b"].get<double>(), 1e-12);
    // walls_summary.csv: the same numbers as summary.json (empty where it says null).
    const std::vector<std::string> f = split_fields(table[1 + w], ',');
    LONGS_EQUAL(11, f.size());
    STRCMP_EQUAL(kIds[w], f[0].c_str());
    STRCMP_EQUAL("exp", f[1].c_str());
    STRCMP_EQUAL("false", f[2].c_str());
    const nlohmann::json& c = one["cases"][0];
    const auto same = [](const nlohmann::json& v, const std::string& text) {
      if (v.is_null()) return text.empty();
      return !text.empty() && std::stod(text) == v.get<double>();
    };
    CHECK_TEXT(same(c["fit_mean_g"], f[3]), table[1 + w].c_str());
    CHECK_TEXT(same(c["fit_std_g"], f[4]), table[1 + w].c_str());
    CHECK_TEXT(same(c["lognormal"]["median_g"], f[5]), table[1 + w].c_str());
    CHECK_TEXT(same(c["lognormal"]["beta"], f[6]), table[1 + w].c_str());
    CHECK_TEXT(same(c["p_collapse_ntc2008"], f[7]), table[1 + w].c_str());
    CHECK_TEXT(same(c["p_collapse_nzsee2016"], f[8]), table[1 + w].c_str());
    CHECK_TEXT(same(one["capacities"]["ntc2008_g"], f[9]), table[1 + w].c_str());
    CHECK_TEXT(same(one["capacities"]["nzsee2016_g"], f[10]), table[1 + w].c_str());
  }
  CHECK_TEXT(some_collapse, "the mini plan should collapse some wall at some level");
  // The paper's wall has the paper's capacities (SPEC section 5 regression values).
  DOUBLES_EQUAL(0.138984, summary["walls"][0]["capacities"]["ntc2008_g"].get<double>(), 5e-7);
  DOUBLES_EQUAL(0.180193, summary["walls"][0]["capacities"]["nzsee2016_g"].get<double>(), 5e-7);
}

// runs.csv is the checkpoint of a portfolio too: rows lost (an interrupted study) are run again by --resume, and the
// files come out the same.
TEST(StudyWalls, ResumeAfterLosingRowsGivesTheSameFiles) {
  const TempDir tmp;
  const std::string walls = tmp.file("walls.csv"), dir = tmp.file("portfolio");
  write_text(walls, kPortfolio);
  check_ok(run_rockwatch(study_args(dir, {"--walls", walls})));
  const std::string runs = read_all(dir + "/runs.csv"), summary = read_all(dir + "/summary.json");
  const std::string table = read_all(dir + "/walls_summary.csv");
  const std::vector<std::string> rows = lines_of(runs);
  std::string kept;
  for (std::size_t i = 0; i < rows.size(); i += (i == 0 ? 1 : 2)) kept += rows[i] + "\n";  // header, every other row
  write_text(dir + "/runs.csv", kept);
  const ProcessResult r = run_rockwatch(study_args(dir, {"--walls", walls, "--resume"}));
  check_ok(r);
  STRCMP_CONTAINS("resuming: 15 of 30 analyses done", r.err.c_str());
  CHECK_TRUE(runs == read_all(dir + "/runs.csv"));
  CHECK_TRUE(summary == read_all(dir + "/summary.json"));
  CHECK_TRUE(table == read_all(dir + "/walls_summary.csv"));

  // Another portfolio in the same directory is another plan.
  write_text(walls, std::string(kPortfolio) + "extra,0.2,,,,,,\n");
  const ProcessResult other = run_rockwatch(study_args(dir, {"--walls", walls, "--resume"}));
  LONGS_EQUAL(2, other.exit_status);
  STRCMP_CONTAINS("planned differently", other.err.c_str());
  STRCMP_CONTAINS("walls", other.err.c_str());
}

// The shipped example: a few dozen valid walls spanning h/b 12 to 40 (the paper's wall among them), with and without
// overburden; one level of one record is enough to check it runs, and the figure of medians vs h/b is drawn.
TEST(StudyWalls, TheExamplePortfolioRunsAndIsPlotted) {
  const TempDir tmp;
  const std::string dir = tmp.file("example");
  const ProcessResult r =
      run_rockwatch({"study", "--suite", kSuite, "--sets", "1", "--pga", "0.15:0.35:0.05", "--r", "exp", "--vertical",
                     "without", "--walls", kExamplePortfolio, "--out", dir, "--plots"});
  check_ok(r);
  const nlohmann::json summary = nlohmann::json::parse(read_all(dir + "/summary.json"));
  const nlohmann::json& walls = summary["walls"];
  CHECK_TEXT(walls.size() >= 24 && walls.size() <= 60, std::to_string(walls.size()).c_str());
  double lo = 1e9, hi = 0.0;
  bool paper = false, loaded = false;
  for (const nlohmann::json& w : walls) {
    lo = std::min(lo, w["h_over_b"].get<double>());
    hi = std::max(hi, w["h_over_b"].get<double>());
    paper = paper || (w["wall"]["b_m"] == 0.1 && w["wall"]["h1_m"] == 1.75 && w["wall"]["fp_npm"] == 0.0);
    loaded = loaded || w["wall"]["fp_npm"].get<double>() > 0.0;
  }
  CHECK_TEXT(lo <= 15.0 && hi >= 35.0, (std::to_string(lo) + " " + std::to_string(hi)).c_str());
  CHECK_TRUE(paper);
  CHECK_TRUE(loaded);
  CHECK_TEXT(fs::file_size(dir + "/walls_fragility.png") > 10 * 1024, r.out.c_str());
  STRCMP_CONTAINS("walls_fragility.png", r.out.c_str());
}

// Every bad row names the file and the line, and what was expected; nothing is run.
TEST(StudyWalls, BadRowsAreRefusedNamingFileAndLine) {
  const TempDir tmp;
  const std::string walls = tmp.file("walls.csv"), dir = tmp.file("out");
  const std::string header = "id,b,h1,h2,rho,fp,a,a_prime\n";
  struct Case {
    std::string text;
    std::vector<std::string> mentions;
  };
  const std::vector<Case> cases{
      {"id,b,h1,h2\nw,0.1,1,1\n", {walls + ":1:", "expected the header id,b,h1,h2,rho,fp,a,a_prime"}},
      {header + "ok,,,,,,,\nw,0.1x,,,,,,\n", {walls + ":3:", "b must be a finite number", "0.1x"}},
      {header + "w,0.1,,,,,\n", {walls + ":2:", "expected 8 comma-separated fields"}},
      {header + "w,,,,,,,\nw,,,,,,,\n", {walls + ":3:", "id w appears twice"}},
      {header + "w x,,,,,,,\n", {walls + ":2:", "id must hold only letters"}},
      {header + ",,,,,,,\n", {walls + ":2:", "id must be 1 to 64 characters"}},
      {header + "w,0.1,0.05,,,,,\n", {walls + ":2:", "wall w: h1"}},
      {header + "w,,,,,-5,,\n", {walls + ":2:", "wall w: fp"}},
      {header + "w,,,,,,nan,\n", {walls + ":2:", "a must be a finite number"}},
      {header, {walls, "no walls"}},
      {"", {walls, "expected the header"}},
  };
  for (const Case& c : cases) {
    write_text(walls, c.text);
    std::vector<std::string> args = study_args(dir, {"--walls", walls});
    args.erase(args.begin());
    expect_command_rejected("study", args, c.mentions);
    CHECK_FALSE(fs::exists(dir));
  }
  write_text(walls, header + "w,,,,,,,\n");
  std::vector<std::string> args = study_args(dir, {"--walls", walls, "--b", "0.2"});
  args.erase(args.begin());
  expect_command_rejected("study", args, {"--walls", "--b"});
  expect_command_rejected("study", {"--walls", tmp.file("missing.csv"), "--out", dir}, {"--walls", "missing.csv"});
  expect_command_rejected("study", {"--walls", walls, "--alarms", "--observer", "--out", dir}, {"--walls", "--observer"});
}

}  // namespace unity_test_study_walls
