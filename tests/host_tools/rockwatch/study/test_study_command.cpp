// `rockwatch study` end to end on a mini study of the shipped suite (set 1, 5 PGA levels: 2 records x 5 x 2 r x 2
// vertical = 40 analyses, well under a second): runs.csv and summary.json checked against each other, the files
// independent of --jobs, --resume after losing half the rows (and after a real SIGINT) giving the same files, a
// resume with another plan refused, the default suite found without a path, --records with real AT2 files, the
// --dt-check, the plots, and every invalid option rejected with a message naming it (exit 2, nothing written).
#include <algorithm>
#include <signal.h>  // kill (POSIX)
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "ci_skip.hpp"
#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "common/plots/python_plot.hpp"
#include "rockwatch/options/option_values.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

using rockwatch::options::split_fields;
using rockwatch::test::describe;
using rockwatch::test::EnvOverride;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;
using rockwatch::test::spawn_rockwatch;
using rockwatch::test::TempDir;
using rockwatch::test::wait_status;
using rockwatch::test::write_text;
namespace fs = std::filesystem;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;
const char* const kHeader =
    "record,component,vertical,r,pga_g,collapsed,t_collapse_s,t_exceed_s,max_abs_x_m,n_impacts,run,error";
const std::vector<double> kLevels{0.15, 0.16, 0.17, 0.18, 0.19};

// The mini study's options (without the command name, as expect_command_rejected takes them).
std::vector<std::string> mini_args(const std::string& out) {
  return {"--suite", kSuite, "--sets", "1", "--pga", "0.15:0.19:0.01", "--out", out};
}

std::vector<std::string> mini_study(const std::string& out) {
  std::vector<std::string> args{"study"};
  for (const std::string& a : mini_args(out)) args.push_back(a);
  return args;
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// runs.csv as header and rows of fields (the mini study's texts hold no commas or quotes).
struct Runs {
  std::string header;
  std::vector<std::vector<std::string>> rows;
};

Runs read_runs(const std::string& path) {
  Runs runs;
  std::vector<std::string> lines = split_fields(slurp(path), '\n');
  CHECK_TRUE(!lines.empty() && lines.back().empty());  // ends with a newline
  lines.pop_back();
  runs.header = lines.front();
  for (std::size_t i = 1; i < lines.size(); ++i) runs.rows.push_back(split_fields(lines[i], ','));
  return runs;
}

void check_ok(const ProcessResult& r) {
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
}

// The summary says what runs.csv holds: per case the runs, the survival rate per level and the smallest PGA that
// collapsed, recomputed from the rows.
void check_summary_against_runs(const nlohmann::json& summary, const Runs& runs) {
  const std::set<std::string> required{
      "vertical",          "r",          "r_value",   "n_runs",  "min_pga_collapse_g", "fit_mean_g", "fit_std_g",
      "survival",          "lognormal",  "resurrections",        "p_collapse_ntc2008",  "p_collapse_nzsee2016",
      "p_collapse_ntc2008_lognormal",    "p_collapse_ntc2008_empirical",             "p_collapse_nzsee2016_lognormal",
      "p_collapse_nzsee2016_empirical",  "fit_ok"};
  const nlohmann::json& cases = summary["cases"];
  LONGS_EQUAL(4, cases.size());
  const char* const order[][2] = {{"ana", "false"}, {"ana", "true"}, {"exp", "false"}, {"exp", "true"}};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const nlohmann::json& c = cases[i];
    for (const std::string& key : required) CHECK_TEXT(c.contains(key), key.c_str());
    for (const char* key : {"median_g", "beta", "median_ci90_g"}) CHECK_TEXT(c["lognormal"].contains(key), key);
    STRCMP_EQUAL(order[i][0], c["r"].get<std::string>().c_str());
    const bool vertical = std::string(order[i][1]) == "true";
    CHECK_EQUAL(vertical, c["vertical"].get<bool>());
    CHECK_TEXT(c["r_value"].get<double>() > 0.8 && c["r_value"].get<double>() < 1.0, c.dump().c_str());

    std::map<double, std::pair<int, int>> per_level;  // pga -> (runs, collapsed)
    std::optional<double> min_collapse;
    for (const std::vector<std::string>& row : runs.rows) {
      if (row[3] != order[i][0] || row[2] != order[i][1]) continue;
      const double pga = std::stod(row[4]);
      const bool collapsed = row[5] == "true";
      ++per_level[pga].first;
      per_level[pga].second += collapsed ? 1 : 0;
      if (collapsed && (!min_collapse || pga < *min_collapse)) min_collapse = pga;
    }
    LONGS_EQUAL(10, c["n_runs"].get<int>());
    if (min_collapse) {
      DOUBLES_EQUAL(*min_collapse, c["min_pga_collapse_g"].get<double>(), 0.0);
    } else {
      CHECK_TEXT(c["min_pga_collapse_g"].is_null(), c.dump().c_str());
    }
    const nlohmann::json& survival = c["survival"];
    LONGS_EQUAL(kLevels.size(), survival.size());
    for (std::size_t k = 0; k < survival.size(); ++k) {
      const double pga = survival[k]["pga_g"].get<double>();
      DOUBLES_EQUAL(kLevels[k], pga, 0.0);
      const auto [n, collapsed] = per_level.at(pga);
      LONGS_EQUAL(2, n);
      DOUBLES_EQUAL(static_cast<double>(n - collapsed) / n, survival[k]["survival_rate"].get<double>(), 1e-15);
    }
    if (!c["fit_ok"].get<bool>()) {
      CHECK_TRUE(c["fit_mean_g"].is_null() && c["p_collapse_ntc2008"].is_null());
    }
  }
}

