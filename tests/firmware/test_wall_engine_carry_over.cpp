// The fixed-point engine's carry-over (core/work_meter.hpp): with a work budget per call, samples whose work does not
// fit finish at later calls, in order, bit-identical to the engine without a budget; a full queue sheds; a sample at
// a queue still full is an overrun. Real records of the shipped suite.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/analysis.hpp"

#include <CppUTest/TestHarness.h>

namespace core = rockwatch::core;
namespace fw = rockwatch::firmware;
namespace records = rockwatch::records;

namespace {

constexpr double kG = 9.81;

std::vector<double> suite_record(int set, int component, double pga_g, double* dt_s) {
  const records::SuiteRecordFile f = records::read_suite_record(records::suite_set_path(ROCKWATCH_SUITE_DIR, set));
  *dt_s = f.dt_s;
  std::vector<double> ug = f.components_mps2[static_cast<std::size_t>(component)];
  double peak = 0.0;
  for (double u : ug) peak = u > peak ? u : (-u > peak ? -u : peak);
  for (double& u : ug) u *= pga_g * kG / peak;
  return ug;
}

fw::WallEngineConfig config(double dt_s, std::int32_t budget, core::RestitutionKind r) {
  fw::WallEngineConfig c;
  c.wall = core::paper_wall();
  c.r_energy = core::restitution_energy_ratio(c.wall, core::Restitution{r, 0.0});
  c.dt_s = dt_s;
  c.work_budget_units = budget;
  return c;
}

struct Compared {
  std::size_t finished = 0;
  std::uint32_t max_late = 0;
  std::size_t late = 0;
};

// Engine a through the seam with a budget, engine b with none (every sample in its own call): a's finished samples,
// in order, are b's samples bit for bit; at the end a's queue is finished without a budget. Nothing shed; the
// samples finished beyond a budget (a's overruns) are returned.
struct Overruns {
  std::size_t flagged = 0;
};
Compared compare(const std::vector<double>& ug, const fw::WallEngineConfig& budgeted, Overruns* overruns = nullptr) {
  fw::WallEngine a, b;
  fw::WallEngineConfig unbudgeted = budgeted;
  unbudgeted.work_budget_units = 0;
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok), static_cast<int>(a.init(budgeted)));
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok), static_cast<int>(b.init(unbudgeted)));
  std::vector<fw::EngineSample> expected;
  std::vector<fw::EngineSample> got;
  Compared c;
  for (std::size_t k = 0; k < ug.size(); ++k) {
    if (k == 0) {
      expected.push_back(b.start(ug[k], 0.0));
      a.start(ug[k], 0.0);
    } else {
      expected.push_back(b.step(ug[k], 0.0));
      a.step(ug[k], 0.0);
    }
    for (int i = 0; i < a.finished_count(); ++i) got.push_back(a.finished_sample(i));
    LONGS_EQUAL(static_cast<long>(expected.size()), static_cast<long>(got.size() + static_cast<std::size_t>(a.pending_samples())));
  }
  while (a.pending_samples() > 0) {
    a.finish_pending();
    for (int i = 0; i < a.finished_count(); ++i) got.push_back(a.finished_sample(i));
  }
  LONGS_EQUAL(static_cast<long>(expected.size()), static_cast<long>(got.size()));
  for (std::size_t k = 0; k < got.size(); ++k) {
    const fw::EngineSample& e = expected[k];
    const fw::EngineSample& g = got[k];
    if (!(e.x_m == g.x_m && e.xd_mps == g.xd_mps && e.alarm.level == g.alarm.level &&
          e.alarm.reasons == g.alarm.reasons && e.energy_ratio == g.energy_ratio && e.moving == g.moving)) {
      FAIL(("sample " + std::to_string(k) + " differs").c_str());
    }
    CHECK_FALSE(g.work_shed);
    if (g.work_overrun && overruns != nullptr) ++overruns->flagged;
    if (g.late_calls > 0) ++c.late;
    if (g.late_calls > c.max_late) c.max_late = g.late_calls;
  }
  c.finished = got.size();
  LONGS_EQUAL(0, static_cast<long>(a.work_counters().shed_samples));
  if (overruns == nullptr) LONGS_EQUAL(0, static_cast<long>(a.work_counters().overruns));
  if (overruns != nullptr) LONGS_EQUAL(static_cast<long>(a.work_counters().overruns), static_cast<long>(overruns->flagged));
  return c;
}

