// `rockwatch study merge --out DIR SHARD_DIR...`: the shards of one study (--shard K/N) into the study's files.
// Each shard directory holds shard.json (K, N, the plan digest, the study's options), study.json and runs.csv. The
// merge checks that the shards are one plan's (the same digest, N and options), that each K of 1..N is there exactly
// once and complete, and that every row of a shard is one of its runs; then it builds the plan again from the
// options (reading the records and walls again: the digest, which covers every record's samples and every wall,
// must come out the same) and writes the files the unsharded study writes, through the same code.
#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/process/text_report.hpp"
#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "study/outputs/study_files.hpp"
#include "study/plan/study_plan.hpp"
#include "study/plan/study_request.hpp"
#include "study/outputs/study_runs_csv.hpp"
#include "study/scale/study_scaled.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace study_merge {

namespace fs = std::filesystem;

constexpr CommandErrors kMergeErrors{"rockwatch study merge: error: ", "out of memory (too many runs?)"};

const char* const kMergeFooter =
    "Merges the shards of a study run with --shard K/N (e.g. the tasks of a batch array, docs/study-array.sbatch)\n"
    "into DIR: runs.csv, summary.json, table3.md (with --walls: walls_summary.csv), study.json and, when the shards\n"
    "were run with --plots, the figures, byte for byte what the study run in one piece writes. The shards must all\n"
    "be there (K = 1..N, each once), complete (an interrupted shard: run it again with --resume) and of one plan\n"
    "(the plan digest in each shard.json). The records and walls are read again from the shards' options, so run the\n"
    "merge where the shards were started (relative paths); the digest check refuses records or walls that changed.\n"
    "\n"
    "Exit status: 0 done; 2 a shard missing, twice, incomplete or of another plan, or DIR holds a study (--force\n"
    "replaces it); 1 an internal error.\n"
    "\n"
    "Example:\n"
    "  for k in 1 2 3 4; do rockwatch study --shard $k/4 --out shard$k; done\n"
    "  rockwatch study merge --out study shard1 shard2 shard3 shard4\n";

struct Shard {
  std::string dir;
  std::size_t index = 0, count = 0;
  std::string digest;
  std::vector<std::string> arguments;
};

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(path + ": cannot be read: is " + fs::path(path).parent_path().string() + " a shard of a "
                            "study (rockwatch study --shard K/N --out DIR)?");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

Shard read_shard(const std::string& dir) {
  const std::string path = (fs::path(dir) / kShardStateName).string();
  const nlohmann::json j = nlohmann::json::parse(read_text_file(path), nullptr, /*allow_exceptions=*/false);
  const auto bad = [&](const std::string& what) {
    return UsageError(path + ": " + what + " (expected a shard.json written by rockwatch study --shard K/N)");
  };
  if (!j.is_object() || j.value("format", std::string()) != "rockwatch-study-shard") {
    throw bad("not a shard state file");
  }
  Shard s;
  s.dir = dir;
  try {
    s.index = j.at("shard").get<std::size_t>();
    s.count = j.at("shards").get<std::size_t>();
    s.digest = j.at("plan_digest").get<std::string>();
    s.arguments = j.at("arguments").get<std::vector<std::string>>();
    const std::string state = j.at("state").get<std::string>();
    if (state != "complete") {
      throw UsageError(path + ": shard " + std::to_string(s.index) + "/" + std::to_string(s.count) + " is " + state +
                       " (" + std::to_string(j.value("runs_done", 0)) + " of " +
                       std::to_string(j.value("runs_in_shard", 0)) +
                       " analyses done): finish it with its command and --resume");
    }
  } catch (const nlohmann::json::exception&) {
    throw bad("a field is missing or of the wrong type");
  }
  if (s.count == 0 || s.index == 0 || s.index > s.count) throw bad("shard K/N must have 1 <= K <= N");
  return s;
}

bool same_directory(const std::string& a, const std::string& b) {
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
}