void check_mini_study_files(const std::string& dir) {
  const Runs runs = read_runs(dir + "/runs.csv");
  STRCMP_EQUAL(kHeader, runs.header.c_str());
  LONGS_EQUAL(40, runs.rows.size());
  for (std::size_t i = 0; i < runs.rows.size(); ++i) {
    const std::vector<std::string>& row = runs.rows[i];
    LONGS_EQUAL(12, row.size());
    STRCMP_EQUAL("set01", row[0].c_str());
    CHECK_TRUE(row[1] == "X" || row[1] == "Y");
    STRCMP_EQUAL(std::to_string(i).c_str(), row[10].c_str());  // in run order
    CHECK_TRUE(row[5] == "true" || row[5] == "false");
    CHECK_EQUAL(row[5] == "true", !row[6].empty());  // a collapse has its time
    CHECK_TRUE(std::stod(row[8]) >= 0.0);
    CHECK_TRUE(row[11].empty());
  }
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir + "/summary.json"));
  check_summary_against_runs(summary, runs);
  DOUBLES_EQUAL(0.139, summary["capacities"]["ntc2008_g"].get<double>(), 0.0005);
  DOUBLES_EQUAL(0.180, summary["capacities"]["nzsee2016_g"].get<double>(), 0.0005);
  CHECK_FALSE(summary["dt_check"]["enabled"].get<bool>());
  const nlohmann::json& plan = summary["plan"];
  LONGS_EQUAL(2, plan["records"].size());
  LONGS_EQUAL(5, plan["pga_g"].size());
  STRCMP_EQUAL("linear", plan["model"].get<std::string>().c_str());
  DOUBLES_EQUAL(2.0, plan["kappa"].get<double>(), 0.0);
  DOUBLES_EQUAL(0.1, plan["wall"]["b_m"].get<double>(), 0.0);

  const std::string table = slurp(dir + "/table3.md");
  for (const char* text : {"| r_ana H-only |", "| r_ana H+V |", "| r_exp H-only |", "| r_exp H+V |", "0.221", "0.055",
                           "0.271", "0.045", "not public", "npr9998-2015", "0.139", "0.180"}) {
    STRCMP_CONTAINS(text, table.c_str());
  }
  const nlohmann::json state = nlohmann::json::parse(slurp(dir + "/study.json"));
  STRCMP_EQUAL("complete", state["state"].get<std::string>().c_str());
  LONGS_EQUAL(40, state["runs_done"].get<int>());
  CHECK_TRUE(state["plan"] == plan);
}

}  // namespace

TEST_GROUP(StudyCommand){};

