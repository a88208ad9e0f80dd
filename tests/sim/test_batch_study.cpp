// The study's batch engine (sim/study/batch_study): run order, results equal to direct sim::analyse calls on the
// same scaled input, resume, cancel, the half-step check, plan validation and refused inputs.
// Every run_study here uses jobs = 1: CppUTest's allocation bookkeeping is not thread-safe, so these tests must not
// start threads (the identity of results for 1 and 2 jobs is tested through the CLI, in its own process).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/study/batch_study.hpp"

#include <CppUTest/TestHarness.h>

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_batch_study {

using namespace rockwatch;
using sim::study::RunKey;
using sim::study::RunResult;
using sim::study::StudyPlan;
using sim::study::StudyRecord;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.005;

// A sine pulse train of `cycles` cycles at f_hz, amplitude 1, zero after it, sampled over t_end_s.
std::vector<double> sine_pulse(double f_hz, double cycles, double phase, double t_end_s) {
  const double t_pulse = cycles / f_hz;
  return sim::sample_motion([&](double t) { return t <= t_pulse ? std::sin(2.0 * kPi * f_hz * t + phase) : 0.0; },
                            kDt, t_end_s)
      .ug_mps2;
}

StudyRecord make_record(const std::string& name, std::vector<double> ug, std::vector<double> vg) {
  StudyRecord r;
  r.name = name;
  r.dt_s = kDt;
  r.ug_mps2 = std::move(ug);
  r.vg_mps2 = std::move(vg);
  r.peak_ug_mps2 = sim::peak_abs(r.ug_mps2);
  return r;
}

// Two records of different length (3 s and 4 s, so the worker's buffer shrinks and grows between runs) and
// frequency, each with a synthetic vertical partner. Made before the tests run: a static first built inside a test
// would count as a leak of that test.
std::vector<StudyRecord> make_records() {
  std::vector<StudyRecord> out;
  out.push_back(make_record("pulse2hz", sine_pulse(2.0, 3.0, 0.0, 3.0), sine_pulse(5.0, 10.0, 0.3, 3.0)));
  out.push_back(make_record("pulse1hz", sine_pulse(1.0, 2.0, 0.0, 4.0), sine_pulse(7.0, 14.0, 1.1, 4.0)));
  return out;
}
const std::vector<StudyRecord> kRecords = make_records();

StudyPlan small_plan() {
  StudyPlan plan;
  plan.records = kRecords;
  plan.pga_g = {0.12, 0.16, 0.20, 0.25, 0.30};
  plan.restitutions = {{core::Restitution{core::RestitutionKind::ana, 0.0}, "ana"},
                       {core::Restitution{core::RestitutionKind::exp, 0.0}, "exp"}};
  plan.vertical = {false, true};
  return plan;
}

// The run's input built here independently, scaled as documented (and as `rockwatch simulate --scale-pga` does).
sim::GroundMotion scaled_input(const StudyPlan& plan, const RunKey& key) {
  const StudyRecord& rec = plan.records[key.record_index];
  const double factor = plan.pga_g[key.pga_index] * plan.wall.g_mps2 / rec.peak_ug_mps2;
  sim::GroundMotion m;
  m.dt_s = rec.dt_s;
  for (const double u : rec.ug_mps2) m.ug_mps2.push_back(u * factor);
  if (plan.vertical[key.vertical_index]) {
    for (const double v : rec.vg_mps2) m.vg_mps2.push_back(v * factor);
  }
  return m;
}

sim::AnalysisResult direct_analysis(const StudyPlan& plan, const RunKey& key, double max_step_s) {
  sim::AnalysisOptions o = plan.analysis;
  o.restitution = plan.restitutions[key.restitution_index].restitution;
  o.max_step_s = max_step_s;
  return sim::analyse(plan.wall, scaled_input(plan, key), o);
}

std::string run_text(std::size_t index) { return "run " + std::to_string(index); }

// Bit-for-bit equality with a direct analysis (no tolerance: the batch runs the same engine on the same numbers).
void check_equals_direct(const StudyPlan& plan, const std::vector<RunResult>& results) {
  for (std::size_t i = 0; i < results.size(); ++i) {
    const RunResult& got = results[i];
    const sim::AnalysisResult want = direct_analysis(plan, sim::study::run_key(plan, i), plan.analysis.max_step_s);
    const std::string where = run_text(i);
    CHECK_TEXT(got.done, where.c_str());
    CHECK_TEXT(got.error.empty(), where.c_str());
    CHECK_TEXT(got.collapsed == want.verdict_collapse(), where.c_str());
    CHECK_TEXT(got.max_abs_x_m == want.max_abs_x_m, where.c_str());
    CHECK_TEXT(got.t_collapse_s == want.t_collapse_s, where.c_str());
    CHECK_TEXT(got.t_exceed_s == want.t_exceed_s, where.c_str());
    LONGS_EQUAL_TEXT(want.n_impacts, got.n_impacts, where.c_str());
  }
}

std::string rejection_of(const StudyPlan& plan) {
  try {
    sim::study::validate_plan(plan);
  } catch (const sim::AnalysisError& e) {
    return e.what();
  }
  return "(accepted)";
}

}  // namespace

