// sim::DoubleWallEngine, the host's double engine behind the monitor loop's seam (core::SampleEngine): its
// validation, and sample by sample the alarm timeline of sim::analyse(--arith double) on a suite record, bit for bit,
// with the linear and the full model. (Behind the loop itself: tests/firmware/test_monitor_loop.cpp.)
#include <cmath>
#include <cstddef>
#include <vector>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/double_wall_engine.hpp"

#include <CppUTest/TestHarness.h>

using namespace rockwatch;
namespace fw = rockwatch::core;  // the engine seam

namespace {

fw::WallEngineConfig paper_config(double dt_s, core::ModelKind model) {
  fw::WallEngineConfig c;
  c.wall = core::paper_wall();
  c.r_energy = core::restitution_energy_ratio(c.wall, core::Restitution{});
  c.model = model;
  c.dt_s = dt_s;
  return c;
}

void check_engine_equals_analysis(double pga_g, core::ModelKind model) {
  const records::SuiteRecordFile f = records::read_suite_record(records::suite_set_path(ROCKWATCH_SUITE_DIR, 1));
  sim::GroundMotion motion;
  motion.dt_s = f.dt_s;
  motion.ug_mps2 = f.components_mps2[0];
  const double factor = pga_g * 9.81 / sim::peak_abs(motion.ug_mps2);
  for (double& u : motion.ug_mps2) u *= factor;
  sim::AnalysisOptions o;
  o.arithmetic = sim::Arithmetic::double_precision;
  o.model = model;
  o.evaluate_alarm = true;
  o.max_alarm_transitions_kept = 100000;
  const sim::AnalysisResult r = sim::analyse(core::paper_wall(), motion, o);

  sim::DoubleWallEngine engine;
  CHECK_TRUE(engine.arithmetic() == fw::MonitorArithmetic::double_precision);
  CHECK_TRUE(engine.init(paper_config(f.dt_s, model)) == fw::WallEngineError::ok);
  fw::EngineSample e = engine.start(motion.ug_mps2[0], 0.0);
  LONGS_EQUAL(static_cast<long>(core::AlarmLevel::quiet), static_cast<long>(e.alarm.level));
  std::size_t next = 0;  // the next expected transition
  for (std::size_t k = 1; k < motion.ug_mps2.size(); ++k) {
    e = engine.step(motion.ug_mps2[k], 0.0);
    if (!e.alarm.changed) continue;
    CHECK_TRUE(next < r.alarm.transitions.size());
    const sim::AlarmTransition& t = r.alarm.transitions[next++];
    // The analysis reports the step's end (or the collapse inside it): the sample that ends that step.
    LONGS_EQUAL(static_cast<long>(std::ceil(t.t_s / f.dt_s - 1e-6)), static_cast<long>(k));
    LONGS_EQUAL(static_cast<long>(t.level), static_cast<long>(e.alarm.level));
    LONGS_EQUAL(static_cast<long>(t.reasons), static_cast<long>(e.alarm.reasons));
    CHECK_TRUE(t.x_m == e.x_m);
    CHECK_TRUE(t.xd_mps == e.xd_mps);
    CHECK_TRUE(t.energy_ratio == e.energy_ratio);
    CHECK_TRUE((t.t_to_instability_s ? *t.t_to_instability_s : -1.0) == e.t_to_instability_s);
  }
  CHECK_TRUE(next >= 3);
  CHECK_EQUAL(r.collapsed, engine.stepper().collapsed());
}

}  // namespace

TEST_GROUP(DoubleWallEngine){};

TEST(DoubleWallEngine, AlarmTimelineEqualsTheDoubleAnalysisSampleBySample) {
  check_engine_equals_analysis(0.40, core::ModelKind::linear);
}

TEST(DoubleWallEngine, AlarmTimelineEqualsTheDoubleAnalysisWithTheFullModel) {
  check_engine_equals_analysis(0.40, core::ModelKind::full);
}

TEST(DoubleWallEngine, InitValidatesLikeTheFirmwareEngine) {
  sim::DoubleWallEngine engine;
  fw::WallEngineConfig c = paper_config(0.005, core::ModelKind::full);
  CHECK_TRUE(engine.init(c) == fw::WallEngineError::ok);  // the full model too
  c.wall.b_m = -0.1;
  CHECK_TRUE(engine.init(c) == fw::WallEngineError::wall_invalid);
  c = paper_config(0.005, core::ModelKind::linear);
  c.r_energy = 1.5;
  CHECK_TRUE(engine.init(c) == fw::WallEngineError::restitution_out_of_range);
  c = paper_config(0.005, core::ModelKind::linear);
  c.alarm.lambda_warning = 0.0;
  CHECK_TRUE(engine.init(c) == fw::WallEngineError::alarm_settings_invalid);
}

TEST(DoubleWallEngine, RestartKeepsTheAlarmLevelAndRestartsTheMotion) {
  sim::DoubleWallEngine engine;
  CHECK_TRUE(engine.init(paper_config(0.005, core::ModelKind::linear)) == fw::WallEngineError::ok);
  engine.start(0.0, 0.0);
  fw::EngineSample e{};
  for (int k = 1; k <= 400 && e.alarm.level == core::AlarmLevel::quiet; ++k) {
    e = engine.step(0.5 * 9.81 * std::sin(2.0 * 3.14159265358979 * 2.0 * k * 0.005), 0.0);
  }
  CHECK_TRUE(e.alarm.level != core::AlarmLevel::quiet);
  const core::AlarmLevel level = e.alarm.level;
  e = engine.restart(0.0, 0.0);
  CHECK_TRUE(e.alarm.level == level);
  CHECK_FALSE(e.moving);
  CHECK_TRUE(e.x_m == 0.0);
}
