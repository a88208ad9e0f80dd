// firmware::MonitorLoop with the wall observer: ground and wall-sensor messages in (encoded, through on_message), the
// fused estimate (wall_estimate_t) and the alarm reasons out. A "true" wall (the double stepper with another r) makes
// the sensor readings; the monitor's nominal wall must follow it while the sensors flow (REASON_MEASURED), fall back
// to the model when they stop (REASON_PREDICTED, SENSOR_LOST) and follow again when they return. Each bad input of the
// wall sensors is injected on its own with the counter and flag it must produce; an alarm that coincides with a
// sensor fault says so (REASON_SENSOR_FAULT). The fixed-point and the double engines agree on the same stream.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/sim/double_wall_engine.hpp"

#include <CppUTest/TestHarness.h>

#include "memory_transport.hpp"

// The file's own scope in a unity build (tests/CMakeLists.txt): its helpers' names recur in other files of the suite.
namespace unity_test_monitor_loop_observer {

using namespace rockwatch;
namespace fw = rockwatch::firmware;
using Status = rockwatch::monitor_status_t;
using Estimate = rockwatch::wall_estimate_t;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.005;
constexpr std::int64_t kPeriodUs = 5000;
constexpr std::int64_t kT0 = 1700000000000000;  // µs since 1970
constexpr std::int64_t kReceiveDelayUs = 1000;
const char* const kAccel = "ROCKWATCH_ACCEL";
const char* const kSensor = "ROCKWATCH_WALL_SENSOR";

using test::MemoryTransport;
using test::encode;

std::int64_t utime_of(std::int64_t seq) { return kT0 + seq * kPeriodUs; }

// 2 Hz at 0.2 g for the first 1.5 s, then quiet: the paper wall rocks with impacts (WARNING and above), then rocks
// freely and settles.
double shaking_ug(std::int64_t seq) {
  return seq < 300 ? 0.20 * kG * std::sin(2.0 * kPi * 2.0 * double(seq) * kDt) : 0.0;
}

// Deterministic small noise (xorshift): ±0.2 mm.
class Noise {
 public:
  double next() {
    s_ ^= s_ << 13;
    s_ ^= s_ >> 7;
    s_ ^= s_ << 17;
    return (double(s_ >> 11) / 9007199254740992.0 - 0.5) * 0.4e-3;
  }

 private:
  std::uint64_t s_ = 88172645463325252ull;
};

fw::MonitorSettings observer_settings(fw::MonitorArithmetic arith = fw::MonitorArithmetic::fixed_point) {
  fw::MonitorSettings s;
  s.engine.wall = core::paper_wall();
  s.engine.r_energy = core::restitution_energy_ratio(s.engine.wall, core::Restitution{});  // r_exp
  s.engine.observer_enabled = true;
  s.arithmetic = arith;
  s.sample_rate_hz = 200.0;
  return s;
}

// The loop with the observer, and the true wall that the sensors measure: the same ground motion, but the wall
// dissipates like r_ana (the nominal wall assumes r_exp = 0.9 r_ana).
struct Rig {
  MemoryTransport transport;
  fw::WallEngine fixed;
  sim::DoubleWallEngine dbl;
  fw::MonitorLoop loop;
  core::RockingStepper<double> truth;
  Noise noise;
  std::int64_t next_seq = 0;

