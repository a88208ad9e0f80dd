// `rockwatch study --shard K/N` and `rockwatch study merge` end to end: merged shards give byte for byte the files of
// the study run in one piece (one wall and a portfolio, N = 1, 3 and more shards than some walls have runs), a
// shard interrupted by SIGTERM or killed outright (SIGKILL after a checkpoint) finishes with --resume, and the merge
// refuses a shard missing, given twice, of another plan, incomplete, or holding another shard's run.
#include <signal.h>  // kill (POSIX)
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "cli_test_files.hpp"
#include "rockwatch/options/option_values.hpp"

#include "cli_expect.hpp"  // brings in CppUTest, after every standard header

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_study_shards {

using rockwatch::options::split_fields;
using rockwatch::test::describe;
using rockwatch::test::EnvOverride;
using rockwatch::test::expect_command_rejected;
using rockwatch::test::ProcessResult;
using rockwatch::test::run_rockwatch;
using rockwatch::test::spawn_rockwatch;
using rockwatch::test::TempDir;
using rockwatch::test::wait_status;
using rockwatch::test::write_text;
namespace fs = std::filesystem;

namespace {

const std::string kSuite = ROCKWATCH_SHIPPED_SUITE_DIR;

// 2 records x 5 levels x 2 r x 2 vertical = 40 analyses.
std::vector<std::string> mini_plan() { return {"--suite", kSuite, "--sets", "1", "--pga", "0.15:0.23:0.02"}; }

std::vector<std::string> study(const std::vector<std::string>& plan, const std::string& out,
                               const std::vector<std::string>& more = {}) {
  std::vector<std::string> args{"study"};
  args.insert(args.end(), plan.begin(), plan.end());
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

void check_ok(const ProcessResult& r) {
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(0, r.signal, what.c_str());
  CHECK_EQUAL_TEXT(0, r.exit_status, what.c_str());
}

void check_same_file(const std::string& a, const std::string& b) {
  CHECK_TEXT(read_all(a) == read_all(b), (a + " differs from " + b).c_str());
}

// Runs the N shards of `plan` into tmp/shardK and merges them into tmp/merged; returns the merge's result.
ProcessResult shard_and_merge(const TempDir& tmp, const std::vector<std::string>& plan, std::size_t n) {
  std::vector<std::string> merge{"study", "merge", "--out", tmp.file("merged")};
  for (std::size_t k = 1; k <= n; ++k) {
    const std::string dir = tmp.file("shard" + std::to_string(k));
    const ProcessResult r = run_rockwatch(study(plan, dir, {"--shard", std::to_string(k) + "/" + std::to_string(n)}));
    check_ok(r);
    CHECK_FALSE(fs::exists(dir + "/summary.json"));
    const nlohmann::json state = nlohmann::json::parse(read_all(dir + "/shard.json"));
    STRCMP_EQUAL("complete", state["state"].get<std::string>().c_str());
    merge.push_back(dir);
  }
  return run_rockwatch(merge);
}

// As expect_command_rejected, for `rockwatch study merge ARGS`.
void expect_merge_rejected(const std::vector<std::string>& args, const std::vector<std::string>& mentions) {
  std::vector<std::string> full{"study", "merge"};
  full.insert(full.end(), args.begin(), args.end());
  const ProcessResult r = run_rockwatch(full);
  const std::string what = describe(r);
  CHECK_EQUAL_TEXT(2, r.exit_status, what.c_str());
  CHECK_TEXT(r.out.empty(), what.c_str());
  CHECK_TEXT(r.err.rfind("rockwatch study merge: error: ", 0) == 0, what.c_str());
  for (const std::string& m : mentions) CHECK_TEXT(r.err.find(m) != std::string::npos, (m + " in\n" + what).c_str());
}

std::size_t lines_in(const std::string& path) {
  const std::string text = read_all(path);
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace

TEST_GROUP(StudyShards){};

TEST(StudyShards, MergedShardsAreByteIdenticalToTheWholeStudy) {
  const TempDir tmp;
  const std::string whole = tmp.file("whole");
  check_ok(run_rockwatch(study(mini_plan(), whole)));
  for (const std::size_t n : {std::size_t{1}, std::size_t{3}}) {
    const TempDir shards;
    const ProcessResult r = shard_and_merge(shards, mini_plan(), n);
    check_ok(r);
    for (const char* name : {"runs.csv", "summary.json", "table3.md"}) check_same_file(whole + "/" + name, shards.file("merged/") + name);
    // The shards split the runs: each holds its share, together all of them.
    std::size_t rows = 0;
    for (std::size_t k = 1; k <= n; ++k) rows += lines_in(shards.file("shard" + std::to_string(k) + "/runs.csv")) - 1;
    LONGS_EQUAL(40, rows);
  }
}

TEST(StudyShards, AMergedPortfolioIsByteIdenticalToTheWholePortfolio) {
  const TempDir tmp;
  const std::string walls = tmp.file("walls.csv");
  write_text(walls, "id,b,h1,h2,rho,fp,a,a_prime\npaper,,,,,,,\nthick,0.14,1.5,1.6,,,,\nloaded,,,,,3000,0.5,0.5\n");
  std::vector<std::string> plan = mini_plan();
  plan.insert(plan.end(), {"--r", "exp", "--walls", walls});
  const std::string whole = tmp.file("whole");
  check_ok(run_rockwatch(study(plan, whole)));
  const TempDir shards;
  check_ok(shard_and_merge(shards, plan, 7));  // 7 does not divide a wall's 20 runs: shards straddle walls
  for (const char* name : {"runs.csv", "summary.json", "walls_summary.csv"}) {
    check_same_file(whole + "/" + name, shards.file("merged/") + name);
  }
}

// SIGTERM: the shard writes what it finished and exits 130; SIGKILL: the last checkpoint survives. Either way
// --resume finishes the shard, and the merge is the whole study.
TEST(StudyShards, AKilledShardResumesAndMergesToTheWholeStudy) {
  const TempDir tmp;
  // Fine steps, so a shard runs long enough to be stopped (about 0.5 s in a release build, alone).
  std::vector<std::string> plan{"--suite", kSuite, "--sets", "1-3", "--pga", "0.11:0.30:0.01", "--r", "exp",
                                "--vertical", "without", "--max-step", "0.0002", "--jobs", "1"};
  const EnvOverride checkpoints("ROCKWATCH_STUDY_CHECKPOINT_S", "0");  // a checkpoint between any two chunks
  for (const int sig : {SIGTERM, SIGKILL}) {
    const std::string dir = tmp.file(sig == SIGTERM ? "term" : "kill"), err = dir + ".err";
    const std::vector<std::string> args = study(plan, dir, {"--shard", "1/1"});
    const pid_t pid = spawn_rockwatch(args, "/dev/null", err);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    bool sent = false;
    while (std::chrono::steady_clock::now() < deadline) {
      if (rockwatch::process::poll_status(pid)) break;
      // Once some rows are checkpointed (runs.csv exists): stop it.
      if (fs::exists(dir + "/runs.csv")) {
        rockwatch::process::send_signal(pid, sig);
        sent = true;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    const int status = wait_status(pid);
    if (!sent || (WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
      std::printf("\nnote: the shard ended before the signal: kill check skipped\n");
      continue;
    }
    if (sig == SIGTERM) {
      CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 130, read_all(err).c_str());
      STRCMP_CONTAINS("--shard 1/1", read_all(err).c_str());
    } else {
      CHECK_TRUE(WIFSIGNALED(status));
    }
    const std::size_t kept = lines_in(dir + "/runs.csv") - 1;
    CHECK_TEXT(kept < 3 * 2 * 20, std::to_string(kept).c_str());
    const ProcessResult resumed = run_rockwatch(study(plan, dir, {"--shard", "1/1", "--resume"}));
    check_ok(resumed);
    STRCMP_CONTAINS(("resuming: " + std::to_string(kept) + " of 120 analyses done").c_str(), resumed.err.c_str());
    const std::string merged = dir + ".merged";
    check_ok(run_rockwatch({"study", "merge", "--out", merged, dir}));
    const std::string whole = tmp.file("whole");
    if (!fs::exists(whole)) check_ok(run_rockwatch(study(plan, whole)));
    for (const char* name : {"runs.csv", "summary.json", "table3.md"}) check_same_file(whole + "/" + name, merged + "/" + name);
  }
}

TEST(StudyShards, TheMergeRefusesShardsThatAreNotOneWholeStudy) {
  const TempDir tmp;
  for (std::size_t k = 1; k <= 3; ++k) {
    check_ok(run_rockwatch(study(mini_plan(), tmp.file("s" + std::to_string(k)), {"--shard", std::to_string(k) + "/3"})));
  }
  const std::string out = tmp.file("merged");
  expect_merge_rejected({"--out", out, tmp.file("s1"), tmp.file("s3")}, {"shard 2 of 3 missing"});
  expect_merge_rejected({"--out", out, tmp.file("s1"), tmp.file("s2"), tmp.file("s3"), tmp.file("s1")},
                          {"shard 1/3 is given twice"});
  // A shard of another plan (other PGA levels).
  std::vector<std::string> other = mini_plan();
  other[5] = "0.15:0.25:0.02";
  check_ok(run_rockwatch(study(other, tmp.file("other2"), {"--shard", "2/3"})));
  expect_merge_rejected({"--out", out, tmp.file("s1"), tmp.file("other2"), tmp.file("s3")},
                          {"not of one study"});
  // A shard of 1/2 among shards of 3.
  check_ok(run_rockwatch(study(mini_plan(), tmp.file("half"), {"--shard", "1/2"})));
  expect_merge_rejected({"--out", out, tmp.file("half"), tmp.file("s2"), tmp.file("s3")},
                          {"not of one study"});
  // Rows lost: the shard is short.
  const std::string runs = read_all(tmp.file("s2/runs.csv"));
  write_text(tmp.file("s2/runs.csv"), runs.substr(0, runs.rfind('\n', runs.size() - 2) + 1));
  expect_merge_rejected({"--out", out, tmp.file("s1"), tmp.file("s2"), tmp.file("s3")},
                          {"s2: shard 2/3 holds 12 of its 13 analyses", "--resume"});
  // A row of shard 1 put into shard 2.
  const std::string first_row = split_fields(read_all(tmp.file("s1/runs.csv")), '\n')[1];
  write_text(tmp.file("s2/runs.csv"), runs + first_row + "\n");
  expect_merge_rejected({"--out", out, tmp.file("s1"), tmp.file("s2"), tmp.file("s3")},
                          {"runs.csv:15:", "belongs to another shard than 2/3"});
  write_text(tmp.file("s2/runs.csv"), runs);
  // Not a shard; an interrupted shard.
  expect_merge_rejected({"--out", out, tmp.file("s1"), tmp.file("nothing")}, {"shard.json"});
  nlohmann::json state = nlohmann::json::parse(read_all(tmp.file("s3/shard.json")));
  state["state"] = "interrupted";
  write_text(tmp.file("s3/shard.json"), state.dump(2));
  expect_merge_rejected({"--out", out, tmp.file("s1"), tmp.file("s2"), tmp.file("s3")},
                          {"shard 3/3 is interrupted", "--resume"});
  CHECK_FALSE(fs::exists(out));
  // The options themselves.
  expect_command_rejected("study", {"--shard", "4/3", "--out", out}, {"--shard must be K/N"});
  expect_command_rejected("study", {"--shard", "0/3", "--out", out}, {"--shard must be K/N"});
  expect_command_rejected("study", {"--shard", "1", "--out", out}, {"--shard must be K/N"});
  expect_merge_rejected({tmp.file("s1")}, {"--out DIR is required"});
  expect_merge_rejected({"--out", tmp.file("s1"), tmp.file("s1")}, {"is one of the shards"});
  // Resuming a shard as another shard is another plan.
  const ProcessResult r = run_rockwatch(study(mini_plan(), tmp.file("s1"), {"--shard", "2/3", "--resume"}));
  LONGS_EQUAL(2, r.exit_status);
  STRCMP_CONTAINS("shard", r.err.c_str());
}

// Built without MPI (no libopenmpi-dev, or -DROCKWATCH_MPI=OFF), --mpi is a usage error that says so; with MPI,
// tests/tools/study_mpi.sh (ctest study_mpi) runs it under mpirun.
TEST(StudyShards, MpiWithoutMpiSaysSo) {
  if (ROCKWATCH_TEST_HAVE_MPI) return;
  const TempDir tmp;
  expect_command_rejected("study", {"--mpi", "--out", tmp.file("x")}, {"--mpi", "built without MPI"});
}

}  // namespace unity_test_study_shards