TEST_GROUP(BatchStudy){};

TEST(BatchStudy, RunIndexIsVerticalThenRestitutionThenRecordThenPgaAndRunKeyIsItsInverse) {
  StudyPlan plan;
  plan.vertical = {false, true};
  plan.restitutions.resize(3);
  plan.records.resize(4);
  plan.pga_g.resize(5);
  LONGS_EQUAL(2 * 3 * 4 * 5, sim::study::run_count(plan));
  for (std::size_t i = 0; i < sim::study::run_count(plan); ++i) {
    const RunKey k = sim::study::run_key(plan, i);
    LONGS_EQUAL(i, sim::study::run_index(plan, k));
    LONGS_EQUAL(i, ((k.vertical_index * 3 + k.restitution_index) * 4 + k.record_index) * 5 + k.pga_index);
  }
  const RunKey k = sim::study::run_key(plan, 1 * 60 + 2 * 20 + 3 * 5 + 4);
  LONGS_EQUAL(1, k.vertical_index);
  LONGS_EQUAL(2, k.restitution_index);
  LONGS_EQUAL(3, k.record_index);
  LONGS_EQUAL(4, k.pga_index);
  const RunKey first = sim::study::run_key(plan, 1);
  LONGS_EQUAL(0, first.record_index);
  LONGS_EQUAL(1, first.pga_index);

  bool thrown = false;
  try {
    sim::study::run_key(plan, 120);
  } catch (const sim::AnalysisError&) {
    thrown = true;
  }
  CHECK_TEXT(thrown, "index past the end");
  thrown = false;
  try {
    sim::study::run_index(plan, RunKey{0, 0, 4, 0});
  } catch (const sim::AnalysisError&) {
    thrown = true;
  }
  CHECK_TEXT(thrown, "record index past the end");
}

TEST(BatchStudy, EveryResultEqualsADirectAnalysisOfTheSameScaledInput) {
  const StudyPlan plan = small_plan();
  std::vector<RunResult> results;
  std::vector<std::size_t> seen;
  sim::study::run_study(
      plan, results, 1, [&](std::size_t done, std::size_t total) {
        seen.push_back(done);
        LONGS_EQUAL(40, total);
      });
  LONGS_EQUAL(2 * 2 * 2 * 5, results.size());
  LONGS_EQUAL(40, seen.size());
  for (std::size_t i = 0; i < seen.size(); ++i) LONGS_EQUAL(i + 1, seen[i]);
  check_equals_direct(plan, results);

  // The plan exercises both verdicts and the vertical really enters.
  std::size_t collapsed = 0;
  for (const RunResult& r : results) collapsed += r.collapsed ? 1 : 0;
  CHECK_TEXT(collapsed > 0 && collapsed < results.size(), ("collapsed " + std::to_string(collapsed)).c_str());
  const RunResult& without = results[sim::study::run_index(plan, RunKey{0, 0, 0, 2})];
  const RunResult& with = results[sim::study::run_index(plan, RunKey{1, 0, 0, 2})];
  CHECK_TEXT(without.max_abs_x_m != with.max_abs_x_m, "the vertical changes the response");
  CHECK_FALSE(results[0].collapsed_reference.has_value());
}

