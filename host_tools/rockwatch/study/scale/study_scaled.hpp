// The study at scale: a portfolio of walls (--walls), a slice of the plan (--shard K/N) and the plan spread over
// MPI ranks (--mpi). One index space for all of them: the global run index g = wall · R + run, R the runs of one
// wall's plan (sim::study::run_index order), walls in file order. Without --walls the portfolio is the study's one
// wall and every file is written exactly as the single-process study writes it (study_command.cpp), which is what
// makes a merged or MPI study byte-identical to it.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockwatch/sim/study/batch_study.hpp"
#include "study/plan/study_plan.hpp"
#include "study/plan/study_records.hpp"
#include "study/plan/study_request.hpp"
#include "study/plan/study_walls.hpp"

namespace rockwatch::cli {

inline constexpr const char* kWallsSummaryName = "walls_summary.csv";     // --walls
inline constexpr const char* kWallsFigureName = "walls_fragility.png";    // --walls --plots
inline constexpr const char* kShardStateName = "shard.json";              // --shard
// The most analyses one portfolio study holds in memory (about 200 bytes each); more belong in shards.
inline constexpr std::size_t kMaxPortfolioRuns = 4000000;

struct ScaledStudy {
  StudyRequest request;
  StudyRecords records;                     // what was read (the records themselves are in plan)
  sim::study::StudyPlan plan;               // plan.wall: the wall in hand (set_wall)
  std::vector<PortfolioWall> walls;         // without --walls: one, the study's wall (id "")
  bool portfolio = false;                   // --walls: a wall column, walls_summary.csv, summary.json "walls"
  std::size_t runs_per_wall = 0;
  nlohmann::ordered_json plan_description;  // the unsharded plan: what summary.json and a merged study.json hold
  std::vector<std::vector<sim::study::RunResult>> results;  // [wall][run]

  std::size_t total() const { return walls.size() * runs_per_wall; }
  bool sharded() const { return request.shard_count > 0; }
  // Shard K of N holds the global indices g with g mod N = K − 1: interleaved, so each shard gets its share of
  // every wall, record and PGA level (collapses end analyses early; the high levels are the cheap ones).
  bool in_shard(std::size_t global) const {
    return !sharded() || global % request.shard_count == request.shard_index - 1;
  }
  // study.json's plan: the unsharded plan, with "shard" {index, count} for a shard (so --resume refuses another K/N).
  nlohmann::ordered_json state_plan() const;
};

// Reads the records and the walls and builds the plan and its description (the readers' notes to stderr unless
// print_notes is false: the MPI ranks but rank 0). No file in --out is touched.
ScaledStudy load_scaled_study(const StudyRequest& request, bool print_notes = true);

void set_wall(ScaledStudy& study, std::size_t wall);

// --out as the single-process study prepares it (and, with --force, without the files only this one writes); with
// --resume the rows of runs.csv back into the results. Returns the runs resumed.
std::size_t prepare_scaled_directory(ScaledStudy& study);

// The global indices still to run (in the shard, not done), ascending.
std::vector<std::size_t> runs_to_do(const ScaledStudy& study);
std::size_t runs_done(const ScaledStudy& study);
std::size_t runs_in_shard(const ScaledStudy& study);

// Runs `indices` (global, ascending) of one wall into `out` (same order): sim::study::run_study on `jobs` threads.
// The study's plan must hold that wall (set_wall). Unfinished runs (cancelled) are left not done.
void run_wall_chunk(const sim::study::StudyPlan& plan, std::size_t runs_per_wall, std::size_t wall,
                    const std::vector<std::size_t>& indices, std::vector<sim::study::RunResult>& out,
                    std::size_t jobs, const std::function<void()>& one_done, const std::atomic<bool>* cancel);

// Runs `todo` in this process, a chunk (of one wall, at most kLocalChunkRuns) at a time, `between_chunks` between
// them (the checkpoints). `progress(done)` after each finished run.
inline constexpr std::size_t kLocalChunkRuns = 256;
void run_scaled_local(ScaledStudy& study, const std::vector<std::size_t>& todo, std::size_t jobs,
                      const std::function<void(std::size_t)>& progress, const std::atomic<bool>* cancel,
                      const std::function<void()>& between_chunks = {});

// runs.csv: the single-process study's file without --walls; with it a first column "wall" (the id) and "run" the
// index within the wall's plan.
void write_scaled_runs(ScaledStudy& study);
// Reads the rows of runs.csv at `path` into the results; each row's global index must pass `accept` (else
// UsageError naming PATH:LINE and `why_refused`). Returns the rows read.
std::size_t read_scaled_runs(ScaledStudy& study, const std::string& path,
                             const std::function<bool(std::size_t)>& accept, const std::string& why_refused);

// After the runs: an incomplete study writes runs.csv and study.json (interrupted) and returns 130; a shard writes
// runs.csv, study.json and shard.json; a whole study every file of the single-process study (with --walls:
// walls_summary.csv, summary.json's "walls", walls_fragility.png with --plots, no table3.md), the text on stdout.
int finish_scaled_study(ScaledStudy& study, int signal_number);

// --out's study.json (and a shard's shard.json) at the current state: running, with the runs done so far.
void write_scaled_state_running(const ScaledStudy& study);

// A checkpoint: runs.csv with the runs done so far and the state files, every kCheckpointInterval_s (or
// $ROCKWATCH_STUDY_CHECKPOINT_S) seconds between chunks, so a study killed outright (SIGKILL) resumes from there.
inline constexpr double kCheckpointInterval_s = 60.0;
double checkpoint_interval_s();
void write_scaled_checkpoint(ScaledStudy& study);

// `rockwatch study --walls/--shard` in one process (--mpi: study_mpi.cpp).
int run_scaled_study(const StudyRequest& request);

// `rockwatch study merge --out DIR SHARD_DIR...`.
int study_merge_main(int argc, const char* const* argv);

}  // namespace rockwatch::cli
