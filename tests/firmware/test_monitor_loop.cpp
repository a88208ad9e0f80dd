// firmware::MonitorLoop: an in-memory transport decodes what the loop publishes. A clean stream gives one
// wall_state_t per sample, bit-identical to a WallEngine fed the same samples, and the alarm timeline of
// sim::analyse(..., fixed_point, evaluate_alarm) on a collapsing suite record; each input fault is injected on its
// own with the flags and counters it must produce; the status message carries them; bad settings are refused.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/double_wall_engine.hpp"

#include <CppUTest/TestHarness.h>

#include "memory_transport.hpp"

using namespace rockwatch;
namespace fw = rockwatch::firmware;
using Status = rockwatch::monitor_status_t;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.005;
constexpr std::int64_t kPeriodUs = 5000;
constexpr std::int64_t kT0 = 1700000000000000;  // µs since 1970
constexpr std::int64_t kReceiveDelayUs = 1000;
const char* const kAccel = "ROCKWATCH_ACCEL";
const char* const kBatch = "ROCKWATCH_ACCEL_BATCH";

using test::MemoryTransport;
using test::Published;
using test::encode;

class RecordingListener : public fw::MonitorListener {
 public:
  void on_alarm(const alarm_event_t& event) override { events.push_back(event); }
  std::vector<alarm_event_t> events;
};

ground_accel_t accel(std::int64_t seq, double ug, double vg = 0.0, std::int32_t sensor_status = 0) {
  ground_accel_t m{};
  // Unsigned arithmetic: the extreme-value test passes seq near INT64_MAX and then sets utime itself.
  m.utime = static_cast<std::int64_t>(static_cast<std::uint64_t>(kT0) +
                                      static_cast<std::uint64_t>(seq) * static_cast<std::uint64_t>(kPeriodUs));
  m.seq = seq;
  m.schema_version = 1;
  m.ug_mps2 = ug;
  m.vg_mps2 = vg;
  m.sensor_status = sensor_status;
  return m;
}

// 2 Hz at 0.2 g: the paper wall rocks with impacts (WARNING and above within the first seconds).
double rocking_ug(std::int64_t seq) { return 0.20 * kG * std::sin(2.0 * kPi * 2.0 * double(seq) * kDt); }

fw::MonitorSettings paper_settings() {
  fw::MonitorSettings s;
  s.engine.wall = core::paper_wall();
  s.engine.r_energy = core::restitution_energy_ratio(s.engine.wall, core::Restitution{});
  s.sample_rate_hz = 200.0;
  s.config_digest = 0x1234567890abcdefLL;
  return s;
}

core::AccelQ7_56 q(double v) { return core::AccelQ7_56(v); }

// The engines a host can hand the loop; the one the settings ask for, as rockwatch-monitor picks it.
struct Engines {
  fw::WallEngine fixed;
  sim::DoubleWallEngine dbl;
  fw::SampleEngine& operator()(const fw::MonitorSettings& s) {
    if (s.arithmetic == fw::MonitorArithmetic::double_precision) return dbl;
    return fixed;
  }
};

// The loop, its transport, and a reference WallEngine fed by hand.
struct Rig {
  MemoryTransport transport;
  RecordingListener listener;
  Engines engines;
  fw::MonitorLoop loop;
  fw::WallEngine ref;

  explicit Rig(const fw::MonitorSettings& s = paper_settings()) {
    CHECK_TRUE(loop.init(s, engines(s), transport, &listener) == fw::MonitorError::ok);
    // The fixed-point reference (the double timeline tests compare with sim::analyse instead).
    if (s.arithmetic == fw::MonitorArithmetic::fixed_point) {
      CHECK_TRUE(ref.init(loop.settings().engine) == fw::WallEngineError::ok);
    }
  }
  void send(const ground_accel_t& m, std::int64_t receive_delay_us = kReceiveDelayUs) {
    const std::vector<std::uint8_t> b = encode(m);
    loop.on_message(kAccel, b.data(), b.size(), m.utime + receive_delay_us);
  }
  void send_bytes(const char* channel, const std::vector<std::uint8_t>& b) {
    loop.on_message(channel, b.data(), b.size(), kT0);
  }
  // Samples from..to (inclusive) of the rocking input, to the loop and the reference engine alike.
  void stream(std::int64_t from, std::int64_t to) {
    for (std::int64_t k = from; k <= to; ++k) {
      send(accel(k, rocking_ug(k)));
      if (k == 0) {
        ref.reset_wall(q(rocking_ug(k)), q(0.0));
      } else {
        ref.process_wall(q(rocking_ug(k)), q(0.0));
      }
    }
  }
  wall_state_t last_state() const {
    const std::vector<wall_state_t> s = transport.states();
    CHECK_FALSE(s.empty());
    return s.back();
  }
  std::size_t n_states() const { return transport.states().size(); }
  // The last published state is the reference engine's state, bit for bit.
  void check_matches_reference() const {
    const wall_state_t s = last_state();
    CHECK_TRUE(s.x_m == ref.stepper().x_m().to_double());
    CHECK_TRUE(s.xd_mps == ref.stepper().xd_mps().to_double());
    LONGS_EQUAL(ref.stepper().moving() ? 1 : 0, s.moving);
    LONGS_EQUAL(static_cast<long>(ref.last().alarm.level), s.alarm_level);
  }
};

// Counters other than the listed ones are zero.
struct Expected {
  std::int64_t received = 0, processed = 0, bridged = 0, gaps = 0, resets = 0, duplicates = 0, out_of_order = 0;
  std::int64_t late = 0, not_finite = 0, out_of_range = 0, lift_off = 0, restarts = 0, decode_errors = 0;
  std::int64_t sensor_flags = 0, ignored = 0, publish_failures = 0;
};

void check_counters(const fw::MonitorCounters& c, const Expected& e) {
  LONGS_EQUAL(e.received, c.samples_received);
  LONGS_EQUAL(e.processed, c.samples_processed);
  LONGS_EQUAL(e.bridged, c.samples_bridged);
  LONGS_EQUAL(e.gaps, c.gaps);
  LONGS_EQUAL(e.resets, c.state_resets);
  LONGS_EQUAL(e.duplicates, c.duplicates);
  LONGS_EQUAL(e.out_of_order, c.out_of_order);
  LONGS_EQUAL(e.late, c.late);
  LONGS_EQUAL(e.not_finite, c.rejected_not_finite);
  LONGS_EQUAL(e.out_of_range, c.rejected_out_of_range);
  LONGS_EQUAL(e.lift_off, c.lift_off);
  LONGS_EQUAL(e.restarts, c.publisher_restarts);
  LONGS_EQUAL(e.decode_errors, c.decode_errors);
  LONGS_EQUAL(0, c.saturated);
  LONGS_EQUAL(e.sensor_flags, c.sensor_flags);
  LONGS_EQUAL(e.ignored, c.messages_ignored);
  LONGS_EQUAL(e.publish_failures, c.publish_failures);
  LONGS_EQUAL(0, c.log_write_failures);
  // Every received sample is accounted for: processed (once; bridged steps are not received) or dropped with a reason.
  LONGS_EQUAL(c.samples_received, c.samples_processed - c.samples_bridged + c.duplicates + c.out_of_order);
}

// data_quality of the status published now (since the previous status), without MONITOR_RESTARTED.
std::int32_t status_quality(Rig& rig) {
  rig.loop.publish_status(kT0);
  return rig.transport.statuses().back().data_quality & ~std::int32_t{Status::QUALITY_MONITOR_RESTARTED};
}