Compared compare(const std::vector<double>& ug, double dt_s, std::int32_t budget, core::RestitutionKind r) {
  return compare(ug, config(dt_s, budget, r));
}

}  // namespace

TEST_GROUP(WallEngineCarryOver){};

TEST(WallEngineCarryOver, SettlingChatterFinishesLaterAndBitIdentical) {
  double dt = 0.0;
  const std::vector<double> ug = suite_record(1, 0, 0.35, &dt);
  const Compared c = compare(ug, dt, fw::WallEngineConfig{}.work_budget_units, core::RestitutionKind::exp);
  CHECK_TRUE(c.late > 0);  // the chatter's samples did not fit one call
}


// Without a budget every sample finishes in its own call (the engine as before carry-over).
TEST(WallEngineCarryOver, WithoutABudgetEverySampleFinishesInItsOwnCall) {
  double dt = 0.0;
  const std::vector<double> ug = suite_record(1, 0, 0.35, &dt);
  const Compared c = compare(ug, dt, 0, core::RestitutionKind::exp);
  LONGS_EQUAL(0, static_cast<long>(c.late));
}

// A collapse: the alarm timeline of the budgeted engine is the unbudgeted one's (compare() checks every sample).
TEST(WallEngineCarryOver, ACollapseIsFinishedBitIdentical) {
  double dt = 0.0;
  const std::vector<double> ug = suite_record(1, 0, 0.40, &dt);
  compare(ug, dt, fw::WallEngineConfig{}.work_budget_units, core::RestitutionKind::exp);
}

TEST(WallEngineCarryOver, ABudgetTooSmallForOneEventIsRefused) {
  fw::WallEngine e;
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::work_budget_invalid),
              static_cast<int>(e.init(config(0.005, core::kMinWorkBudgetUnits - 1, core::RestitutionKind::exp))));
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::work_budget_invalid),
              static_cast<int>(e.init(config(0.005, -1, core::RestitutionKind::exp))));
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok),
              static_cast<int>(e.init(config(0.005, core::kMinWorkBudgetUnits, core::RestitutionKind::exp))));
}

// The least budget on a record that keeps the wall rocking: the queue fills, the engine sheds (events not located:
// flagged on the sample and counted) and never holds more than its queue; every sample is still finished, in order.
TEST(WallEngineCarryOver, AFullQueueShedsFlaggedAndCountedAndEverySampleFinishes) {
  double dt = 0.0;
  const std::vector<double> ug = suite_record(1, 0, 0.30, &dt);
  fw::WallEngineConfig c = config(dt, core::kMinWorkBudgetUnits, core::RestitutionKind::ana);
  c.max_step_s = dt / 16.0;  // 16 sub-steps a sample: its trials alone nearly fill a call
  fw::WallEngine e;
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok), static_cast<int>(e.init(c)));
  std::size_t finished = 0, flagged = 0;
  int most_pending = 0;
  for (std::size_t k = 0; k < ug.size(); ++k) {
    if (k == 0) {
      e.start(ug[k], 0.0);
    } else {
      e.step(ug[k], 0.0);
    }
    CHECK_TRUE(e.finished_count() <= fw::WallEngine::kMaxFinishedPerCall + 1);
    for (int i = 0; i < e.finished_count(); ++i) flagged += e.finished_sample(i).work_shed ? 1u : 0u;
    finished += static_cast<std::size_t>(e.finished_count());
    if (e.pending_samples() > most_pending) most_pending = e.pending_samples();
  }
  while (e.pending_samples() > 0) {
    e.finish_pending();
    for (int i = 0; i < e.finished_count(); ++i) flagged += e.finished_sample(i).work_shed ? 1u : 0u;
    finished += static_cast<std::size_t>(e.finished_count());
  }
  LONGS_EQUAL(static_cast<long>(ug.size()), static_cast<long>(finished));
  CHECK_TRUE(most_pending <= core::StepperAlarmChain<core::FixedRockingStepper>::kMaxPendingSamples);
  CHECK_TRUE(e.work_counters().shed_samples > 0);
  LONGS_EQUAL(static_cast<long>(e.work_counters().shed_samples), static_cast<long>(flagged));
}