int merge(const std::string& out, bool force, const std::vector<std::string>& dirs) {
  std::vector<Shard> shards;
  for (const std::string& dir : dirs) {
    if (same_directory(dir, out)) {
      throw UsageError("--out " + options::quoted(out) + " is one of the shards: merge into another directory");
    }
    shards.push_back(read_shard(dir));
  }
  const Shard& first = shards.front();
  std::map<std::size_t, const Shard*> by_index;
  for (const Shard& s : shards) {
    if (s.count != first.count || s.digest != first.digest || s.arguments != first.arguments) {
      throw UsageError(s.dir + " is shard " + std::to_string(s.index) + "/" + std::to_string(s.count) + " of plan " +
                       s.digest + ", " + first.dir + " shard " + std::to_string(first.index) + "/" +
                       std::to_string(first.count) + " of plan " + first.digest +
                       (s.count == first.count && s.digest == first.digest ? " with other options" : "") +
                       ": the shards are not of one study");
    }
    const auto [it, inserted] = by_index.emplace(s.index, &s);
    if (!inserted) {
      throw UsageError("shard " + std::to_string(s.index) + "/" + std::to_string(s.count) + " is given twice: " +
                       it->second->dir + " and " + s.dir);
    }
  }
  std::string missing;
  for (std::size_t k = 1; k <= first.count; ++k) {
    if (by_index.count(k) == 0) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  }
  if (!missing.empty()) {
    throw UsageError("shard" + std::string(missing.find(',') == std::string::npos ? " " : "s ") + missing + " of " +
                     std::to_string(first.count) + " missing (given: " + std::to_string(shards.size()) + ")");
  }

  // The plan again, from the shards' options.
  std::vector<std::string> args{"study"};
  args.insert(args.end(), first.arguments.begin(), first.arguments.end());
  args.emplace_back("--out");
  args.push_back(out);
  if (force) args.emplace_back("--force");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  const StudyParse parsed = parse_study_arguments(static_cast<int>(argv.size()), argv.data());
  if (!parsed.request) throw UsageError("the shards' options ask for help, not a study");
  ScaledStudy study = load_scaled_study(*parsed.request);
  const std::string digest = plan_digest(study.plan_description);
  if (digest != first.digest) {
    throw UsageError("the shards were run with plan " + first.digest + ", but their options give plan " + digest +
                     " here: the records or walls they read changed, or the merge runs in another directory than the "
                     "shards (relative paths)");
  }
  for (const auto& [k, shard] : by_index) {
    const std::size_t n = first.count, slot = k - 1;
    const std::size_t expected = study.total() > slot ? (study.total() - slot + n - 1) / n : 0;
    const std::size_t read = read_scaled_runs(
        study, (fs::path(shard->dir) / kRunsCsvName).string(), [&](std::size_t g) { return g % n == slot; },
        "the run belongs to another shard than " + std::to_string(k) + "/" + std::to_string(n));
    if (read != expected) {
      throw UsageError(shard->dir + ": shard " + std::to_string(k) + "/" + std::to_string(n) + " holds " +
                       std::to_string(read) + " of its " + std::to_string(expected) +
                       " analyses: run it again with --resume");
    }
  }
  std::cerr << "study merge: " << shards.size() << " shards, " << study.total() << " analyses\n";
  prepare_scaled_directory(study);
  return finish_scaled_study(study, 0);
}

}  // namespace study_merge
}  // namespace

int study_merge_main(int argc, const char* const* argv) {
  using namespace study_merge;
  return run_command(kMergeErrors, [&] {
    CLI::App app{"Merge the shards of a study (rockwatch study --shard K/N) into the study's files.",
                 "rockwatch study merge"};
    std::string out;
    bool force = false;
    std::vector<std::string> dirs;
    app.add_option("--out", out, "Directory for the merged study's files")->type_name("DIR");
    app.add_flag("--force", force, "Replace a study already in --out");
    app.add_option("shards", dirs, "The shard directories (--out of each rockwatch study --shard K/N)")
        ->type_name("SHARD_DIR...");
    app.footer(kMergeFooter);
    if (std::optional<std::string> help = parse_command_line(app, argc, argv, "study merge")) return print_help(*help);
    if (!given(app, "--out") || out.empty()) throw UsageError("--out DIR is required: where the merged study goes");
    if (dirs.empty()) throw UsageError("no shard directories given (rockwatch study merge --out DIR SHARD_DIR...)");
    return merge(out, force, dirs);
  });
}

}  // namespace rockwatch::cli