// One mini study checked from every side, then again with two threads and resumed after losing half its rows.
TEST(StudyCommand, MiniStudyIsConsistentAndIndependentOfJobsAndResume) {
  const TempDir tmp;
  const std::string one = tmp.file("one"), two = tmp.file("two");
  const ProcessResult r = run_rockwatch(with(mini_study(one), {"--jobs", "1"}));
  check_ok(r);
  check_mini_study_files(one);
  for (const char* text : {"Case r_ana H-only", "Case r_exp H+V", "min PGA collapse", "normal fit", "P(collapse)",
                           "lognormal", "resurrections", "runs.csv", "summary.json", "table3.md", "(--suite)"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
  STRCMP_CONTAINS("study: 40/40 analyses (100 %)", r.err.c_str());  // progress lines when stderr is not a terminal

  check_ok(run_rockwatch(with(mini_study(two), {"--jobs", "2"})));
  for (const char* name : {"runs.csv", "summary.json", "table3.md"}) {
    CHECK_TEXT(slurp(one + "/" + name) == slurp(two + "/" + name), name);
  }

  // Half the rows lost: --resume runs only those and ends with the same files.
  const std::string runs = slurp(one + "/runs.csv"), summary = slurp(one + "/summary.json");
  const std::vector<std::string> lines = split_fields(runs, '\n');
  std::string half = lines[0] + "\n";
  for (std::size_t i = 1; i + 1 < lines.size(); i += 2) half += lines[i] + "\n";
  write_text(one + "/runs.csv", half);
  fs::remove(one + "/summary.json");
  const ProcessResult resumed = run_rockwatch(with(mini_study(one), {"--jobs", "2", "--resume"}));
  check_ok(resumed);
  STRCMP_CONTAINS("resuming: 20 of 40 analyses done", resumed.err.c_str());
  CHECK_TRUE(slurp(one + "/runs.csv") == runs);
  CHECK_TRUE(slurp(one + "/summary.json") == summary);
}

TEST(StudyCommand, ResumeRefusesAnotherPlanAndAnOccupiedDirectoryNeedsResumeOrForce) {
  const TempDir tmp;
  const std::string dir = tmp.file("study");
  check_ok(run_rockwatch(mini_study(dir)));
  const std::string runs = slurp(dir + "/runs.csv");
  rockwatch::test::expect_command_rejected(
      "study", {"--suite", kSuite, "--sets", "1", "--pga", "0.15:0.18:0.01", "--out", dir, "--resume"},
      {"--resume", "planned differently", "pga_g", "0.15 to 0.19 g (5 levels)", "0.15 to 0.18 g (4 levels)",
       "--force"});
  rockwatch::test::expect_command_rejected(
      "study", {"--suite", kSuite, "--sets", "1", "--pga", "0.15:0.19:0.01", "--r", "exp", "--out", dir, "--resume"},
      {"restitutions"});
  rockwatch::test::expect_command_rejected("study", mini_args(dir), {"already holds a study", "--resume", "--force"});
  CHECK_TRUE(slurp(dir + "/runs.csv") == runs);  // refused before touching anything

  // A runs.csv of another study is refused by its rows, not taken as this one's results.
  std::string edited = runs;
  edited.replace(edited.find("set01,X,false,ana,0.15"), 22, "set01,Y,false,ana,0.15");
  write_text(dir + "/runs.csv", edited);
  rockwatch::test::expect_command_rejected("study", with(mini_args(dir), {"--resume"}),
                                           {dir + "/runs.csv:2", "another study"});

  // --force starts again.
  const ProcessResult forced = run_rockwatch(with(mini_study(dir), {"--force"}));
  check_ok(forced);
  CHECK_TRUE(slurp(dir + "/runs.csv") == runs);
}

TEST(StudyCommand, FindsTheShippedSuiteWithoutAPath) {
  const TempDir tmp;
  {
    const EnvOverride unset("ROCKWATCH_SUITE_DIR", nullptr);
    const ProcessResult r = run_rockwatch({"study", "--sets", "1", "--pga", "0.2:0.2:0.01", "--out", tmp.file("a")});
    check_ok(r);
    STRCMP_CONTAINS("the source tree the tool was built from", r.out.c_str());
    STRCMP_CONTAINS("suite npr9998-2015, set 1", r.out.c_str());
  }
  {
    const EnvOverride chosen("ROCKWATCH_SUITE_DIR", kSuite.c_str());
    const ProcessResult r = run_rockwatch({"study", "--sets", "1", "--pga", "0.2:0.2:0.01", "--out", tmp.file("b")});
    check_ok(r);
    STRCMP_CONTAINS("found in $ROCKWATCH_SUITE_DIR", r.out.c_str());
    CHECK_TRUE(slurp(tmp.file("a") + "/runs.csv") == slurp(tmp.file("b") + "/runs.csv"));
  }
  {
    const EnvOverride wrong("ROCKWATCH_SUITE_DIR", tmp.path().c_str());
    rockwatch::test::expect_command_rejected("study", {"--out", tmp.file("c")},
                                             {"$ROCKWATCH_SUITE_DIR", "holds no suite", "--suite"});
    CHECK_FALSE(fs::exists(tmp.file("c")));
  }
}

TEST(StudyCommand, RecordsListOfRealRecords) {
  const TempDir tmp;
  // Paths relative to the list's directory, a comment, a blank line.
  const std::string records = fs::relative(rockwatch::test::record_path(""), tmp.path()).string();
  const std::string list = tmp.file("records.txt");
  write_text(list, "# El Centro 1940 with its vertical, and Northridge without one\n\n" + records +
                       "/RSN6_IMPVALL.I_I-ELC180-hor1.AT2 " + records + "/RSN6_IMPVALL.I_I-ELC-UP.AT2\n" + records +
                       "/RSN960_NORTHR_LOS270.AT2  # no vertical partner\n");
  const ProcessResult r = run_rockwatch({"study", "--records", list, "--vertical", "without", "--pga", "0.1:0.3:0.1",
                                         "--out", tmp.file("study")});
  check_ok(r);
  STRCMP_CONTAINS(("2 records of " + list + " (1 with a vertical partner)").c_str(), r.out.c_str());
  const Runs runs = read_runs(tmp.file("study/runs.csv"));
  LONGS_EQUAL(2 * 3 * 2, runs.rows.size());
  STRCMP_EQUAL("RSN6_IMPVALL.I_I-ELC180-hor1.AT2", runs.rows.front()[0].c_str());
  STRCMP_EQUAL("", runs.rows.front()[1].c_str());
  STRCMP_EQUAL("RSN960_NORTHR_LOS270.AT2", runs.rows.back()[0].c_str());
  const nlohmann::json summary = nlohmann::json::parse(slurp(tmp.file("study/summary.json")));
  STRCMP_EQUAL(list.c_str(), summary["records_source"]["list"].get<std::string>().c_str());
  LONGS_EQUAL(2, summary["cases"].size());

  // The record with its partner runs with the vertical too.
  write_text(tmp.file("pair.txt"), records + "/RSN6_IMPVALL.I_I-ELC180-hor1.AT2 " + records +
                                       "/RSN6_IMPVALL.I_I-ELC-UP.AT2\n");
  check_ok(run_rockwatch({"study", "--records", tmp.file("pair.txt"), "--pga", "0.2:0.3:0.1", "--r", "exp", "--out",
                          tmp.file("pair")}));
  LONGS_EQUAL(4, read_runs(tmp.file("pair/runs.csv")).rows.size());

  // Errors name LIST:line.
  rockwatch::test::expect_command_rejected("study", {"--records", list, "--out", tmp.file("x")},
                                           {list + ":4", "no vertical partner", "--vertical without"});
  write_text(tmp.file("missing.txt"), "# one\n" + records + "/RSN6_IMPVALL.I_I-ELC180-hor1.AT2\nnot-there.AT2\n");
  rockwatch::test::expect_command_rejected(
      "study", {"--records", tmp.file("missing.txt"), "--vertical", "without", "--out", tmp.file("x")},
      {tmp.file("missing.txt") + ":3", "not-there.AT2"});
  write_text(tmp.file("three.txt"), "a.AT2 b.AT2 c.AT2\n");
  rockwatch::test::expect_command_rejected("study", {"--records", tmp.file("three.txt"), "--out", tmp.file("x")},
                                           {tmp.file("three.txt") + ":1", "PATH [VERTICAL_PATH]", "3 fields"});
  write_text(tmp.file("empty.txt"), "# nothing\n\n");
  rockwatch::test::expect_command_rejected("study", {"--records", tmp.file("empty.txt"), "--out", tmp.file("x")},
                                           {"--records", "lists no records"});
  CHECK_FALSE(fs::exists(tmp.file("x")));
}

TEST(StudyCommand, DtCheckComparesWithTheReferenceStepAndReportsTheConvergence) {
  const TempDir tmp;
  const std::string dir = tmp.file("study");
  const ProcessResult r = run_rockwatch(with(mini_study(dir), {"--dt-check"}));
  check_ok(r);
  const Runs runs = read_runs(dir + "/runs.csv");
  STRCMP_EQUAL((std::string(kHeader).substr(0, std::string(kHeader).size() - 6) +
                ",collapsed_reference,max_abs_x_reference_m,error")
                   .c_str(),
               runs.header.c_str());
  std::size_t flips = 0, survivors = 0;
  std::vector<double> rel;
  for (const std::vector<std::string>& row : runs.rows) {
    LONGS_EQUAL(14, row.size());
    CHECK_TRUE(row[11] == "true" || row[11] == "false");
    flips += row[11] != row[5] ? 1 : 0;
    const double x = std::stod(row[8]), x_ref = std::stod(row[12]);
    if (row[5] == "false" && row[11] == "false" && x_ref > 0.0) {
      ++survivors;
      rel.push_back(std::fabs(x - x_ref) / x_ref);
    }
  }
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir + "/summary.json"));
  const nlohmann::json& d = summary["dt_check"];
  CHECK_TRUE(d["enabled"].get<bool>());
  LONGS_EQUAL(flips, d["flips"].get<std::size_t>());
  LONGS_EQUAL(flips, d["flipped_runs"].size());
  // The reference: half the default max step of 1 ms.
  DOUBLES_EQUAL(0.0005, d["reference_step_s"].get<double>(), 0.0);
  LONGS_EQUAL(survivors, d["survivors_compared"].get<std::size_t>());
  CHECK_TRUE(survivors > 0);
  std::sort(rel.begin(), rel.end());
  DOUBLES_EQUAL(rel.back(), d["max_abs_x_rel_error"]["max"].get<double>(), 0.0);
  const double h = 0.5 * double(rel.size() - 1);  // type 7 median
  const auto lo = static_cast<std::size_t>(h);
  const double median = rel[lo] + (h - double(lo)) * (rel[std::min(lo + 1, rel.size() - 1)] - rel[lo]);
  DOUBLES_EQUAL(median, d["max_abs_x_rel_error"]["median"].get<double>(), 1e-15);
  STRCMP_CONTAINS("against the double engine at 5e-04 s", r.out.c_str());
  STRCMP_CONTAINS("survivors' max |x|", r.out.c_str());
  // The plan includes the check: a resume without it is another study.
  rockwatch::test::expect_command_rejected("study", with(mini_args(dir), {"--resume"}), {"dt_check"});
}