  explicit Rig(const fw::MonitorSettings& s = observer_settings()) {
    fw::SampleEngine& engine =
        s.arithmetic == fw::MonitorArithmetic::double_precision ? static_cast<fw::SampleEngine&>(dbl) : fixed;
    CHECK_TRUE(loop.init(s, engine, transport) == fw::MonitorError::ok);
    core::StepperOptions o;
    o.dt_s = kDt;
    truth.init(core::make_stepper_setup(s.engine.wall, core::ModelKind::linear, core::r_ana(s.engine.wall), o));
  }
  void ground(std::int64_t seq, double ug, std::int64_t receive_delay_us = kReceiveDelayUs) {
    ground_accel_t m{};
    m.utime = utime_of(seq);
    m.seq = seq;
    m.schema_version = 1;
    m.ug_mps2 = ug;
    const std::vector<std::uint8_t> b = encode(m);
    loop.on_message(kAccel, b.data(), b.size(), m.utime + receive_delay_us);
  }
  void sensor(std::int64_t utime, double x, std::int32_t valid = wall_sensor_t::VALID_X, double a = 0.0,
              std::int32_t status = 0, std::int64_t receive_utime = 0) {
    wall_sensor_t m{};
    m.utime = utime;
    m.seq = utime / kPeriodUs;
    m.schema_version = 1;
    m.x_mid_m = x;
    m.a_mid_mps2 = a;
    m.valid = valid;
    m.sensor_status = status;
    const std::vector<std::uint8_t> b = encode(m);
    loop.on_message(kSensor, b.data(), b.size(), receive_utime != 0 ? receive_utime : utime + kReceiveDelayUs);
  }
  // The true wall steps to this sample (the first sample is its start, as the monitor's).
  double true_x(std::int64_t seq, double ug) {
    if (seq == 0) {
      truth.reset(ug, 0.0);
    } else {
      truth.step(ug, 0.0);
    }
    return truth.state().x_m;
  }
  // One sample: the wall sensor (unless `with_sensor` is false) reading the true wall, then the ground sample of
  // the same time. `reading` replaces the true reading when given.
  void sample(double ug, bool with_sensor = true, const double* reading = nullptr, std::int32_t status = 0) {
    const std::int64_t seq = next_seq++;
    const double x = true_x(seq, ug) + noise.next();
    if (with_sensor) sensor(utime_of(seq), reading != nullptr ? *reading : x, wall_sensor_t::VALID_X, 0.0, status);
    ground(seq, ug);
  }
  void run(std::int64_t n, bool with_sensor = true) {
    for (std::int64_t k = 0; k < n; ++k) sample(shaking_ug(next_seq), with_sensor);
  }
  wall_state_t last_state() const { return transport.states().back(); }
  Estimate last_estimate() const { return transport.estimates().back(); }
  std::int32_t status_quality() {
    loop.publish_status(kT0);
    return transport.statuses().back().data_quality & ~Status::QUALITY_MONITOR_RESTARTED;
  }
};

bool has(std::int32_t bits, std::int32_t bit) { return (bits & bit) != 0; }

}  // namespace

TEST_GROUP(MonitorLoopObserver){};

TEST(MonitorLoopObserver, PublishesTheFusedEstimateThatFollowsTheRealWall) {
  Rig rig;
  rig.run(600);
  const std::vector<wall_state_t> states = rig.transport.states();
  const std::vector<Estimate> estimates = rig.transport.estimates();
  LONGS_EQUAL(600, static_cast<long>(states.size()));
  LONGS_EQUAL(600, static_cast<long>(estimates.size()));
  LONGS_EQUAL(600, rig.loop.counters().estimates_published);
  LONGS_EQUAL(600, rig.loop.counters().sensor_samples_received);
  double max_error = 0.0, max_true = 0.0;
  for (std::size_t k = 0; k < estimates.size(); ++k) {
    const Estimate& e = estimates[k];
    LONGS_EQUAL(Estimate::SCHEMA_VERSION, e.schema_version);
    LONGS_EQUAL(static_cast<long>(k), e.seq);
    LONGS_EQUAL(static_cast<long>(k), e.input_seq);
    CHECK_TRUE(e.utime == utime_of(static_cast<std::int64_t>(k)));
    // The alarm sees the fused state: wall_state_t carries the same x.
    CHECK_TRUE(e.x_m == states[k].x_m);
    CHECK_TRUE(e.xd_mps == states[k].xd_mps);
    if (k > 0) {
      CHECK_TRUE(has(states[k].alarm_reasons, alarm_event_t::REASON_MEASURED));
      CHECK_FALSE(has(states[k].alarm_reasons, alarm_event_t::REASON_PREDICTED));
      CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_X_ACTIVE));
    }
    CHECK_FALSE(has(states[k].alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
    CHECK_FALSE(has(states[k].data_quality, Status::QUALITY_SENSOR_FAULT));
  }
  // Against the true wall, replayed the same way.
  Rig replay;
  for (std::int64_t k = 0; k < 600; ++k) {
    const double x = replay.true_x(k, shaking_ug(k));
    max_true = std::fmax(max_true, std::fabs(x));
    max_error = std::fmax(max_error, std::fabs(estimates[static_cast<std::size_t>(k)].x_m - x));
  }
  CHECK_TRUE(max_true > 0.01);   // the wall rocked
  CHECK_TRUE(max_error < 2e-3);  // within a few sensor noises of the real wall, impacts included
  const Estimate last = rig.last_estimate();
  CHECK_TRUE(last.x_updates > 300);
  CHECK_TRUE(last.sigma_x_m >= 0.0 && last.sigma_x_m < 1e-3);
  CHECK_TRUE(last.r_estimate > 0.0 && last.r_estimate <= 1.0);
  LONGS_EQUAL(600, last.sensor_samples);
  LONGS_EQUAL(0, last.not_finite + last.out_of_range + last.stuck + last.queue_overflow + last.stale + last.dropouts);
  CHECK_FALSE(has(rig.status_quality(), Status::QUALITY_SENSOR_FAULT));
}