// The alarm events published agree with the listener's and with the state published just before each.
void check_alarm_events_consistent(const Rig& rig) {
  const std::vector<alarm_event_t> events = rig.transport.alarms();
  LONGS_EQUAL(static_cast<long>(events.size()), static_cast<long>(rig.listener.events.size()));
  LONGS_EQUAL(static_cast<long>(events.size()), rig.loop.counters().alarm_events);
  std::int8_t level = 0;
  std::size_t i = 0;
  bool have_state = false;
  wall_state_t state{};
  for (const Published& p : rig.transport.sent) {
    if (p.channel == "ROCKWATCH_WALL_STATE") {
      LONGS_EQUAL(static_cast<long>(p.bytes.size()), state.decode(p.bytes.data(), 0, static_cast<int>(p.bytes.size())));
      have_state = true;
      continue;
    }
    if (p.channel != "ROCKWATCH_ALARM") continue;
    const alarm_event_t& e = events[i];
    LONGS_EQUAL(static_cast<long>(i), e.seq);
    LONGS_EQUAL(e.input_seq, rig.listener.events[i].input_seq);
    LONGS_EQUAL(level, e.previous_level);
    CHECK_TRUE(e.level != e.previous_level);
    level = e.level;
    CHECK_TRUE(have_state);
    LONGS_EQUAL(state.input_seq, e.input_seq);
    LONGS_EQUAL(state.utime, e.utime);
    LONGS_EQUAL(state.alarm_level, e.level);
    LONGS_EQUAL(state.alarm_reasons, e.reasons);
    CHECK_TRUE(state.x_m == e.x_m);
    CHECK_TRUE(state.energy_ratio == e.energy_ratio);
    ++i;
  }
  LONGS_EQUAL(static_cast<long>(events.size()), static_cast<long>(i));
}

}  // namespace

TEST_GROUP(MonitorLoop){};

TEST(MonitorLoop, CleanStreamOneStatePerSampleBitIdenticalToTheEngine) {
  Rig rig;
  const std::int64_t n = 1200;
  std::vector<std::int32_t> ref_levels;
  std::vector<double> ref_x, ref_xd;
  for (std::int64_t k = 0; k < n; ++k) {
    rig.stream(k, k);
    ref_levels.push_back(static_cast<std::int32_t>(rig.ref.last().alarm.level));
    ref_x.push_back(rig.ref.stepper().x_m().to_double());
    ref_xd.push_back(rig.ref.stepper().xd_mps().to_double());
  }
  // A sample whose work exceeds a call's budget is published by a later call (carry-over, core/work_meter.hpp):
  // what is still in work is finished here, as the adapter does when the stream stops.
  rig.loop.finish_pending();
  const std::vector<wall_state_t> states = rig.transport.states();
  LONGS_EQUAL(n, static_cast<long>(states.size()));
  bool moved = false;
  for (std::int64_t k = 0; k < n; ++k) {
    const wall_state_t& s = states[static_cast<std::size_t>(k)];
    CHECK_TRUE(s.x_m == ref_x[static_cast<std::size_t>(k)]);
    CHECK_TRUE(s.xd_mps == ref_xd[static_cast<std::size_t>(k)]);
    LONGS_EQUAL(ref_levels[static_cast<std::size_t>(k)], s.alarm_level);
    LONGS_EQUAL(k, s.seq);
    LONGS_EQUAL(k, s.input_seq);
    LONGS_EQUAL(kT0 + k * kPeriodUs, s.utime);
    LONGS_EQUAL(1, s.schema_version);
    LONGS_EQUAL(0, s.data_quality);
    CHECK_TRUE(s.side == 1 || s.side == -1);
    CHECK_TRUE(s.x_m / core::paper_wall().h1_m == s.theta1_rad);
    CHECK_TRUE(s.t_to_instability_s == -1.0 || s.t_to_instability_s >= 0.0);
    moved = moved || s.moving == 1;
  }
  CHECK_TRUE(moved);
  // Alarm events: one per level change of the reference engine, at the same sample.
  std::vector<std::int64_t> changes;
  for (std::size_t k = 1; k < ref_levels.size(); ++k) {
    if (ref_levels[k] != ref_levels[k - 1]) changes.push_back(static_cast<std::int64_t>(k));
  }
  const std::vector<alarm_event_t> events = rig.transport.alarms();
  CHECK_TRUE(events.size() >= 2);
  LONGS_EQUAL(static_cast<long>(changes.size()), static_cast<long>(events.size()));
  for (std::size_t i = 0; i < events.size(); ++i) LONGS_EQUAL(changes[i], events[i].input_seq);
  check_alarm_events_consistent(rig);
  Expected e;
  e.received = e.processed = n;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(n, rig.loop.counters().states_published);
  LONGS_EQUAL(0, status_quality(rig));
}

namespace {

// The monitor against sim::analyse(arithmetic, model, evaluate_alarm) on a suite record scaled like `rockwatch
// simulate --scale-pga`: the same transitions at the same sample with the same values, up to the end of the record
// (the analysis goes on in free motion after it; the monitor waits for samples). collapses: what the analysis must
// say (the monitor must agree).
void check_timeline_equals_analysis(int set, int component, double pga_g, bool collapses,
                                    fw::MonitorArithmetic arith = fw::MonitorArithmetic::fixed_point,
                                    core::ModelKind model = core::ModelKind::linear) {
  const records::SuiteRecordFile f = records::read_suite_record(records::suite_set_path(ROCKWATCH_SUITE_DIR, set));
  sim::GroundMotion motion;
  motion.dt_s = f.dt_s;
  motion.ug_mps2 = f.components_mps2[static_cast<std::size_t>(component)];
  const double factor = pga_g * kG / sim::peak_abs(motion.ug_mps2);
  for (double& u : motion.ug_mps2) u *= factor;
  sim::AnalysisOptions o;
  o.arithmetic = arith == fw::MonitorArithmetic::fixed_point ? sim::Arithmetic::fixed_point
                                                              : sim::Arithmetic::double_precision;
  o.model = model;
  o.evaluate_alarm = true;
  o.max_alarm_transitions_kept = 100000;
  const sim::AnalysisResult r = sim::analyse(core::paper_wall(), motion, o);
  CHECK_EQUAL(collapses, r.collapsed);
  LONGS_EQUAL(static_cast<long>(r.alarm.n_transitions), static_cast<long>(r.alarm.transitions.size()));
  std::vector<sim::AlarmTransition> expected;
  for (const sim::AlarmTransition& t : r.alarm.transitions) {
    if (t.t_s <= motion.duration_s() + 1e-9) expected.push_back(t);
  }
  CHECK_TRUE(expected.size() >= 3);

  fw::MonitorSettings s = paper_settings();
  s.sample_rate_hz = 1.0 / f.dt_s;
  s.arithmetic = arith;
  s.engine.model = model;
  Rig rig(s);
  for (std::size_t k = 0; k < motion.ug_mps2.size(); ++k) rig.send(accel(static_cast<std::int64_t>(k), motion.ug_mps2[k]));
  CHECK_EQUAL(collapses, rig.loop.alarm_level() == core::AlarmLevel::collapsed);
  const std::vector<alarm_event_t> events = rig.transport.alarms();
  LONGS_EQUAL(static_cast<long>(expected.size()), static_cast<long>(events.size()));
  for (std::size_t i = 0; i < events.size(); ++i) {
    const sim::AlarmTransition& t = expected[i];
    const alarm_event_t& e = events[i];
    // The analysis reports the step's end (or the collapse inside it): the sample that ends that step.
    LONGS_EQUAL(static_cast<long>(std::ceil(t.t_s / f.dt_s - 1e-6)), e.input_seq);
    LONGS_EQUAL(static_cast<long>(t.level), e.level);
    LONGS_EQUAL(static_cast<long>(t.previous), e.previous_level);
    LONGS_EQUAL(static_cast<long>(t.reasons), e.reasons);
    CHECK_TRUE(t.x_m == e.x_m);
    CHECK_TRUE(t.xd_mps == e.xd_mps);
    CHECK_TRUE(t.energy_ratio == e.energy_ratio);
    CHECK_TRUE((t.t_to_instability_s ? *t.t_to_instability_s : -1.0) == e.t_to_instability_s);
  }
  if (collapses) LONGS_EQUAL(static_cast<long>(core::AlarmLevel::collapsed), events.back().level);
  check_alarm_events_consistent(rig);
  Expected e;
  e.received = e.processed = static_cast<std::int64_t>(motion.ug_mps2.size());
  check_counters(rig.loop.counters(), e);
  // Every state is clean and the published maximum |x| is the analysis's (up to the collapse when it collapses).
  double max_abs_x = 0.0;
  for (const wall_state_t& st : rig.transport.states()) {
    LONGS_EQUAL(0, st.data_quality);
    max_abs_x = std::fmax(max_abs_x, std::fabs(st.x_m));
  }
  if (collapses) CHECK_TRUE(max_abs_x == r.max_abs_x_m);
  rig.loop.publish_status(kT0);
  LONGS_EQUAL(arith == fw::MonitorArithmetic::fixed_point ? Status::ARITH_FIXED : Status::ARITH_DOUBLE,
              rig.transport.statuses().back().arithmetic);
}

}  // namespace