// The same least budget with WorkOverflow::finish: nothing is shed, the oldest sample is finished beyond the budget
// whenever the queue is full (flagged on that sample, counted), and every sample is the unbudgeted engine's, bit for
// bit — the trade: the answers kept, the call's work no longer bounded by the budget.
TEST(WallEngineCarryOver, AFullQueueWithFinishOverrunsFlaggedAndEverySampleIsBitIdentical) {
  double dt = 0.0;
  const std::vector<double> ug = suite_record(1, 0, 0.30, &dt);
  fw::WallEngineConfig c = config(dt, core::kMinWorkBudgetUnits, core::RestitutionKind::ana);
  c.max_step_s = dt / 16.0;
  c.work_overflow = core::WorkOverflow::finish;
  Overruns overruns;
  compare(ug, c, &overruns);
  CHECK_TRUE(overruns.flagged > 0);
}

TEST(WallEngineCarryOver, AnUnknownOverflowPolicyIsRefused) {
  fw::WallEngineConfig c = config(0.005, core::kDefaultWorkBudgetUnits, core::RestitutionKind::exp);
  c.work_overflow = static_cast<core::WorkOverflow>(2);
  fw::WallEngine e;
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::work_overflow_invalid), static_cast<int>(e.init(c)));
}

// The study's "as published" figures (sim::analyse with work_budget_units) are the monitor's engine's: the call at
// which WallEngine::step() first finishes an IMMINENT sample, and how many samples waited.
TEST(WallEngineCarryOver, TheAnalysisReportsWhenTheMonitorsEnginePublishes) {
  double dt = 0.0;
  for (const double pga_g : {0.20, 0.40}) {
    const std::vector<double> ug = suite_record(1, 0, pga_g, &dt);
    rockwatch::sim::GroundMotion motion;
    motion.dt_s = dt;
    motion.ug_mps2 = ug;
    rockwatch::sim::AnalysisOptions o;
    o.arithmetic = rockwatch::sim::Arithmetic::fixed_point;
    o.evaluate_alarm = true;
    o.work_budget_units = fw::WallEngineConfig{}.work_budget_units;
    const rockwatch::sim::AnalysisResult r = rockwatch::sim::analyse(core::paper_wall(), motion, o);
    const rockwatch::sim::AlarmSummary::Published& p = r.alarm.published;
    CHECK_TRUE(p.measured);
    CHECK_TRUE(p.t_first_imminent_s.has_value() == r.alarm.t_first_imminent_s.has_value());

    fw::WallEngine e;
    LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok), static_cast<int>(e.init(config(dt, o.work_budget_units,
                                                                                             core::RestitutionKind::exp))));
    std::size_t first_imminent_call = 0;
    std::uint32_t late = 0;
    for (std::size_t k = 0; k < ug.size() && double(k) * dt <= r.t_final_s + 1e-9; ++k) {
      if (k == 0) {
        e.start(ug[k], 0.0);
        continue;
      }
      e.step(ug[k], 0.0);
      for (int i = 0; i < e.finished_count(); ++i) {
        const fw::EngineSample& s = e.finished_sample(i);
        if (s.alarm.level >= core::AlarmLevel::imminent && first_imminent_call == 0) first_imminent_call = k;
        late += s.late_calls > 0 ? 1u : 0u;
      }
    }
    if (p.t_first_imminent_s) {
      CHECK_TRUE(*p.t_first_imminent_s >= *r.alarm.t_first_imminent_s);
      DOUBLES_EQUAL(double(first_imminent_call) * dt, *p.t_first_imminent_s, 1e-9);
    }
    CHECK_TRUE(late <= p.late_samples);  // the analysis also counts those finished after its last input
    LONGS_EQUAL(0, static_cast<long>(p.shed_samples));
  }
}