TEST(MonitorLoopObserver, PredictedAfterADropoutMeasuredAgainWhenTheSensorsReturn) {
  Rig rig;
  rig.run(150);
  CHECK_TRUE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_MEASURED));
  rig.run(100, false);  // 0.5 s without sensors: beyond the dropout time (0.25 s)
  wall_state_t st = rig.last_state();
  Estimate e = rig.last_estimate();
  CHECK_TRUE(has(st.alarm_reasons, alarm_event_t::REASON_PREDICTED));
  CHECK_FALSE(has(st.alarm_reasons, alarm_event_t::REASON_MEASURED));
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_LOST));
  CHECK_FALSE(has(e.sensor_health, Estimate::SENSOR_X_ACTIVE));
  LONGS_EQUAL(1, e.dropouts);
  // A dropout is not a sensor fault: the model alone is flagged PREDICTED, not SENSOR_FAULT.
  CHECK_FALSE(has(st.alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
  rig.run(60);
  st = rig.last_state();
  e = rig.last_estimate();
  CHECK_TRUE(has(st.alarm_reasons, alarm_event_t::REASON_MEASURED));
  CHECK_FALSE(has(e.sensor_health, Estimate::SENSOR_LOST));
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_X_ACTIVE));
  LONGS_EQUAL(1, e.dropouts);
}

TEST(MonitorLoopObserver, GroundWithoutSensorsRunsTheModelAloneFlagged) {
  Rig rig;
  rig.run(200, false);
  const Estimate e = rig.last_estimate();
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_LOST));
  LONGS_EQUAL(1, e.dropouts);
  LONGS_EQUAL(0, e.sensor_samples);
  CHECK_TRUE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_PREDICTED));
  // The open-loop state is exactly the engine without the observer.
  fw::MonitorSettings off = observer_settings();
  off.engine.observer_enabled = false;
  MemoryTransport t;
  fw::WallEngine engine;
  fw::MonitorLoop loop;
  CHECK_TRUE(loop.init(off, engine, t) == fw::MonitorError::ok);
  for (std::int64_t k = 0; k < 200; ++k) {
    ground_accel_t m{};
    m.utime = utime_of(k);
    m.seq = k;
    m.schema_version = 1;
    m.ug_mps2 = shaking_ug(k);
    const std::vector<std::uint8_t> b = encode(m);
    loop.on_message(kAccel, b.data(), b.size(), m.utime + kReceiveDelayUs);
  }
  CHECK_TRUE(t.states().back().x_m == rig.last_state().x_m);
  CHECK_TRUE(t.states().back().xd_mps == rig.last_state().xd_mps);
  CHECK_TRUE(t.estimates().empty());
}

TEST(MonitorLoopObserver, SensorsWithoutGroundOverflowTheQueueCountedAndFlagged) {
  Rig rig;
  constexpr int kSent = core::WallObserver<core::FixedRockingStepper>::kQueueCapacity + 24;
  for (int k = 0; k < kSent; ++k) rig.sensor(utime_of(k), 0.0);
  LONGS_EQUAL(kSent, rig.loop.counters().sensor_samples_received);
  LONGS_EQUAL(kSent - core::WallObserver<core::FixedRockingStepper>::kQueueCapacity,
              rig.fixed.observer_counters().queue_overflow);
  LONGS_EQUAL(0, rig.loop.counters().samples_processed);
  CHECK_TRUE(rig.transport.estimates().empty());
  CHECK_TRUE(has(rig.status_quality(), Status::QUALITY_SENSOR_FAULT));
  // Then the ground stream starts: the overflow shows in the first step's health, and the monitor goes on. (The
  // first step applies the queued samples that are not stale: more than one call's budget, so it is published a few
  // calls later, carried over: core/wall_observer.hpp.)
  for (int k = 0; k < 4; ++k) rig.ground(kSent + k, 0.0);
  bool flagged = false;
  for (const Estimate& e : rig.transport.estimates()) flagged = flagged || has(e.sensor_health, Estimate::SENSOR_QUEUE_OVERFLOW);
  CHECK_TRUE(flagged);
  bool fault_reason = false;
  for (const auto& st : rig.transport.states()) {
    fault_reason = fault_reason || has(st.alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT);
  }
  CHECK_TRUE(fault_reason);
  LONGS_EQUAL(24, rig.last_estimate().queue_overflow);
}