// Shipped suite, set 1, X at 0.40 g: collapses at 4.30 s (at 0.35 g it survives in the fixed engine).
TEST(MonitorLoop, AlarmTimelineEqualsTheFixedPointAnalysisOnACollapsingSuiteRecord) {
  check_timeline_equals_analysis(1, 0, 0.40, true);
}

TEST(MonitorLoop, AlarmTimelineEqualsTheFixedPointAnalysisOnASurvivingSuiteRecord) {
  check_timeline_equals_analysis(1, 0, 0.35, false);
}

// Carry-over (core/work_meter.hpp): a settling wall's chatter does not fit one call's budget, so the engine finishes
// those samples at later calls; the loop publishes each with its own utime and input_seq, in order, and bit-identical
// to the engine without a budget; samples still in work when the stream pauses are published at the next status.
TEST(MonitorLoop, SamplesTheEngineFinishesLaterArePublishedInOrderWithTheirOwnTime) {
  const records::SuiteRecordFile f = records::read_suite_record(records::suite_set_path(ROCKWATCH_SUITE_DIR, 1));
  std::vector<double> ug = f.components_mps2[0];
  const double factor = 0.20 * kG / sim::peak_abs(ug);
  for (double& u : ug) u *= factor;
  fw::MonitorSettings s = paper_settings();
  s.sample_rate_hz = 1.0 / f.dt_s;
  Rig rig(s);
  fw::WallEngineConfig unbudgeted = s.engine;
  unbudgeted.dt_s = f.dt_s;
  unbudgeted.work_budget_units = 0;
  fw::WallEngine ref;
  LONGS_EQUAL(static_cast<int>(fw::WallEngineError::ok), static_cast<int>(ref.init(unbudgeted)));
  std::vector<fw::EngineSample> expected;
  const std::size_t n = 3740;  // through the chatter of samples 3705-3735, and stop there (the stream pauses)
  for (std::size_t k = 0; k < n; ++k) {
    rig.send(accel(static_cast<std::int64_t>(k), ug[k]));
    expected.push_back(k == 0 ? ref.start(ug[k], 0.0) : ref.step(ug[k], 0.0));
  }
  CHECK_TRUE(rig.n_states() < n);  // some samples are still in work
  CHECK_TRUE(rig.loop.counters().samples_late > 0);
  CHECK_TRUE(rig.loop.counters().max_late_calls > 1);
  rig.loop.publish_status(kT0);  // no sample since the last status: the loop finishes them
  rig.loop.publish_status(kT0 + 1000000);
  const std::vector<wall_state_t> states = rig.transport.states();
  LONGS_EQUAL(static_cast<long>(n), static_cast<long>(states.size()));
  for (std::size_t k = 0; k < n; ++k) {
    LONGS_EQUAL(static_cast<long>(k), static_cast<long>(states[k].input_seq));
    CHECK_TRUE(states[k].x_m == expected[k].x_m);
    CHECK_TRUE(states[k].xd_mps == expected[k].xd_mps);
    LONGS_EQUAL(static_cast<long>(expected[k].alarm.level), states[k].alarm_level);
    CHECK_FALSE((states[k].data_quality & (Status::QUALITY_WORK_SHED | Status::QUALITY_OVER_BUDGET)) != 0);
  }
  LONGS_EQUAL(0, static_cast<long>(rig.loop.counters().samples_work_shed));
}

// --arith double: the double engine of `rockwatch simulate --arith double`, bit for bit.
TEST(MonitorLoop, AlarmTimelineEqualsTheDoubleAnalysisOnACollapsingSuiteRecord) {
  check_timeline_equals_analysis(1, 0, 0.40, true, fw::MonitorArithmetic::double_precision);
}

TEST(MonitorLoop, AlarmTimelineEqualsTheDoubleAnalysisOnASurvivingSuiteRecord) {
  check_timeline_equals_analysis(1, 0, 0.30, false, fw::MonitorArithmetic::double_precision);
}

TEST(MonitorLoop, AlarmTimelineEqualsTheDoubleAnalysisWithTheFullModel) {
  check_timeline_equals_analysis(1, 0, 0.40, true, fw::MonitorArithmetic::double_precision, core::ModelKind::full);
}

TEST(MonitorLoop, TheFixedPointEngineRefusesTheFullModel) {
  fw::MonitorSettings s = paper_settings();
  s.engine.model = core::ModelKind::full;
  MemoryTransport t;
  Engines engines;
  fw::MonitorLoop loop;
  CHECK_TRUE(loop.init(s, engines(s), t) == fw::MonitorError::engine);
  CHECK_TRUE(loop.engine_error() == fw::WallEngineError::model_not_supported);
  STRCMP_EQUAL("the fixed-point engine runs the linear model only",
               fw::wall_engine_error_message(fw::WallEngineError::model_not_supported));
  s.arithmetic = fw::MonitorArithmetic::double_precision;
  CHECK_TRUE(loop.init(s, engines(s), t) == fw::MonitorError::ok);
  // The engine given must run the arithmetic the settings ask for.
  CHECK_TRUE(loop.init(s, engines.fixed, t) == fw::MonitorError::arithmetic_invalid);
  s.arithmetic = static_cast<fw::MonitorArithmetic>(7);
  CHECK_TRUE(loop.init(s, engines(s), t) == fw::MonitorError::arithmetic_invalid);
}

// The input of missing sample k of a gap from seq a to seq b (SPEC §12): linear between the last good input before the
// gap and the input that ends it.
static double bridged_input(double before, double after, std::int64_t a, std::int64_t b, std::int64_t k) {
  const double w = static_cast<double>(k - a) / static_cast<double>(b - a);
  return before + w * (after - before);
}

TEST(MonitorLoop, ShortGapBridgedByInterpolatingBetweenTheSamplesOnEitherSide) {
  Rig rig;
  rig.stream(0, 150);
  CHECK_TRUE(rig.ref.stepper().moving());
  // 151..153 missing (3 ≤ max_bridge_samples = 10): interpolated between the inputs of 150 and 154.
  rig.send(accel(154, rocking_ug(154)));
  for (std::int64_t k = 151; k <= 153; ++k) {
    rig.ref.process_wall(q(bridged_input(rocking_ug(150), rocking_ug(154), 150, 154, k)), q(0.0));
  }
  rig.ref.process_wall(q(rocking_ug(154)), q(0.0));
  rig.check_matches_reference();
  const std::vector<wall_state_t> states = rig.transport.states();
  LONGS_EQUAL(155, static_cast<long>(states.size()));
  for (std::int64_t k = 151; k <= 154; ++k) {
    const wall_state_t& s = states[static_cast<std::size_t>(k)];
    LONGS_EQUAL(k, s.input_seq);
    LONGS_EQUAL(kT0 + k * kPeriodUs, s.utime);
    LONGS_EQUAL(Status::QUALITY_GAP_BRIDGED, s.data_quality);
  }
  Expected e;
  e.received = 152;
  e.processed = 155;
  e.bridged = 3;
  e.gaps = 1;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_GAP_BRIDGED, status_quality(rig));
  // Continues normally; a gap of exactly max_bridge_samples is still bridged.
  rig.send(accel(155, rocking_ug(155)));
  rig.ref.process_wall(q(rocking_ug(155)), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(0, rig.last_state().data_quality);
  rig.send(accel(166, rocking_ug(166)));
  for (std::int64_t k = 156; k <= 165; ++k) {
    rig.ref.process_wall(q(bridged_input(rocking_ug(155), rocking_ug(166), 155, 166, k)), q(0.0));
  }
  rig.ref.process_wall(q(rocking_ug(166)), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(13, rig.loop.counters().samples_bridged);
  LONGS_EQUAL(2, rig.loop.counters().gaps);
  LONGS_EQUAL(0, rig.loop.counters().state_resets);
  check_alarm_events_consistent(rig);
}

// A ground that is linear across the gap is restored exactly: the bridged wall is the wall that lost nothing, state for
// state (the inputs are exact binary fractions, so the interpolation is exact). Holding the last input would not be.
TEST(MonitorLoop, GapInALinearGroundIsBridgedExactly) {
  const auto ramp = [](std::int64_t seq) { return 1.0 + 0.125 * static_cast<double>(seq); };  // [m/s²]
  Rig lossless, lossy;
  for (std::int64_t k = 0; k <= 20; ++k) lossless.send(accel(k, ramp(k)));
  for (std::int64_t k = 0; k <= 20; ++k) {
    if (k < 9 || k > 15) lossy.send(accel(k, ramp(k)));  // 9..15 lost: 7 ≤ max_bridge_samples
  }
  const std::vector<wall_state_t> a = lossless.transport.states(), b = lossy.transport.states();
  LONGS_EQUAL(21, static_cast<long>(a.size()));
  LONGS_EQUAL(21, static_cast<long>(b.size()));
  CHECK_TRUE(lossless.loop.counters().samples_bridged == 0);
  LONGS_EQUAL(7, lossy.loop.counters().samples_bridged);
  bool moved = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    LONGS_EQUAL(a[i].input_seq, b[i].input_seq);
    CHECK_TRUE(a[i].x_m == b[i].x_m);
    CHECK_TRUE(a[i].xd_mps == b[i].xd_mps);
    moved = moved || a[i].x_m != 0.0;
  }
  CHECK_TRUE(moved);  // the ramp (1.0 to 3.5 m/s², above the threshold 1.12) rocks the wall: the states say something
}