// With WorkOverflow::finish the analysis counts the calls that overran and the most work in a call as WallEngine
// does on the same input: a wall settling at r_ana, whose chatter fills the queue.
TEST(WallEngineCarryOver, TheAnalysisCountsTheOverrunsOfTheMonitorsEngine) {
  double dt = 0.0;
  const std::vector<double> ug = suite_record(1, 0, 0.12, &dt);
  rockwatch::sim::GroundMotion motion;
  motion.dt_s = dt;
  motion.ug_mps2 = ug;
  rockwatch::sim::AnalysisOptions o;
  o.arithmetic = rockwatch::sim::Arithmetic::fixed_point;
  o.evaluate_alarm = true;
  o.restitution = core::Restitution{core::RestitutionKind::ana, 0.0};
  o.work_budget_units = core::kDefaultWorkBudgetUnits;
  o.work_overflow = core::WorkOverflow::finish;
  const rockwatch::sim::AnalysisResult r = rockwatch::sim::analyse(core::paper_wall(), motion, o);
  const rockwatch::sim::AlarmSummary::Published& p = r.alarm.published;

  fw::WallEngineConfig c = config(dt, o.work_budget_units, core::RestitutionKind::ana);
  c.work_overflow = core::WorkOverflow::finish;
  fw::WallEngine e;
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok), static_cast<int>(e.init(c)));
  std::int32_t most_units = 0;
  for (std::size_t k = 0; k < ug.size() && double(k) * dt <= r.t_final_s + 1e-9; ++k) {
    if (k == 0) {
      e.start(ug[k], 0.0);
      continue;
    }
    e.step(ug[k], 0.0);
    if (e.last_call_units() > most_units) most_units = e.last_call_units();
  }
  CHECK_TRUE(p.overruns > 0);
  LONGS_EQUAL(static_cast<long>(e.work_counters().overruns), static_cast<long>(p.overruns));
  LONGS_EQUAL(0, static_cast<long>(p.shed_samples));
  LONGS_EQUAL(static_cast<long>(most_units), static_cast<long>(p.max_call_units));
  CHECK_TRUE(p.max_call_units > o.work_budget_units);
  LONGS_EQUAL(static_cast<long>(most_units), static_cast<long>(e.work_counters().max_call_units));
  // The same input with shed: every call within the budget, some samples shed.
  o.work_overflow = core::WorkOverflow::shed;
  const rockwatch::sim::AlarmSummary::Published shed = rockwatch::sim::analyse(core::paper_wall(), motion, o).alarm.published;
  CHECK_TRUE(shed.shed_samples > 0);
  CHECK_TRUE(shed.max_call_units <= o.work_budget_units);
}

TEST(WallEngineCarryOver, TheAnalysisMeasuresOnlyWithABudget) {
  double dt = 0.0;
  rockwatch::sim::AnalysisOptions unmeasured;
  unmeasured.arithmetic = rockwatch::sim::Arithmetic::fixed_point;
  unmeasured.evaluate_alarm = true;
  rockwatch::sim::GroundMotion motion;
  motion.ug_mps2 = suite_record(1, 0, 0.2, &dt);
  motion.dt_s = dt;
  CHECK_FALSE(rockwatch::sim::analyse(core::paper_wall(), motion, unmeasured).alarm.published.measured);
}