TEST(StudyCommand, PlotsTheFiguresPerCase) {
  if (!rockwatch::cli::find_matplotlib_python()) {
    if (rockwatch::test::skip_or_fail_in_ci("no Python with matplotlib on this machine")) return;
  }
  const TempDir tmp;
  const std::string dir = tmp.file("study");
  const ProcessResult r = run_rockwatch(with(mini_study(dir), {"--r", "exp", "--vertical", "with", "--plots"}));
  check_ok(r);
  for (const char* name : {"fig6_collapse_map_exp_HV.png", "fig7_max_displacement_exp_HV.png"}) {
    CHECK_TEXT(fs::file_size(dir + "/" + name) > 10 * 1024, name);
    STRCMP_CONTAINS(name, r.out.c_str());
  }
  CHECK_FALSE(fs::exists(dir + "/fig6_collapse_map_exp_H.png"));
}

// Ctrl-C mid-study: the finished analyses are kept, the exit status is 130, and --resume finishes the study. The
// signal is sent once the first progress line (10 %) is out; should the study have ended by then, there is
// nothing to check.
TEST(StudyCommand, InterruptKeepsTheFinishedRunsAndResumeCompletesThem) {
  const TempDir tmp;
  const std::string dir = tmp.file("study"), err = tmp.file("stderr");
  // 8 records x 20 levels at a fine step: long enough to be interrupted, short enough for a test.
  const std::vector<std::string> args{"study",   "--suite", kSuite, "--sets",     "1-4",    "--r",   "exp",
                                      "--vertical", "without", "--max-step", "0.0002", "--jobs", "1", "--out", dir};
  const pid_t pid = spawn_rockwatch(args, "/dev/null", err);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  bool signalled = false;
  while (std::chrono::steady_clock::now() < deadline) {
    if (rockwatch::process::poll_status(pid)) {
      std::printf("\nnote: the study ended before it could be interrupted: interrupt check skipped\n");
      return;
    }
    std::ifstream in(err);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find("study: ") != std::string::npos) {
      rockwatch::process::send_signal(pid, SIGINT);
      signalled = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  CHECK_TRUE(signalled);
  const int status = wait_status(pid);
  const std::string message = slurp(err);
  CHECK_TEXT(WIFEXITED(status), message.c_str());
  if (WEXITSTATUS(status) == 0) {
    std::printf("\nnote: the study ended before the signal arrived: interrupt check skipped\n");
    return;
  }
  CHECK_EQUAL_TEXT(130, WEXITSTATUS(status), message.c_str());
  STRCMP_CONTAINS("interrupted by SIGINT", message.c_str());
  STRCMP_CONTAINS("--resume", message.c_str());
  const nlohmann::json state = nlohmann::json::parse(slurp(dir + "/study.json"));
  STRCMP_EQUAL("interrupted", state["state"].get<std::string>().c_str());
  const std::size_t done = read_runs(dir + "/runs.csv").rows.size();
  CHECK_TEXT(done > 0 && done < 160, std::to_string(done).c_str());
  LONGS_EQUAL(done, state["runs_done"].get<std::size_t>());
  CHECK_FALSE(fs::exists(dir + "/summary.json"));

  std::vector<std::string> resume = args;
  resume.back() = dir;
  resume.emplace_back("--resume");
  const ProcessResult r = run_rockwatch(resume);
  check_ok(r);
  STRCMP_CONTAINS(("resuming: " + std::to_string(done) + " of 160 analyses done").c_str(), r.err.c_str());
  LONGS_EQUAL(160, read_runs(dir + "/runs.csv").rows.size());
  STRCMP_EQUAL("complete", nlohmann::json::parse(slurp(dir + "/study.json"))["state"].get<std::string>().c_str());
}

TEST(StudyCommand, HelpListsTheOptionsAndTheFiles) {
  const ProcessResult r = run_rockwatch({"study", "--help"});
  check_ok(r);
  for (const char* text : {"--suite", "--records", "--sets", "--wall", "--b", "--pga", "--r", "--vertical", "--model",
                           "--kappa", "--max-step", "--jobs", "--dt-check", "--out", "--plots", "--resume", "--force",
                           "runs.csv", "summary.json", "table3.md", "study.json", "fig6_collapse_map", "ROCKWATCH_SUITE_DIR",
                           "0.11:0.30:0.01", "130"}) {
    STRCMP_CONTAINS(text, r.out.c_str());
  }
  STRCMP_CONTAINS("study", run_rockwatch({"--help"}).out.c_str());
}

namespace {

// Every rejection names the option, and nothing is written: the directory is not even created.
void expect_rejected(const std::vector<std::string>& options, const std::vector<std::string>& mentions) {
  const TempDir tmp;
  const std::string dir = tmp.file("study");
  std::vector<std::string> args{"--suite", kSuite, "--out", dir};
  args.insert(args.end(), options.begin(), options.end());
  rockwatch::test::expect_command_rejected("study", args, mentions);
  CHECK_TEXT(!fs::exists(dir), dir.c_str());
}

}  // namespace

TEST_GROUP(StudyRejects){};

TEST(StudyRejects, MissingOut) {
  rockwatch::test::expect_command_rejected("study", {"--suite", kSuite, "--sets", "1"}, {"--out DIR is required"});
}
TEST(StudyRejects, PgaDescending) {
  expect_rejected({"--pga", "0.3:0.1:0.01"}, {"--pga", "FROM must not exceed TO", "'0.3:0.1:0.01'"});
}
TEST(StudyRejects, PgaStepZero) { expect_rejected({"--pga", "0.1:0.3:0"}, {"--pga", "STEP must be > 0"}); }
TEST(StudyRejects, PgaNotThreeNumbers) { expect_rejected({"--pga", "0.1:0.3"}, {"--pga", "FROM:TO:STEP"}); }
TEST(StudyRejects, PgaNotANumber) { expect_rejected({"--pga", "0.1:x:0.01"}, {"--pga", "TO is not a finite number"}); }
TEST(StudyRejects, PgaZero) { expect_rejected({"--pga", "0:0.3:0.01"}, {"--pga", "FROM must be > 0"}); }
TEST(StudyRejects, PgaTooManyLevels) { expect_rejected({"--pga", "0.1:30:0.0001"}, {"--pga", "levels", "raise STEP"}); }
TEST(StudyRejects, RBogus) { expect_rejected({"--r", "ana,bogus"}, {"--r", "'bogus'", "ana, exp, impulse"}); }
TEST(StudyRejects, RTwice) { expect_rejected({"--r", "exp,exp"}, {"--r", "exp twice"}); }
TEST(StudyRejects, VerticalMaybe) { expect_rejected({"--vertical", "maybe"}, {"--vertical", "'maybe'", "without,with"}); }
TEST(StudyRejects, JobsNegative) { expect_rejected({"--jobs", "-1"}, {"--jobs", "whole number from 0", "'-1'"}); }
TEST(StudyRejects, JobsNotWhole) { expect_rejected({"--jobs", "1.5"}, {"--jobs", "'1.5'"}); }
TEST(StudyRejects, SetsNotInTheSuite) { expect_rejected({"--sets", "99"}, {"--sets", "no set 99", "1-11"}); }
TEST(StudyRejects, SetsMalformed) { expect_rejected({"--sets", "3-1"}, {"--sets", "1,2 or 1-3", "'3-1'"}); }
TEST(StudyRejects, SuiteWithRecords) {
  expect_rejected({"--records", "list.txt"}, {"--suite cannot be combined with --records"});
}
TEST(StudyRejects, SetsWithRecords) {
  const TempDir tmp;
  rockwatch::test::expect_command_rejected("study", {"--records", "list.txt", "--sets", "1", "--out", tmp.file("x")},
                                           {"--sets", "--records"});
}
TEST(StudyRejects, UnitsForASuite) { expect_rejected({"--units", "g"}, {"--units", "--records"}); }
TEST(StudyRejects, KappaBelowOne) { expect_rejected({"--kappa", "0.5"}, {"--kappa", ">= 1"}); }
TEST(StudyRejects, ModelBogus) { expect_rejected({"--model", "quadratic"}, {"--model", "linear or full"}); }
TEST(StudyRejects, MaxStepZero) { expect_rejected({"--max-step", "0"}, {"--max-step", "> 0"}); }
TEST(StudyRejects, WallNotPaper) { expect_rejected({"--wall", "brick"}, {"--wall", "paper"}); }
TEST(StudyRejects, WallFieldInvalid) { expect_rejected({"--h1", "0.05"}, {"--h1", "greater than b"}); }
TEST(StudyRejects, ResumeWithForce) { expect_rejected({"--resume", "--force"}, {"--resume", "--force"}); }
TEST(StudyRejects, ResumeWithoutAStudy) {
  const TempDir tmp;
  rockwatch::test::expect_command_rejected("study", {"--suite", kSuite, "--out", tmp.path(), "--resume"},
                                           {"--resume", "holds no study"});
}
TEST(StudyRejects, OutIsAFile) {
  const TempDir tmp;
  write_text(tmp.file("file"), "x");
  rockwatch::test::expect_command_rejected("study", {"--suite", kSuite, "--sets", "1", "--out", tmp.file("file")},
                                           {"--out", "not a directory"});
}
TEST(StudyRejects, UnknownOption) { expect_rejected({"--frobnicate"}, {"--frobnicate"}); }