// A gap ended by a sample whose value is rejected (NaN) is bridged towards the last good value: held, since nothing
// better is known.
TEST(MonitorLoop, GapEndedByARejectedValueIsBridgedTowardsTheLastGoodInput) {
  Rig rig;
  rig.stream(0, 150);
  rig.send(accel(153, std::numeric_limits<double>::quiet_NaN()));
  for (int i = 0; i < 3; ++i) rig.ref.process_wall(q(rocking_ug(150)), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(2, rig.loop.counters().samples_bridged);
  LONGS_EQUAL(1, rig.loop.counters().rejected_not_finite);
}

TEST(MonitorLoop, LongGapDeclaresTheStateUnknownAndRestartsFromRest) {
  Rig rig;
  rig.stream(0, 300);
  CHECK_TRUE(rig.ref.stepper().moving());
  CHECK_TRUE(rig.loop.alarm_level() != core::AlarmLevel::quiet);
  const std::size_t events_before = rig.transport.alarms().size();
  // 11 missing > max_bridge_samples = 10.
  const core::AlarmLevel level_before = rig.loop.alarm_level();
  rig.send(accel(312, rocking_ug(312)));
  rig.ref.restart_motion(q(rocking_ug(312)), q(0.0));
  rig.check_matches_reference();
  const wall_state_t s = rig.last_state();
  LONGS_EQUAL(312, s.input_seq);
  LONGS_EQUAL(Status::QUALITY_STATE_UNKNOWN, s.data_quality);
  LONGS_EQUAL(0, s.moving);
  CHECK_TRUE(s.x_m == 0.0);
  // The motion restarted from rest; the alarm keeps its level (held, not dropped by missing data).
  LONGS_EQUAL(static_cast<long>(level_before), s.alarm_level);
  CHECK_TRUE((s.alarm_reasons & alarm_event_t::REASON_HELD) != 0);
  LONGS_EQUAL(static_cast<long>(events_before), static_cast<long>(rig.transport.alarms().size()));
  Expected e;
  e.received = 302;
  e.processed = 302;
  e.gaps = 1;
  e.resets = 1;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_STATE_UNKNOWN, status_quality(rig));
  // Then steps normally from the new sample.
  rig.send(accel(313, rocking_ug(313)));
  rig.ref.process_wall(q(rocking_ug(313)), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(0, rig.last_state().data_quality);
  check_alarm_events_consistent(rig);
}

TEST(MonitorLoop, DuplicatesAreDropped) {
  Rig rig;
  rig.stream(0, 20);
  rig.send(accel(20, 5.0));  // the last one again
  rig.send(accel(17, 5.0));  // an earlier one again
  LONGS_EQUAL(21, static_cast<long>(rig.n_states()));
  rig.stream(21, 22);
  rig.check_matches_reference();
  Expected e;
  e.received = 25;
  e.processed = 23;
  e.duplicates = 2;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_DUPLICATE, status_quality(rig));
}

TEST(MonitorLoop, OutOfOrderSamplesAreDropped) {
  Rig rig;
  rig.stream(0, 20);
  // 22 before 21: 21 is bridged (halfway between 20 and 22), then arrives too late to be used.
  rig.send(accel(22, rocking_ug(22)));
  rig.ref.process_wall(q(bridged_input(rocking_ug(20), rocking_ug(22), 20, 22, 21)), q(0.0));
  rig.ref.process_wall(q(rocking_ug(22)), q(0.0));
  rig.send(accel(21, rocking_ug(21)));
  rig.check_matches_reference();
  LONGS_EQUAL(23, static_cast<long>(rig.n_states()));
  // A seq far back, within the restart window, never seen: out of order as well.
  rig.send(accel(-500, 0.0));
  Expected e;
  e.received = 24;
  e.processed = 23;
  e.bridged = 1;
  e.gaps = 1;
  e.out_of_order = 2;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_OUT_OF_ORDER | Status::QUALITY_GAP_BRIDGED, status_quality(rig));
  // Received twice: the second is a duplicate.
  rig.send(accel(22, rocking_ug(22)));
  LONGS_EQUAL(1, rig.loop.counters().duplicates);
}

TEST(MonitorLoop, LateSamplesAreCountedAndStillProcessed) {
  Rig rig;
  rig.stream(0, 20);
  rig.send(accel(21, rocking_ug(21)), 50000);  // exactly the limit: not late
  rig.send(accel(22, rocking_ug(22)), 50001);
  rig.ref.process_wall(q(rocking_ug(21)), q(0.0));
  rig.ref.process_wall(q(rocking_ug(22)), q(0.0));
  rig.check_matches_reference();
  const std::vector<wall_state_t> states = rig.transport.states();
  LONGS_EQUAL(0, states[21].data_quality);
  LONGS_EQUAL(Status::QUALITY_LATE, states[22].data_quality);
  Expected e;
  e.received = e.processed = 23;
  e.late = 1;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_LATE, status_quality(rig));
}

TEST(MonitorLoop, NaNIsReplacedByTheLastGoodInput) {
  Rig rig;
  rig.stream(0, 150);
  rig.send(accel(151, std::numeric_limits<double>::quiet_NaN(), 0.5));
  rig.ref.process_wall(q(rocking_ug(150)), q(0.5));
  rig.check_matches_reference();
  LONGS_EQUAL(Status::QUALITY_NOT_FINITE, rig.last_state().data_quality);
  // The good vertical of 151 is the last good one now.
  rig.send(accel(152, rocking_ug(152), std::numeric_limits<double>::quiet_NaN()));
  rig.ref.process_wall(q(rocking_ug(152)), q(0.5));
  rig.check_matches_reference();
  Expected e;
  e.received = e.processed = 153;
  e.not_finite = 2;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_NOT_FINITE, status_quality(rig));
}

TEST(MonitorLoop, InfinityIsReplacedByTheLastGoodInput) {
  Rig rig;
  rig.stream(0, 150);
  rig.send(accel(151, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()));
  rig.ref.process_wall(q(rocking_ug(150)), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(Status::QUALITY_NOT_FINITE, rig.last_state().data_quality);
  Expected e;
  e.received = e.processed = 152;
  e.not_finite = 1;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_NOT_FINITE, status_quality(rig));
}

TEST(MonitorLoop, LiftOffWithSubStepsMovesUntilTheCrossing) {
  Rig rig;  // the default: 5 sub-steps of 1 ms per 5 ms sample
  LONGS_EQUAL(5, rig.ref.substeps());
  rig.stream(0, 150);
  CHECK_TRUE(rig.ref.stepper().moving());
  const wall_state_t before = rig.last_state();
  rig.send(accel(151, rocking_ug(151), -10.0));  // G falls linearly from 9.81 to −0.19: valid for 4 sub-steps of 5
  rig.ref.process_wall(q(rocking_ug(151)), q(-10.0));
  rig.check_matches_reference();
  const wall_state_t s = rig.last_state();
  CHECK_TRUE(s.x_m != before.x_m);
  LONGS_EQUAL(Status::QUALITY_LIFT_OFF, s.data_quality);
  CHECK_TRUE((s.alarm_reasons & alarm_event_t::REASON_INPUT_INVALID) != 0);
}