// With the wall observer the engine's work and the observer's are paid from one meter per call (the estimator's share
// of a 1 kHz sample) and carried over together: every finished sample — the fused state, the alarm and the published
// estimates — is the unmetered engine's bit for bit, though many finish a call late; the sensor samples, pushed on
// arrival, are applied to the sub-step they belong to, never a later one; nothing shed. One sample in three brings a
// burst of 8 sensor samples (more updates than the share pays: since the single-precision covariance a sample with
// one sensor sample fits its call), so those samples wait.
TEST(WallEngineCarryOver, TheObserverIsMeteredAndCarriedOverBitIdentical) {
  double dt5 = 0.0;
  const std::vector<double> ug5 = suite_record(1, 0, 0.25, &dt5);
  // The record resampled to 1 kHz (linear), its first 8 s.
  const double dt = 0.001;
  std::vector<double> ug;
  for (std::size_t k = 0; double(k) * dt <= 8.0; ++k) {
    const double t = double(k) * dt, pos = t / dt5;
    const std::size_t i = static_cast<std::size_t>(pos);
    const double a = pos - double(i);
    ug.push_back(i + 1 < ug5.size() ? ug5[i] + (ug5[i + 1] - ug5[i]) * a : 0.0);
  }
  // The sensors: a truer wall (r_ana, the model r_exp) through the open-loop engine, with a 1 mm offset.
  fw::WallEngine truth;
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok),
              static_cast<int>(truth.init(config(dt, 0, core::RestitutionKind::ana))));
  std::vector<double> x_true;
  x_true.push_back(truth.start(ug[0], 0.0).x_m);
  for (std::size_t k = 1; k < ug.size(); ++k) x_true.push_back(truth.step(ug[k], 0.0).x_m);

  fw::WallEngineConfig metered = config(dt, core::kDefaultWorkBudgetUnits, core::RestitutionKind::exp);
  metered.observer_enabled = true;
  fw::WallEngineConfig unmetered = metered;
  unmetered.work_budget_units = 0;
  fw::WallEngine a, b;
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok), static_cast<int>(a.init(metered)));
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok), static_cast<int>(b.init(unmetered)));
  const std::int64_t step_us = 1000;
  std::vector<fw::EngineSample> expected, got;
  a.start(ug[0], 0.0);
  b.start(ug[0], 0.0);
  for (std::size_t k = 1; k < ug.size(); ++k) {
    const std::int64_t t_us = core::observed_step_end_us(double(k - 1) * dt, dt);
    const int burst = k % 3 == 0 ? 8 : 1;
    for (int j = 1; j <= burst; ++j) {
      core::WallSensorSample s;
      s.utime_us = t_us - (step_us * (burst - j)) / burst;
      s.x_mid_m = x_true[k] + 0.001;
      s.x_valid = true;
      a.push_sensor(s);
      b.push_sensor(s);
    }
    expected.push_back(b.step_at(ug[k], 0.0, t_us, step_us));
    a.step_at(ug[k], 0.0, t_us, step_us);
    for (int i = 0; i < a.finished_count(); ++i) got.push_back(a.finished_sample(i));
  }
  while (a.pending_samples() > 0) {
    a.finish_pending();
    for (int i = 0; i < a.finished_count(); ++i) got.push_back(a.finished_sample(i));
  }
  LONGS_EQUAL(static_cast<long>(expected.size()), static_cast<long>(got.size()));
  for (std::size_t k = 0; k < expected.size(); ++k) {
    CHECK_TRUE(got[k].x_m == expected[k].x_m);
    CHECK_TRUE(got[k].xd_mps == expected[k].xd_mps);
    CHECK_TRUE(got[k].alarm.level == expected[k].alarm.level);
    CHECK_TRUE(got[k].observer.sigma_x_m == expected[k].observer.sigma_x_m);
    CHECK_TRUE(got[k].observer.r_estimate == expected[k].observer.r_estimate);
    CHECK_TRUE(got[k].observer.x_inst_alarm_m == expected[k].observer.x_inst_alarm_m);
  }
  CHECK_TRUE(b.observer_counters().x_updates > 1000);
  LONGS_EQUAL(static_cast<long>(b.observer_counters().x_updates), static_cast<long>(a.observer_counters().x_updates));
  CHECK_TRUE(a.work_counters().late_samples > 100);  // the meter did carry work over
  LONGS_EQUAL(0, static_cast<long>(a.work_counters().shed_samples));
  LONGS_EQUAL(0, static_cast<long>(a.observer_counters().queue_overflow));
}