TEST(MonitorLoopObserver, NotFiniteAndOutOfRangeReadingsAreDiscardedCountedAndFlagged) {
  Rig rig;
  rig.run(100);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  rig.sample(shaking_ug(rig.next_seq), true, &nan);
  Estimate e = rig.last_estimate();
  LONGS_EQUAL(1, e.not_finite);
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_NOT_FINITE));
  CHECK_TRUE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
  CHECK_TRUE(has(rig.last_state().data_quality, Status::QUALITY_SENSOR_FAULT));
  rig.sample(shaking_ug(rig.next_seq), true, &inf);
  LONGS_EQUAL(2, rig.last_estimate().not_finite);
  // An infinite acceleration reading (with a good displacement) counts as well.
  const std::int64_t seq = rig.next_seq++;
  rig.sensor(utime_of(seq), rig.true_x(seq, shaking_ug(seq)), wall_sensor_t::VALID_X | wall_sensor_t::VALID_A, -inf);
  rig.ground(seq, shaking_ug(seq));
  LONGS_EQUAL(3, rig.last_estimate().not_finite);
  const double far = 1.0;  // beyond the default transducer range (0.5 m)
  rig.sample(shaking_ug(rig.next_seq), true, &far);
  e = rig.last_estimate();
  LONGS_EQUAL(1, e.out_of_range);
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_OUT_OF_RANGE));
  CHECK_TRUE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
  // The good readings around them still keep the state measured.
  CHECK_TRUE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_MEASURED));
  rig.run(5);
  CHECK_FALSE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
  CHECK_TRUE(has(rig.status_quality(), Status::QUALITY_SENSOR_FAULT));
}

TEST(MonitorLoopObserver, AStuckTransducerWhileTheGroundShakesIsFlagged) {
  Rig rig;
  rig.run(100);
  CHECK_EQUAL(1, rig.last_state().moving);
  const double frozen = rig.last_estimate().x_m;
  for (int k = 0; k < 60; ++k) rig.sample(shaking_ug(rig.next_seq), true, &frozen);
  const Estimate e = rig.last_estimate();
  CHECK_TRUE(e.stuck > 0);
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_STUCK));
  CHECK_TRUE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
}

TEST(MonitorLoopObserver, ADisplacementJumpWhileTheGroundIsQuietIsAFault) {
  Rig rig;
  rig.run(310);  // shaking, then the first quiet samples: the wall still rocks freely
  CHECK_EQUAL(1, rig.last_state().moving);
  CHECK_TRUE(shaking_ug(rig.next_seq) == 0.0);
  const double jumped = rig.last_estimate().x_m + 0.05;
  rig.sample(0.0, true, &jumped);
  const Estimate e = rig.last_estimate();
  LONGS_EQUAL(1, e.jumps);
  LONGS_EQUAL(0, e.reinitialised);
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_JUMP));
  CHECK_TRUE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
  CHECK_TRUE(has(rig.last_state().data_quality, Status::QUALITY_SENSOR_FAULT));
}