TEST(MonitorLoop, ValuesBeyondTheSensorRangeAreReplaced) {
  fw::MonitorSettings s = paper_settings();
  s.sensor_range_mps2 = 5.0;
  Rig rig(s);
  rig.stream(0, 150);
  rig.send(accel(151, 5.0, -5.0));  // at the range: accepted
  rig.ref.process_wall(q(5.0), q(-5.0));
  rig.check_matches_reference();
  LONGS_EQUAL(0, rig.last_state().data_quality);
  rig.send(accel(152, -5.5, 1.0));
  rig.ref.process_wall(q(5.0), q(1.0));
  rig.check_matches_reference();
  LONGS_EQUAL(Status::QUALITY_OUT_OF_RANGE, rig.last_state().data_quality);
  rig.send(accel(153, 1.0, 1e300));
  rig.ref.process_wall(q(1.0), q(1.0));
  rig.check_matches_reference();
  Expected e;
  e.received = e.processed = 154;
  e.out_of_range = 2;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_OUT_OF_RANGE, status_quality(rig));
}

// One integration step per sample here: with sub-steps the lift-off sample's ramp continues into the next sample
// interval, whose engine step then also reports invalid input (LiftOffHoldsTheStateAndIsFlagged says more).
fw::MonitorSettings one_step_per_sample() {
  fw::MonitorSettings s = paper_settings();
  s.engine.max_step_s = 1.0 / s.sample_rate_hz;
  return s;
}

// With one step per sample the whole step is outside the model: the state is held. With sub-steps (the default)
// the input is linear between samples, so the wall moves until G = g + v̈ reaches zero inside the interval and is held
// from there (LiftOffWithSubStepsMovesUntilTheCrossing).
TEST(MonitorLoop, LiftOffHoldsTheStateAndIsFlagged) {
  Rig rig(one_step_per_sample());
  rig.stream(0, 150);
  CHECK_TRUE(rig.ref.stepper().moving());
  const wall_state_t before = rig.last_state();
  rig.send(accel(151, rocking_ug(151), -10.0));  // G = 9.81 − 10 < 0
  rig.ref.process_wall(q(rocking_ug(151)), q(-10.0));
  rig.check_matches_reference();
  const wall_state_t s = rig.last_state();
  CHECK_TRUE(s.x_m == before.x_m);
  CHECK_TRUE(s.xd_mps == before.xd_mps);
  LONGS_EQUAL(Status::QUALITY_LIFT_OFF, s.data_quality);
  CHECK_TRUE((s.alarm_reasons & alarm_event_t::REASON_INPUT_INVALID) != 0);
  rig.send(accel(152, rocking_ug(152), -kG));  // G = 0 exactly
  rig.ref.process_wall(q(rocking_ug(152)), q(-kG));
  LONGS_EQUAL(Status::QUALITY_LIFT_OFF, rig.last_state().data_quality);
  rig.stream(153, 160);
  rig.check_matches_reference();
  LONGS_EQUAL(0, rig.last_state().data_quality);
  Expected e;
  e.received = e.processed = 161;
  e.lift_off = 2;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_LIFT_OFF, status_quality(rig));
}

TEST(MonitorLoop, PublisherRestartRestartsTheStateAndFollowsTheNewNumbering) {
  Rig rig;
  rig.stream(0, 1500);
  CHECK_TRUE(rig.loop.alarm_level() != core::AlarmLevel::quiet);
  const std::size_t events_before = rig.transport.alarms().size();
  const core::AlarmLevel level_before = rig.loop.alarm_level();
  rig.send(accel(499, 0.0));  // 1001 back: beyond the window of 1000
  rig.ref.restart_motion(q(0.0), q(0.0));
  rig.check_matches_reference();
  const wall_state_t s = rig.last_state();
  LONGS_EQUAL(499, s.input_seq);
  LONGS_EQUAL(Status::QUALITY_PUBLISHER_RESTART, s.data_quality);
  // The alarm keeps its level across the restart (COLLAPSED stays latched); no event.
  LONGS_EQUAL(static_cast<long>(level_before), s.alarm_level);
  LONGS_EQUAL(static_cast<long>(events_before), static_cast<long>(rig.transport.alarms().size()));
  rig.send(accel(500, 0.1));
  rig.ref.process_wall(q(0.1), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(0, rig.last_state().data_quality);
  // Within the window: out of order, not a restart.
  rig.send(accel(-500, 0.0));
  Expected e;
  e.received = 1504;
  e.processed = 1503;
  e.restarts = 1;
  e.out_of_order = 1;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_PUBLISHER_RESTART | Status::QUALITY_OUT_OF_ORDER, status_quality(rig));
  check_alarm_events_consistent(rig);
}