TEST(BatchStudy, ResumeRunsOnlyTheRunsNotDoneAndKeepsTheOthers) {
  const StudyPlan plan = small_plan();
  std::vector<RunResult> reference;
  sim::study::run_study(plan, reference, 1);

  std::vector<RunResult> results(reference.size());
  RunResult sentinel;
  sentinel.done = true;
  sentinel.collapsed = true;
  sentinel.max_abs_x_m = 123.0;
  sentinel.n_impacts = -7;
  const std::vector<std::size_t> kept = {0, 5, 17, 39};
  for (const std::size_t i : kept) results[i] = sentinel;
  std::size_t calls = 0, last_total = 0;
  sim::study::run_study(plan, results, 1, [&](std::size_t done, std::size_t total) {
    calls = done;
    last_total = total;
  });
  LONGS_EQUAL(36, calls);
  LONGS_EQUAL(36, last_total);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const bool is_kept = std::find(kept.begin(), kept.end(), i) != kept.end();
    CHECK_TEXT(results[i].done, run_text(i).c_str());
    if (is_kept) {
      CHECK_TEXT(results[i].max_abs_x_m == 123.0 && results[i].n_impacts == -7, run_text(i).c_str());
    } else {
      CHECK_TEXT(results[i].max_abs_x_m == reference[i].max_abs_x_m, run_text(i).c_str());
      CHECK_TEXT(results[i].collapsed == reference[i].collapsed, run_text(i).c_str());
      LONGS_EQUAL_TEXT(reference[i].n_impacts, results[i].n_impacts, run_text(i).c_str());
    }
  }

  // All done: nothing runs, nothing reports.
  calls = 0;
  sim::study::run_study(plan, results, 1, [&](std::size_t, std::size_t) { ++calls; });
  LONGS_EQUAL(0, calls);
}

TEST(BatchStudy, CancelSetBeforeTheStartRunsNothingAndCancelDuringTheStudyStopsBetweenRuns) {
  const StudyPlan plan = small_plan();
  std::atomic<bool> cancel{true};
  std::vector<RunResult> results;
  std::size_t calls = 0;
  sim::study::run_study(plan, results, 1, [&](std::size_t, std::size_t) { ++calls; }, &cancel);
  LONGS_EQUAL(40, results.size());  // sized all the same
  LONGS_EQUAL(0, calls);
  for (const RunResult& r : results) CHECK_FALSE(r.done);

  cancel = false;
  sim::study::run_study(
      plan, results, 1,
      [&](std::size_t done, std::size_t) {
        if (done == 3) cancel = true;
      },
      &cancel);
  std::size_t done = 0;
  for (const RunResult& r : results) done += r.done ? 1 : 0;
  LONGS_EQUAL(3, done);
  CHECK_TRUE(results[0].done && results[1].done && results[2].done);

  // Resuming after the cancel finishes the study with the same results as one uninterrupted run.
  cancel = false;
  sim::study::run_study(plan, results, 1, {}, &cancel);
  check_equals_direct(plan, results);
}

TEST(BatchStudy, DtCheckGivesTheVerdictOfADirectAnalysisAtHalfTheMaxStep) {
  StudyPlan plan = small_plan();
  plan.dt_check = true;
  plan.analysis.max_step_s = 0.01;  // coarser than the records: sub-stepping at both steps
  std::vector<RunResult> results;
  sim::study::run_study(plan, results, 1);
  check_equals_direct(plan, results);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const RunKey key = sim::study::run_key(plan, i);
    const sim::AnalysisResult half = direct_analysis(plan, key, 0.005);
    CHECK_TEXT(results[i].collapsed_reference.has_value(), run_text(i).c_str());
    CHECK_TEXT(*results[i].collapsed_reference == half.verdict_collapse(), run_text(i).c_str());
  }
}