TEST(MonitorLoopObserver, MotionReportedWhileTheGroundIsQuietIsAFaultNotAnAlarm) {
  Rig rig;
  for (int k = 0; k < 20; ++k) rig.sample(0.0);
  const double moving = 0.05;  // 50 mm while the wall rests and the ground is still
  for (int k = 0; k < 20; ++k) rig.sample(0.0, true, &moving);
  const Estimate e = rig.last_estimate();
  LONGS_EQUAL(20, e.motion_while_quiet);
  LONGS_EQUAL(0, e.reinitialised);
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_MOTION_WHILE_QUIET));
  const wall_state_t st = rig.last_state();
  CHECK_EQUAL(0, st.moving);
  CHECK_TRUE(st.x_m == 0.0);
  LONGS_EQUAL(static_cast<long>(core::AlarmLevel::quiet), st.alarm_level);
  CHECK_TRUE(rig.transport.alarms().empty());
  CHECK_TRUE(has(st.alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
}

TEST(MonitorLoopObserver, StreamsMisalignedByMoreThanASampleAreFlaggedAndStaleOnesDropped) {
  Rig rig;
  rig.run(50);
  // A reading 3 samples old when it arrives (within max_age, 50 ms): applied, flagged misaligned.
  std::int64_t seq = rig.next_seq++;
  double x = rig.true_x(seq, 0.0);
  rig.sensor(utime_of(seq - 3), x);
  rig.ground(seq, shaking_ug(seq));
  Estimate e = rig.last_estimate();
  LONGS_EQUAL(1, e.misaligned);
  LONGS_EQUAL(0, e.stale);
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_MISALIGNED));
  // 100 ms old (beyond max_age): dropped as stale, a fault.
  seq = rig.next_seq++;
  x = rig.true_x(seq, 0.0);
  rig.sensor(utime_of(seq - 20), x);
  rig.ground(seq, shaking_ug(seq));
  e = rig.last_estimate();
  LONGS_EQUAL(1, e.stale);
  CHECK_TRUE(has(e.sensor_health, Estimate::SENSOR_STALE));
  CHECK_TRUE(has(rig.last_state().alarm_reasons, alarm_event_t::REASON_SENSOR_FAULT));
  // A reading ahead of the ground stream waits for it (never applied early).
  seq = rig.next_seq++;
  rig.sensor(utime_of(seq + 2), 0.0);
  rig.ground(seq, shaking_ug(seq));
  const std::int64_t updates = rig.last_estimate().x_updates + rig.last_estimate().rejected;
  const std::int64_t before = e.x_updates + e.rejected;
  LONGS_EQUAL(before, updates);
}

TEST(MonitorLoopObserver, SensorMessagesBadlyEncodedOrStampedFarFromTheClockAreCountedAndDropped) {
  Rig rig;
  rig.run(10);
  const std::vector<std::uint8_t> garbage(20, 0x5a);
  rig.loop.on_message(kSensor, garbage.data(), garbage.size(), kT0);
  LONGS_EQUAL(1, rig.loop.counters().decode_errors);
  wall_sensor_t wrong{};
  wrong.schema_version = 2;
  const std::vector<std::uint8_t> b = encode(wrong);
  rig.loop.on_message(kSensor, b.data(), b.size(), kT0);
  LONGS_EQUAL(2, rig.loop.counters().decode_errors);
  // Stamped 20 s ahead of the ground stream: not pushed.
  rig.sensor(utime_of(10) + 20000000, 0.0, wall_sensor_t::VALID_X, 0.0, 0, utime_of(10));
  // Received 20 s after its time, but on the ground stream's clock (a replay faster than real time runs both streams
  // ahead of the monitor's clock): used.
  rig.sensor(utime_of(10), 0.0, wall_sensor_t::VALID_X, 0.0, 0, utime_of(10) - 20000000);
  LONGS_EQUAL(11, rig.fixed.observer_counters().samples);
  LONGS_EQUAL(1, rig.loop.counters().sensor_time_untrusted);
  LONGS_EQUAL(1, rig.loop.counters().time_untrusted);
  const std::int32_t q = rig.status_quality();
  CHECK_TRUE(has(q, Status::QUALITY_DECODE_ERROR));
  CHECK_TRUE(has(q, Status::QUALITY_TIME_UNTRUSTED));
  // A repeated datagram: dropped, counted, not measured twice.
  rig.sensor(utime_of(10), 0.0);
  LONGS_EQUAL(1, rig.loop.counters().sensor_duplicates);
  LONGS_EQUAL(11, rig.fixed.observer_counters().samples);
  CHECK_TRUE(has(rig.status_quality(), Status::QUALITY_DUPLICATE));
  rig.ground(10, 0.0);
  LONGS_EQUAL(1, rig.last_estimate().time_untrusted);
  LONGS_EQUAL(1, rig.last_estimate().duplicates);
}