// A replay or sensor restarted after a few samples numbers from 0 again with the current time: a restart, not a run
// of duplicates, however small the jump back.
TEST(MonitorLoop, SequenceBackWithTimeForwardIsAPublisherRestart) {
  Rig rig;
  rig.stream(0, 300);
  ground_accel_t m = accel(0, 0.0);
  m.utime = kT0 + 400 * kPeriodUs;  // later than sample 300
  rig.send(m);
  rig.ref.restart_motion(q(0.0), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(0, rig.last_state().input_seq);
  LONGS_EQUAL(Status::QUALITY_PUBLISHER_RESTART, rig.last_state().data_quality);
  ground_accel_t next = accel(1, 0.05);
  next.utime = m.utime + kPeriodUs;
  rig.send(next);
  rig.ref.process_wall(q(0.05), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(0, rig.last_state().data_quality);
  rig.send(next);  // the same sample again: a duplicate (same seq, same time)
  Expected e;
  e.received = 304;
  e.processed = 303;
  e.restarts = 1;
  e.duplicates = 1;
  check_counters(rig.loop.counters(), e);
}

// One sample stamped an hour ahead of the monitor's clock, after 100 good ones, then the publisher restarts (seq
// from 0, the current time): the stamp is flagged and counted, and does not hide the restart — before the fix the
// restarted publisher's first 101 samples were dropped as duplicates and out of order.
TEST(MonitorLoop, ASampleStampedFarAheadDoesNotHideAPublisherRestart) {
  Rig rig;
  rig.stream(0, 99);
  ground_accel_t future = accel(100, rocking_ug(100));
  future.utime = kT0 + 100 * kPeriodUs + 3600LL * 1000000;
  const std::vector<std::uint8_t> b = encode(future);
  const std::int64_t receive_utime = kT0 + 100 * kPeriodUs + kReceiveDelayUs;  // the monitor's clock
  rig.loop.on_message(kAccel, b.data(), b.size(), receive_utime);
  rig.ref.process_wall(q(rocking_ug(100)), q(0.0));  // its value is processed by its seq
  rig.check_matches_reference();
  LONGS_EQUAL(Status::QUALITY_TIME_UNTRUSTED, rig.last_state().data_quality);
  LONGS_EQUAL(1, rig.loop.counters().time_untrusted);
  // The restarted publisher: seq 0, 1, … stamped with the current time, which is before the bad stamp.
  for (std::int64_t k = 0; k <= 100; ++k) {
    ground_accel_t m = accel(k, 0.0);
    m.utime = kT0 + (200 + k) * kPeriodUs;
    rig.send(m);
  }
  Expected e;
  e.received = 100 + 1 + 101;
  e.processed = e.received;
  e.restarts = 1;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(100, rig.last_state().input_seq);
  LONGS_EQUAL(1, rig.loop.counters().time_untrusted);
}

// A stamp far in the past is untrusted too; a sample within the tolerance is not (late, at most).
TEST(MonitorLoop, TimeToleranceBothWays) {
  Rig rig;
  rig.stream(0, 9);
  rig.send(accel(10, 0.0), fw::kDefaultClockTolerance_us + 1);  // received 10 s after its stamp: untrusted (and late)
  LONGS_EQUAL(1, rig.loop.counters().time_untrusted);
  LONGS_EQUAL(1, rig.loop.counters().late);
  rig.send(accel(11, 0.0), fw::kDefaultClockTolerance_us);  // exactly at the tolerance: trusted, late
  rig.send(accel(12, 0.0), -fw::kDefaultClockTolerance_us);  // stamped 10 s ahead: trusted
  LONGS_EQUAL(1, rig.loop.counters().time_untrusted);
  rig.send(accel(13, 0.0), -fw::kDefaultClockTolerance_us - 1);
  LONGS_EQUAL(2, rig.loop.counters().time_untrusted);
  LONGS_EQUAL(Status::QUALITY_TIME_UNTRUSTED, rig.last_state().data_quality);
}

// The tolerance is a setting (clock_tolerance_us): with 2 ms, a sample received 2 ms after its stamp is trusted and
// one received 2 ms + 1 µs after is not, both ways; the values are processed all the same, and a publisher restart
// (seq back, time forward) is still detected — by trusted times only: an untrusted stamp just before it does not count.
TEST(MonitorLoop, ASmallClockToleranceFlagsJustOutsideAndStillDetectsRestarts) {
  fw::MonitorSettings s = paper_settings();
  constexpr std::int64_t kTol = 2000;  // 2 ms
  s.clock_tolerance_us = kTol;
  Rig rig(s);
  rig.stream(0, 9);
  LONGS_EQUAL(0, rig.loop.counters().time_untrusted);
  rig.send(accel(10, 0.0), kTol);  // just inside (late: 2 ms is under the 50 ms late limit, so not late either)
  LONGS_EQUAL(0, rig.loop.counters().time_untrusted);
  LONGS_EQUAL(0, rig.last_state().data_quality);
  rig.send(accel(11, 0.0), kTol + 1);  // just outside, behind
  LONGS_EQUAL(1, rig.loop.counters().time_untrusted);
  LONGS_EQUAL(Status::QUALITY_TIME_UNTRUSTED, rig.last_state().data_quality);
  LONGS_EQUAL(11, rig.last_state().input_seq);  // processed by its seq
  rig.send(accel(12, 0.0), -kTol);  // stamped 2 ms ahead: just inside
  LONGS_EQUAL(1, rig.loop.counters().time_untrusted);
  LONGS_EQUAL(0, rig.last_state().data_quality);
  rig.send(accel(13, 0.0), -kTol - 1);  // just outside, ahead
  LONGS_EQUAL(2, rig.loop.counters().time_untrusted);
  LONGS_EQUAL(Status::QUALITY_TIME_UNTRUSTED, rig.last_state().data_quality);
  // The default would have trusted all four.
  CHECK_TRUE(kTol + 1 < fw::kDefaultClockTolerance_us);

  // A restarted publisher (seq from 0, its time after the last trusted one), received within the tolerance.
  ground_accel_t m = accel(0, 0.0);
  m.utime = kT0 + 400 * kPeriodUs;
  rig.send(m, kTol / 2);
  LONGS_EQUAL(1, rig.loop.counters().publisher_restarts);
  LONGS_EQUAL(Status::QUALITY_PUBLISHER_RESTART, rig.last_state().data_quality);
  LONGS_EQUAL(0, rig.last_state().input_seq);
  for (std::int64_t k = 1; k <= 20; ++k) {
    ground_accel_t n = accel(k, 0.0);
    n.utime = m.utime + k * kPeriodUs;
    rig.send(n, kTol / 2);
  }
  // A second restart whose first sample arrives just outside the tolerance: its time is not evidence, so it is
  // taken for a repeat of the earlier seq 0 (a duplicate) ...
  ground_accel_t late = accel(0, 0.0);
  late.utime = m.utime + 100 * kPeriodUs;
  rig.send(late, kTol + 1);
  LONGS_EQUAL(1, rig.loop.counters().publisher_restarts);
  LONGS_EQUAL(1, rig.loop.counters().duplicates);
  LONGS_EQUAL(3, rig.loop.counters().time_untrusted);
  // ... and the next one, within it, is the restart.
  ground_accel_t next = accel(1, 0.0);
  next.utime = late.utime + kPeriodUs;
  rig.send(next, kTol);
  LONGS_EQUAL(2, rig.loop.counters().publisher_restarts);
  LONGS_EQUAL(1, rig.last_state().input_seq);
  LONGS_EQUAL(Status::QUALITY_PUBLISHER_RESTART, rig.last_state().data_quality);
}

// The host's receive path reports its totals; the status carries them and flags an increase once.
TEST(MonitorLoop, DatagramCountsFromTheHostAreInTheStatus) {
  Rig rig;
  rig.stream(0, 3);
  rig.loop.note_datagram_counts(2, 5);
  rig.loop.publish_status(kT0 + 1000000);
  rig.loop.note_datagram_counts(2, 5);  // no change: no flag
  rig.loop.publish_status(kT0 + 2000000);
  const std::vector<monitor_status_t> st = rig.transport.statuses();
  CHECK_TRUE(st.size() >= 2);
  const monitor_status_t& first = st[st.size() - 2];
  const monitor_status_t& second = st.back();
  LONGS_EQUAL(2, first.datagrams_rejected);
  LONGS_EQUAL(5, first.datagrams_from_other_sources);
  CHECK_TRUE((first.data_quality & Status::QUALITY_BAD_DATAGRAM) != 0);
  LONGS_EQUAL(2, second.datagrams_rejected);
  CHECK_TRUE((second.data_quality & Status::QUALITY_BAD_DATAGRAM) == 0);
}

TEST(MonitorLoop, WrongMessageTypesOnTheInputChannelsAreDecodeErrors) {
  Rig rig;
  rig.stream(0, 5);
  wall_state_t ws{};
  ws.seq = 6;
  rig.send_bytes(kAccel, encode(ws));
  ground_accel_batch_t batch{};
  batch.seq = 6;
  batch.schema_version = 1;
  batch.sample_period_us = 5000;
  batch.count = 1;
  rig.send_bytes(kAccel, encode(batch));        // a batch on the single-sample channel
  rig.send_bytes(kBatch, encode(accel(6, 0.0)));  // a single sample on the batch channel
  rig.send_bytes("ROCKWATCH_WALL_STATE", encode(accel(6, 0.0)));  // not an input channel: ignored
  rig.send_bytes("SOMETHING_ELSE", encode(accel(6, 0.0)));
  rig.loop.on_message(nullptr, nullptr, 0, kT0);
  LONGS_EQUAL(6, static_cast<long>(rig.n_states()));
  Expected e;
  e.received = e.processed = 6;
  e.decode_errors = 3;
  e.ignored = 3;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_DECODE_ERROR, status_quality(rig));
  rig.stream(6, 7);
  rig.check_matches_reference();
}

TEST(MonitorLoop, TruncatedAndPaddedBytesAreDecodeErrors) {
  Rig rig;
  rig.stream(0, 5);
  std::vector<std::uint8_t> b = encode(accel(6, 0.0));
  const std::vector<std::uint8_t> truncated(b.begin(), b.end() - 1);
  rig.send_bytes(kAccel, truncated);
  const std::vector<std::uint8_t> only_fingerprint(b.begin(), b.begin() + 8);
  rig.send_bytes(kAccel, only_fingerprint);
  b.push_back(0);
  rig.send_bytes(kAccel, b);
  rig.loop.on_message(kAccel, b.data(), 0, kT0);
  rig.loop.on_message(kAccel, nullptr, 10, kT0);
  LONGS_EQUAL(6, static_cast<long>(rig.n_states()));
  Expected e;
  e.received = e.processed = 6;
  e.decode_errors = 5;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_DECODE_ERROR, status_quality(rig));
}

TEST(MonitorLoop, BatchesAreSplitIntoSamples) {
  Rig rig;
  ground_accel_batch_t batch{};
  batch.utime = kT0;
  batch.seq = 0;
  batch.schema_version = 1;
  batch.sample_period_us = 5000;
  batch.count = ground_accel_batch_t::MAX_SAMPLES;
  for (int i = 0; i < batch.count; ++i) batch.ug_mps2[i] = rocking_ug(i);
  std::vector<std::uint8_t> b = encode(batch);
  rig.loop.on_message(kBatch, b.data(), b.size(), kT0 + 250000);
  batch.utime = kT0 + 50 * kPeriodUs;
  batch.seq = 50;
  batch.count = 3;
  for (int i = 0; i < 3; ++i) batch.ug_mps2[i] = rocking_ug(50 + i);
  for (int i = 3; i < 50; ++i) batch.ug_mps2[i] = std::numeric_limits<double>::quiet_NaN();  // unused entries
  b = encode(batch);
  rig.loop.on_message(kBatch, b.data(), b.size(), kT0 + 265000);
  rig.ref.reset_wall(q(rocking_ug(0)), q(0.0));
  for (int k = 1; k <= 52; ++k) rig.ref.process_wall(q(rocking_ug(k)), q(0.0));
  rig.check_matches_reference();
  const std::vector<wall_state_t> states = rig.transport.states();
  LONGS_EQUAL(53, static_cast<long>(states.size()));
  for (std::int64_t k = 0; k < 53; ++k) {
    LONGS_EQUAL(k, states[static_cast<std::size_t>(k)].input_seq);
    LONGS_EQUAL(kT0 + k * kPeriodUs, states[static_cast<std::size_t>(k)].utime);
  }
  Expected e;
  e.received = e.processed = 53;
  check_counters(rig.loop.counters(), e);
  // Lateness of a batch: its newest sample's time (here 50 ms + 1 µs before reception) for all its samples.
  batch.utime = kT0 + 53 * kPeriodUs;
  batch.seq = 53;
  b = encode(batch);
  rig.loop.on_message(kBatch, b.data(), b.size(), kT0 + 55 * kPeriodUs + 50001);
  LONGS_EQUAL(3, rig.loop.counters().late);
  LONGS_EQUAL(Status::QUALITY_LATE, rig.last_state().data_quality);
}