TEST(BatchStudy, ValidatePlanNamesWhatIsWrong) {
  STRCMP_EQUAL("(accepted)", rejection_of(small_plan()).c_str());

  StudyPlan p = small_plan();
  p.records.clear();
  STRCMP_CONTAINS("no records", rejection_of(p).c_str());
  p = small_plan();
  p.pga_g.clear();
  STRCMP_CONTAINS("no PGA levels", rejection_of(p).c_str());
  p = small_plan();
  p.restitutions.clear();
  STRCMP_CONTAINS("no restitution cases", rejection_of(p).c_str());
  p = small_plan();
  p.vertical.clear();
  STRCMP_CONTAINS("no vertical settings", rejection_of(p).c_str());

  p = small_plan();
  p.records[1].ug_mps2.clear();
  p.records[1].vg_mps2.clear();
  STRCMP_CONTAINS("record 1 (pulse1hz): no samples", rejection_of(p).c_str());
  p = small_plan();
  p.records[0].peak_ug_mps2 = 0.0;
  STRCMP_CONTAINS("record 0 (pulse2hz): no peak", rejection_of(p).c_str());
  p = small_plan();
  p.records[1].vg_mps2.clear();
  STRCMP_CONTAINS("record 1 (pulse1hz): the plan runs it with its vertical, but it has no vertical partner",
                  rejection_of(p).c_str());
  p.vertical = {false};  // horizontal only: a record without a partner is fine
  STRCMP_EQUAL("(accepted)", rejection_of(p).c_str());
  p = small_plan();
  p.records[0].vg_mps2.pop_back();
  STRCMP_CONTAINS("record 0 (pulse2hz): its vertical has 600 samples, the horizontal 601", rejection_of(p).c_str());
  p = small_plan();
  p.pga_g[0] = 0.0;
  STRCMP_CONTAINS("PGA level 0 is 0 g: levels must be > 0", rejection_of(p).c_str());
  p = small_plan();
  p.pga_g[2] = -0.1;
  STRCMP_CONTAINS("PGA level 2 is -0.1 g", rejection_of(p).c_str());
  p = small_plan();
  p.pga_g = {0.2, 0.1};
  STRCMP_CONTAINS("PGA levels must be ascending", rejection_of(p).c_str());
  p = small_plan();
  p.records[0].dt_s = 0.0;
  STRCMP_CONTAINS("record 0 (pulse2hz): sample interval must be > 0 s", rejection_of(p).c_str());
  p = small_plan();
  p.restitutions[1].restitution = core::Restitution{core::RestitutionKind::value, 1.5};
  STRCMP_CONTAINS("restitution case 1 (exp): r must be in [0, 1]", rejection_of(p).c_str());
  p = small_plan();
  p.wall.b_m = -0.1;
  STRCMP_CONTAINS("wall parameter", rejection_of(p).c_str());
  p = small_plan();
  p.analysis.kappa = 0.5;
  STRCMP_CONTAINS("kappa", rejection_of(p).c_str());
  p = small_plan();
  p.analysis.max_step_s = 0.0;
  STRCMP_CONTAINS("max step", rejection_of(p).c_str());

  // run_study validates first and leaves the results alone; results of another size are refused.
  p = small_plan();
  p.pga_g.clear();
  std::vector<RunResult> results;
  bool thrown = false;
  try {
    sim::study::run_study(p, results, 1);
  } catch (const sim::AnalysisError&) {
    thrown = true;
  }
  CHECK_TRUE(thrown);
  CHECK_TRUE(results.empty());
  results.resize(7);
  thrown = false;
  try {
    sim::study::run_study(small_plan(), results, 1);
  } catch (const sim::AnalysisError& e) {
    thrown = true;
    STRCMP_CONTAINS("study results hold 7 runs, the plan has 40", e.what());
  }
  CHECK_TRUE(thrown);
}

TEST(BatchStudy, AnInputTheAnalysisRefusesGivesItsMessageAndCountsAsDoneWithoutThrowing) {
  // A vertical twice the horizontal: at 0.6 g it reaches -1.2 g, so G = g + v'' < 0 (lift-off); at 0.2 g it is fine.
  StudyPlan plan;
  std::vector<double> ug = sine_pulse(2.0, 2.0, 0.0, 2.0);
  std::vector<double> vg = ug;
  for (double& v : vg) v *= -2.0;
  plan.records.push_back(make_record("lift", ug, vg));
  plan.pga_g = {0.2, 0.6};
  plan.restitutions = {{core::Restitution{}, "exp"}};
  plan.vertical = {false, true};
  std::vector<RunResult> results;
  std::size_t calls = 0;
  sim::study::run_study(plan, results, 1, [&](std::size_t, std::size_t) { ++calls; });
  LONGS_EQUAL(4, calls);
  for (std::size_t i = 0; i < results.size(); ++i) CHECK_TEXT(results[i].done, run_text(i).c_str());
  CHECK_TRUE(results[0].error.empty() && results[1].error.empty() && results[2].error.empty());
  const RunResult& refused = results[3];
  STRCMP_CONTAINS("G = g + v'' must stay > 0", refused.error.c_str());
  CHECK_FALSE(refused.collapsed);
  CHECK_FALSE(refused.t_exceed_s.has_value());
  CHECK_EQUAL(0.0, refused.max_abs_x_m);
}

}  // namespace unity_test_batch_study