TEST(MonitorLoopObserver, AnAlarmThatCoincidesWithASensorFaultSaysSo) {
  // The sensor node reports a status bit on every sample (e.g. its clock unsynchronised): the readings are used, and
  // every alarm level change carries REASON_SENSOR_FAULT.
  Rig rig;
  for (int k = 0; k < 400; ++k) rig.sample(shaking_ug(rig.next_seq), true, nullptr, wall_sensor_t::SENSOR_CLOCK_UNSYNC);
  const std::vector<alarm_event_t> alarms = rig.transport.alarms();
  CHECK_TRUE(alarms.size() >= 2);
  bool warning = false;
  for (const alarm_event_t& a : alarms) {
    CHECK_TRUE(has(a.reasons, alarm_event_t::REASON_SENSOR_FAULT));
    CHECK_TRUE(has(a.reasons, alarm_event_t::REASON_MEASURED));
    warning = warning || a.level >= alarm_event_t::LEVEL_WARNING;
  }
  CHECK_TRUE(warning);
  CHECK_TRUE(has(rig.last_estimate().sensor_health, Estimate::SENSOR_FLAG));
  LONGS_EQUAL(400, rig.last_estimate().sensor_flags);
}

TEST(MonitorLoopObserver, FixedAndDoubleEnginesAgreeOnTheSameStream) {
  Rig fixed(observer_settings(fw::MonitorArithmetic::fixed_point));
  Rig dbl(observer_settings(fw::MonitorArithmetic::double_precision));
  fixed.run(600);
  dbl.run(600);
  const std::vector<Estimate> a = fixed.transport.estimates(), b = dbl.transport.estimates();
  LONGS_EQUAL(static_cast<long>(a.size()), static_cast<long>(b.size()));
  double max_dx = 0.0, max_dxd = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    max_dx = std::fmax(max_dx, std::fabs(a[k].x_m - b[k].x_m));
    max_dxd = std::fmax(max_dxd, std::fabs(a[k].xd_mps - b[k].xd_mps));
  }
  CHECK_TRUE(max_dx < 0.5e-3);
  CHECK_TRUE(max_dxd < 0.02);
  DOUBLES_EQUAL(a.back().r_estimate, b.back().r_estimate, 0.01);
  DOUBLES_EQUAL(a.back().bias_m, b.back().bias_m, 1e-4);
  LONGS_EQUAL(a.back().x_updates, b.back().x_updates);
  const std::vector<alarm_event_t> fa = fixed.transport.alarms(), da = dbl.transport.alarms();
  LONGS_EQUAL(static_cast<long>(fa.size()), static_cast<long>(da.size()));
  for (std::size_t k = 0; k < fa.size() && k < da.size(); ++k) LONGS_EQUAL(fa[k].level, da[k].level);
}

// Each sensor's fusion status (wall_estimate_t schema 3) is the observer's, through the message's encoding, in both
// arithmetics; a reading far off is published rejected with a test ratio above 1, the last fused time unchanged.
TEST(MonitorLoopObserver, PublishesEachSensorsFusionStatus) {
  for (const fw::MonitorArithmetic arithmetic :
       {fw::MonitorArithmetic::fixed_point, fw::MonitorArithmetic::double_precision}) {
    Rig rig(observer_settings(arithmetic));
    rig.run(300);
    const core::ObserverSensorStatus x = arithmetic == fw::MonitorArithmetic::fixed_point
                                             ? rig.fixed.observer().x_status()
                                             : rig.dbl.observer().x_status();
    const Estimate ok = rig.last_estimate();
    CHECK_TRUE(ok.x_innovation_var_m2 == x.innovation_variance);
    CHECK_TRUE(ok.x_test_ratio == x.test_ratio);
    CHECK_TRUE(ok.innovation_x_m == x.innovation);
    CHECK_TRUE(ok.x_last_fused_utime == x.last_fused_us);
    CHECK_FALSE(ok.x_rejected);
    CHECK_TRUE(ok.x_test_ratio < 1.0);
    CHECK_TRUE(ok.x_innovation_var_m2 >= 0.5e-3 * 0.5e-3 * 0.999);  // at least the transducer's variance
    CHECK_TRUE(ok.x_last_fused_utime == utime_of(299));
    // No accelerometer in this stream: nothing tried, nothing fused.
    CHECK_FALSE(ok.a_rejected);
    CHECK_TRUE(ok.a_last_fused_utime == 0 && ok.a_innovation_var_m2ps4 == 0.0 && ok.a_test_ratio == 0.0);
    // One reading 10 cm off.
    const std::int64_t seq = rig.next_seq++;
    const double x_true = rig.true_x(seq, shaking_ug(seq));
    rig.sensor(utime_of(seq), x_true + 0.1);
    rig.ground(seq, shaking_ug(seq));
    const Estimate bad = rig.last_estimate();
    CHECK_TRUE(bad.x_rejected);
    CHECK_TRUE(bad.x_test_ratio > 1.0);
    CHECK_TRUE(bad.x_last_fused_utime == utime_of(299));
    CHECK_TRUE(has(bad.sensor_health, Estimate::SENSOR_REJECTED));
  }
}