TEST(MonitorLoop, BadBatchFieldsAndSchemaVersionsAreDecodeErrors) {
  Rig rig;
  rig.stream(0, 5);
  ground_accel_batch_t batch{};
  batch.utime = kT0 + 6 * kPeriodUs;
  batch.seq = 6;
  batch.schema_version = 1;
  batch.sample_period_us = 5000;
  batch.count = 0;
  rig.send_bytes(kBatch, encode(batch));
  batch.count = 51;
  rig.send_bytes(kBatch, encode(batch));
  batch.count = -1;
  rig.send_bytes(kBatch, encode(batch));
  batch.count = 2;
  batch.sample_period_us = 0;
  rig.send_bytes(kBatch, encode(batch));
  batch.sample_period_us = 5000;
  batch.schema_version = 2;
  rig.send_bytes(kBatch, encode(batch));
  ground_accel_t single = accel(6, 0.0);
  single.schema_version = 2;
  rig.send(single);
  single.schema_version = 0;
  rig.send(single);
  LONGS_EQUAL(6, static_cast<long>(rig.n_states()));
  Expected e;
  e.received = e.processed = 6;
  e.decode_errors = 7;
  check_counters(rig.loop.counters(), e);
  LONGS_EQUAL(Status::QUALITY_DECODE_ERROR, status_quality(rig));
  // The stream goes on.
  batch.schema_version = 1;
  rig.send_bytes(kBatch, encode(batch));
  LONGS_EQUAL(8, static_cast<long>(rig.n_states()));
}

TEST(MonitorLoop, SensorFlagsAreCountedAndFlagged) {
  Rig rig;
  rig.stream(0, 5);
  rig.send(accel(6, rocking_ug(6), 0.0, ground_accel_t::SENSOR_CLIPPED | ground_accel_t::SENSOR_CLOCK_UNSYNC));
  rig.ref.process_wall(q(rocking_ug(6)), q(0.0));
  rig.check_matches_reference();
  LONGS_EQUAL(Status::QUALITY_SENSOR_FLAG, rig.last_state().data_quality);
  Expected e;
  e.received = e.processed = 7;
  e.sensor_flags = 1;
  check_counters(rig.loop.counters(), e);
}

TEST(MonitorLoop, StatusCarriesTheCountersAndTheQualitySinceTheLastStatus) {
  Rig rig(one_step_per_sample());
  rig.loop.publish_status(kT0);  // before any sample
  rig.stream(0, 150);
  rig.send(accel(150, 0.0));                                           // duplicate
  rig.send(accel(153, rocking_ug(153)));                               // gap of 2, bridged
  rig.send(accel(152, 0.0));                                           // out of order
  rig.send(accel(154, std::numeric_limits<double>::quiet_NaN()));      // not finite
  rig.send(accel(155, 100.0));                                         // out of range
  rig.send(accel(156, 0.0, -20.0));                                    // lift-off
  rig.send(accel(157, 0.0), 100000);                                   // late
  rig.send(accel(170, 0.0));                                           // long gap: reset
  rig.send(accel(-900, 0.0));                                          // restart
  rig.send_bytes(kAccel, std::vector<std::uint8_t>(3, 0));             // decode error
  rig.send(accel(-899, 0.0, 0.0, ground_accel_t::SENSOR_CLIPPED));     // sensor flag
  rig.send_bytes("OTHER_CHANNEL", encode(accel(0, 0.0)));              // ignored
  rig.loop.note_log_write_failure();                                   // the host's log failed twice
  rig.loop.note_log_write_failure();
  rig.transport.fail = true;
  rig.loop.publish_status(kT0 + 1000000);                              // a publish failure (this status is lost)
  rig.transport.fail = false;
  rig.loop.publish_status(kT0 + 2000000);
  rig.loop.publish_status(kT0 + 3000000);
  const std::vector<monitor_status_t> st = rig.transport.statuses();
  LONGS_EQUAL(3, static_cast<long>(st.size()));
  LONGS_EQUAL(0, st[0].seq);
  LONGS_EQUAL(Status::ARITH_FIXED, st[0].arithmetic);
  LONGS_EQUAL(Status::QUALITY_MONITOR_RESTARTED, st[0].data_quality);
  LONGS_EQUAL(0, st[0].samples_received);
  const monitor_status_t& m = st[1];
  const fw::MonitorCounters& c = rig.loop.counters();
  LONGS_EQUAL(2, m.seq);  // seq 1 was the status the transport failed to send
  LONGS_EQUAL(kT0 + 2000000, m.utime);
  LONGS_EQUAL(3, m.schema_version);
  LONGS_EQUAL(Status::SCHEMA_VERSION, m.schema_version);
  LONGS_EQUAL(ROCKWATCH_EXPECTED_VERSION_MAJOR, m.version_major);
  LONGS_EQUAL(ROCKWATCH_EXPECTED_VERSION_MINOR, m.version_minor);
  LONGS_EQUAL(ROCKWATCH_EXPECTED_VERSION_PATCH, m.version_patch);
  CHECK_TRUE(m.config_digest == 0x1234567890abcdefLL);
  LONGS_EQUAL(161, m.samples_received);
  LONGS_EQUAL(161, m.samples_processed);
  LONGS_EQUAL(2, m.samples_bridged);
  LONGS_EQUAL(2, m.gaps);
  LONGS_EQUAL(1, m.state_resets);
  LONGS_EQUAL(1, m.duplicates);
  LONGS_EQUAL(1, m.out_of_order);
  LONGS_EQUAL(1, m.late);
  LONGS_EQUAL(1, m.rejected_not_finite);
  LONGS_EQUAL(1, m.rejected_out_of_range);
  LONGS_EQUAL(1, m.lift_off);
  LONGS_EQUAL(1, m.publisher_restarts);
  LONGS_EQUAL(1, m.decode_errors);
  LONGS_EQUAL(0, m.saturated);
  LONGS_EQUAL(0, m.worst_step_ns);  // no step clock installed
  LONGS_EQUAL(1, m.sensor_flags);
  LONGS_EQUAL(0, m.time_untrusted);
  LONGS_EQUAL(0, m.datagrams_rejected);
  LONGS_EQUAL(0, m.datagrams_from_other_sources);
  LONGS_EQUAL(1, m.messages_ignored);
  LONGS_EQUAL(1, m.publish_failures);
  LONGS_EQUAL(2, m.log_write_failures);
  LONGS_EQUAL(Status::ARITH_FIXED, m.arithmetic);
  LONGS_EQUAL(c.samples_received, m.samples_received);
  LONGS_EQUAL(c.samples_processed, m.samples_processed);
  LONGS_EQUAL(static_cast<long>(rig.loop.alarm_level()), m.alarm_level);
  const std::int32_t all_faults = Status::QUALITY_GAP_BRIDGED | Status::QUALITY_STATE_UNKNOWN |
                                  Status::QUALITY_NOT_FINITE | Status::QUALITY_OUT_OF_RANGE | Status::QUALITY_LIFT_OFF |
                                  Status::QUALITY_DUPLICATE | Status::QUALITY_OUT_OF_ORDER | Status::QUALITY_LATE |
                                  Status::QUALITY_PUBLISHER_RESTART | Status::QUALITY_DECODE_ERROR |
                                  Status::QUALITY_SENSOR_FLAG | Status::QUALITY_LOG_WRITE_FAILED;
  LONGS_EQUAL(all_faults, m.data_quality);
  // Cleared by the status; the counters are not.
  LONGS_EQUAL(0, st[2].data_quality);
  LONGS_EQUAL(3, st[2].seq);
  LONGS_EQUAL(161, st[2].samples_received);
}