// The appended fields survive LCM's encoding (append-only: the fields before them keep their places).
TEST(MonitorLoopObserver, TheEstimateMessageRoundTripsWithTheSensorStatus) {
  Estimate m{};
  m.utime = 123456789;
  m.schema_version = Estimate::SCHEMA_VERSION;
  m.clamped = 7;
  m.x_innovation_var_m2 = 2.5e-7;
  m.x_test_ratio = 0.25;
  m.x_rejected = 0;
  m.x_last_fused_utime = 123450000;
  m.a_innovation_var_m2ps4 = 3.5e-3;
  m.a_test_ratio = 4.5;
  m.a_rejected = 1;
  m.a_last_fused_utime = 123440000;
  const std::vector<std::uint8_t> bytes = encode(m);
  Estimate d{};
  LONGS_EQUAL(static_cast<long>(bytes.size()), d.decode(bytes.data(), 0, static_cast<int>(bytes.size())));
  LONGS_EQUAL(3, Estimate::SCHEMA_VERSION);
  CHECK_TRUE(d.utime == m.utime && d.clamped == m.clamped && d.schema_version == m.schema_version);
  CHECK_TRUE(d.x_innovation_var_m2 == m.x_innovation_var_m2 && d.x_test_ratio == m.x_test_ratio);
  CHECK_TRUE(d.x_rejected == 0 && d.x_last_fused_utime == m.x_last_fused_utime);
  CHECK_TRUE(d.a_innovation_var_m2ps4 == m.a_innovation_var_m2ps4 && d.a_test_ratio == m.a_test_ratio);
  CHECK_TRUE(d.a_rejected == 1 && d.a_last_fused_utime == m.a_last_fused_utime);
}

TEST(MonitorLoopObserver, WithoutTheObserverTheSensorChannelIsNotAnInput) {
  fw::MonitorSettings off = observer_settings();
  off.engine.observer_enabled = false;
  Rig rig(off);
  rig.run(20);
  LONGS_EQUAL(20, rig.loop.counters().messages_ignored);
  LONGS_EQUAL(0, rig.loop.counters().sensor_samples_received);
  CHECK_TRUE(rig.transport.estimates().empty());
  CHECK_FALSE(has(rig.last_state().alarm_reasons,
                  alarm_event_t::REASON_MEASURED | alarm_event_t::REASON_PREDICTED | alarm_event_t::REASON_SENSOR_FAULT));
}

TEST(MonitorLoopObserver, BadObserverSettingsAreRefused) {
  MemoryTransport t;
  fw::WallEngine engine;
  fw::MonitorLoop loop;
  fw::MonitorSettings s = observer_settings();
  s.engine.observer.x_noise_m = 0.0;
  CHECK_TRUE(loop.init(s, engine, t) == fw::MonitorError::engine);
  CHECK_TRUE(loop.engine_error() == fw::WallEngineError::observer_invalid);
  s = observer_settings();
  s.engine.observer.gate_chi2 = 0.5;
  sim::DoubleWallEngine dbl;
  s.arithmetic = fw::MonitorArithmetic::double_precision;
  CHECK_TRUE(loop.init(s, dbl, t) == fw::MonitorError::engine);
  CHECK_TRUE(dbl.observer_error() == core::ObserverError::gate_out_of_range);
  // The sensor channel is an input: it may not be another channel's name.
  s = observer_settings();
  std::snprintf(s.channels.wall_sensor, fw::kChannelNameMax, "%s", "ROCKWATCH_ACCEL");
  CHECK_TRUE(loop.init(s, engine, t) == fw::MonitorError::channel_name_invalid);
  s = observer_settings();
  std::snprintf(s.channels.wall_estimate, fw::kChannelNameMax, "%s", "ROCKWATCH_WALL_SENSOR");
  CHECK_TRUE(loop.init(s, engine, t) == fw::MonitorError::channel_name_invalid);
  // Without the observer those two names are not looked at (configurations valid before stay valid).
  s.engine.observer_enabled = false;
  CHECK_TRUE(loop.init(s, engine, t) == fw::MonitorError::ok);
}

}  // namespace unity_test_monitor_loop_observer