TEST(MonitorLoop, ListenerSeesEveryAlarmEventAfterItIsPublished) {
  Rig rig;
  rig.stream(0, 1000);
  const std::vector<alarm_event_t> events = rig.transport.alarms();
  CHECK_TRUE(events.size() >= 2);
  LONGS_EQUAL(static_cast<long>(events.size()), static_cast<long>(rig.listener.events.size()));
  for (std::size_t i = 0; i < events.size(); ++i) {
    const alarm_event_t& a = events[i];
    const alarm_event_t& b = rig.listener.events[i];
    CHECK_TRUE(encode(a) == encode(b));
    LONGS_EQUAL(1, a.schema_version);
  }
  check_alarm_events_consistent(rig);
}

TEST(MonitorLoop, PublishFailuresAreCountedAndTheLoopGoesOn) {
  Rig rig;
  rig.transport.fail = true;
  rig.stream(0, 9);
  rig.loop.publish_status(kT0);
  const fw::MonitorCounters& c = rig.loop.counters();
  LONGS_EQUAL(10, c.samples_processed);
  LONGS_EQUAL(0, c.states_published);
  LONGS_EQUAL(11 + c.alarm_events, c.publish_failures);
  rig.transport.fail = false;
  rig.stream(10, 10);
  rig.check_matches_reference();
  LONGS_EQUAL(1, c.states_published);
}

namespace {
std::int64_t g_fake_ns = 0;
std::int64_t fake_clock() {
  g_fake_ns += 700;
  return g_fake_ns;
}
}  // namespace

TEST(MonitorLoop, WorstStepTimeFromTheStepClock) {
  Rig rig;
  rig.loop.set_step_clock(&fake_clock);
  rig.stream(0, 20);
  LONGS_EQUAL(700, rig.loop.counters().worst_step_ns);
  rig.loop.publish_status(kT0);
  LONGS_EQUAL(700, rig.transport.statuses().back().worst_step_ns);
}

TEST(MonitorLoop, NothingHappensBeforeInit) {
  MemoryTransport t;
  fw::MonitorLoop loop;
  const std::vector<std::uint8_t> b = encode(accel(0, 0.0));
  loop.on_message(kAccel, b.data(), b.size(), kT0);
  loop.publish_status(kT0);
  LONGS_EQUAL(0, loop.counters().samples_received);
  LONGS_EQUAL(0, static_cast<long>(t.sent.size()));
}

namespace {
void check_refused(const fw::MonitorSettings& s, fw::MonitorError expected, const char* mention) {
  MemoryTransport t;
  Engines engines;
  fw::MonitorLoop loop;
  const fw::MonitorError e = loop.init(s, engines(s), t);
  LONGS_EQUAL(static_cast<long>(expected), static_cast<long>(e));
  STRCMP_CONTAINS(mention, fw::monitor_error_message(e));
  // A refused loop stays inert.
  const std::vector<std::uint8_t> b = encode(accel(0, 0.0));
  loop.on_message(kAccel, b.data(), b.size(), kT0);
  LONGS_EQUAL(0, loop.counters().samples_received);
  LONGS_EQUAL(0, static_cast<long>(t.sent.size()));
}
}  // namespace

TEST(MonitorLoop, InitRefusesBadSettingsNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  using E = fw::MonitorError;
  fw::MonitorSettings s = paper_settings();
  s.sample_rate_hz = 20.0;  // 50 ms steps: beyond the engine's 30 ms
  check_refused(s, E::sample_rate_out_of_range, "sample_rate_hz");
  s.sample_rate_hz = 0.0;
  check_refused(s, E::sample_rate_out_of_range, "sample_rate_hz");
  s.sample_rate_hz = 20000.0;
  check_refused(s, E::sample_rate_out_of_range, "(0, 10000]");
  s.sample_rate_hz = nan;
  check_refused(s, E::sample_rate_out_of_range, "sample_rate_hz");
  s = paper_settings();
  s.max_bridge_samples = -1;
  check_refused(s, E::bridge_out_of_range, "max_bridge_samples");
  s.max_bridge_samples = 1001;
  check_refused(s, E::bridge_out_of_range, "[0, 1000]");
  s = paper_settings();
  s.sensor_range_mps2 = 0.0;
  check_refused(s, E::sensor_range_out_of_range, "sensor_range_mps2");
  s.sensor_range_mps2 = 80.5;
  check_refused(s, E::sensor_range_out_of_range, "(0, 80]");
  s.sensor_range_mps2 = nan;
  check_refused(s, E::sensor_range_out_of_range, "sensor_range_mps2");
  s = paper_settings();
  s.late_limit_s = 0.0;
  check_refused(s, E::late_limit_out_of_range, "late_limit_s");
  s.late_limit_s = 61.0;
  check_refused(s, E::late_limit_out_of_range, "late_limit_s");
  s = paper_settings();
  s.restart_window = 0;
  check_refused(s, E::restart_window_out_of_range, "restart_window");
  s = paper_settings();
  s.clock_tolerance_us = 0;
  check_refused(s, E::clock_tolerance_out_of_range, "clock_tolerance_us");
  s.clock_tolerance_us = -1;
  check_refused(s, E::clock_tolerance_out_of_range, "clock_tolerance_us");
  s.clock_tolerance_us = fw::kMaxClockTolerance_us + 1;
  check_refused(s, E::clock_tolerance_out_of_range, "clock_tolerance_us");
  s.clock_tolerance_us = fw::kMaxClockTolerance_us;
  {
    MemoryTransport t;
    Engines engines;
    fw::MonitorLoop loop;
    CHECK_TRUE(loop.init(s, engines(s), t) == E::ok);
  }
  s = paper_settings();
  s.channels.status[0] = '\0';
  check_refused(s, E::channel_name_invalid, "channel names");
  s = paper_settings();
  std::memset(s.channels.alarm, 'A', fw::kChannelNameMax);
  check_refused(s, E::channel_name_invalid, "NUL-terminated");
  s = paper_settings();
  std::strcpy(s.channels.accel_batch, s.channels.accel);
  check_refused(s, E::channel_name_invalid, "input channel");
  s = paper_settings();
  std::strcpy(s.channels.wall_state, s.channels.accel_batch);
  check_refused(s, E::channel_name_invalid, "input channel");
  // The engine's own validation.
  s = paper_settings();
  s.engine.wall.b_m = -0.1;
  {
    MemoryTransport t;
    Engines engines;
    fw::MonitorLoop loop;
    LONGS_EQUAL(static_cast<long>(E::engine), static_cast<long>(loop.init(s, engines(s), t)));
    CHECK_TRUE(loop.engine_error() == fw::WallEngineError::wall_invalid);
    STRCMP_CONTAINS("engine", fw::monitor_error_message(E::engine));
  }
  s = paper_settings();
  s.engine.r_energy = 1.5;
  check_refused(s, E::engine, "engine");
  // Same output channel names are fine (the loop only publishes on them); the defaults work.
  s = paper_settings();
  {
    MemoryTransport t;
    Engines engines;
    fw::MonitorLoop loop;
    CHECK_TRUE(loop.init(s, engines(s), t) == E::ok);
    STRCMP_EQUAL("ok", fw::monitor_error_message(E::ok));
  }
}

TEST(MonitorLoop, ExtremeSequenceAndTimeValuesDoNotOverflow) {
  Rig rig;
  const std::int64_t big = std::numeric_limits<std::int64_t>::max();
  ground_accel_t m = accel(big - 1, 0.1);
  m.utime = big;
  rig.send(m, 0);
  m.seq = big;
  rig.send(m, 0);
  m.seq = std::numeric_limits<std::int64_t>::min();  // far below: a restart
  m.utime = std::numeric_limits<std::int64_t>::min();
  rig.send(m, 0);
  ground_accel_batch_t batch{};
  batch.utime = big;
  batch.seq = big - 1;
  batch.schema_version = 1;
  batch.sample_period_us = 2000000000;
  batch.count = 50;
  const std::vector<std::uint8_t> b = encode(batch);
  rig.loop.on_message(kBatch, b.data(), b.size(), std::numeric_limits<std::int64_t>::min());
  const fw::MonitorCounters& c = rig.loop.counters();
  LONGS_EQUAL(53, c.samples_received);
  CHECK_TRUE(c.publisher_restarts >= 1);
  CHECK_TRUE(c.samples_processed >= 3);
}
