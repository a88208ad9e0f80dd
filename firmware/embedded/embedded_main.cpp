// Minimal Cortex-M4 image for the embedded build proof (scripts/embedded-build.sh): initialises a WallEngine for
// the design paper's wall and runs it over a short built-in synthetic input, first on the sensor path
// (WallEngine::process), then inside the monitor loop (MonitorLoop: each sample encoded as a ground_accel_t, as
// the sensor node sends it, decoded, checked, stepped, and the wall state, alarm events and status encoded for a
// static transport that only counts them), so that the linker keeps everything a real firmware would (init in
// double, the loop and the engine per sample) and arm-none-eabi-size reports a realistic footprint. Not run on a
// target; linked against newlib-nano with nosys stubs. Then the monitor loop once more on an engine with the wall
// observer (core::WallObserver in fixed point): a wall_sensor_t message before every ground sample, so that the image
// holds the observer's per-sample path (push, covariance prediction, gated updates) and its size is measured with it.
//
// The input is a table computed at compile time (constexpr Taylor series; no libm, no floating point per
// sample on the sensor path): one period of a 2 Hz sine at 0.30 g, replayed for 4 s with an integer gain that
// grows every second (0.3, 0.6, 0.9, 1.2 g): the wall rocks with impacts, then collapses (reset() and again).
#include <array>
#include <cstdint>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/monitor_loop.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/ground_accel_t.hpp"
#include "rockwatch/wall_sensor_t.hpp"

namespace {

namespace core = rockwatch::core;
namespace firmware = rockwatch::firmware;

constexpr double kPi = 3.14159265358979323846;
constexpr int kTableSamples = 100;  // one period of 2 Hz at 200 Hz

// sin(x) for x in [-π, π] by its Taylor series (error < 1e-12 with 14 terms there): compile-time only.
constexpr double taylor_sin(double x) {
  double term = x, sum = x;
  for (int k = 1; k < 14; ++k) {
    term *= -x * x / double((2 * k) * (2 * k + 1));
    sum += term;
  }
  return sum;
}

// 0.30 g · sin(2π n / 100) in Q7.24 raw [m/s²].
constexpr std::array<std::int32_t, kTableSamples> make_sine_table() {
  std::array<std::int32_t, kTableSamples> t{};
  for (int n = 0; n < kTableSamples; ++n) {
    double x = 2.0 * kPi * double(n) / double(kTableSamples);
    if (x > kPi) x -= 2.0 * kPi;
    t[static_cast<std::size_t>(n)] = core::AccelQ7_24(0.30 * 9.81 * taylor_sin(x)).raw();
  }
  return t;
}

constexpr std::array<std::int32_t, kTableSamples> kSine = make_sine_table();

// Results escape through volatiles so that nothing is optimised away.
volatile std::uint32_t g_impacts = 0;
volatile std::uint32_t g_collapses = 0;
volatile std::uint8_t g_level = 0;

firmware::WallEngine g_engine;  // static storage: no heap, no large stack frame
firmware::WallEngine g_observed;  // the same with the wall observer

// The loop's transport: where a real firmware would hand the bytes to its radio or UART.
class CountingTransport final : public firmware::Transport {
 public:
  bool publish(const char* /*channel*/, const std::uint8_t* /*data*/, std::size_t size) override {
    messages = messages + 1;
    bytes = bytes + size;
    return true;
  }
  volatile std::uint32_t messages = 0;
  volatile std::size_t bytes = 0;
};

firmware::MonitorLoop g_loop;
firmware::MonitorLoop g_observed_loop;
std::uint8_t g_message[64];  // one encoded ground_accel_t (48 bytes) or wall_sensor_t (52 bytes)

// The input sample n (0.3 g · gain(n) · sine) [m/s²] in Q7.24.
core::AccelQ7_24 input_sample(int n) {
  const core::AccelQ7_24 gain(1 + n / (2 * kTableSamples));  // 1 … 4, one step per second
  const core::AccelQ7_24 unit = core::AccelQ7_24::from_raw(kSine[std::size_t(n % kTableSamples)]);
  return core::fixed_mul<core::AccelQ7_24>(gain, unit);
}

}  // namespace

// Eigen's assertions (the embedded build keeps them: no NDEBUG) end here instead of in newlib's __assert_func,
// which would pull fiprintf and the whole stdio into the image. A real firmware would log and reset.
extern "C" [[noreturn]] void __assert_func(const char*, int, const char*, const char*) {
  for (;;) {
  }
}

// Transport's virtual destructor puts a deleting destructor into every transport's vtable, and that one calls
// operator delete. Nothing here is ever deleted (no heap: the symbol audit forbids malloc and new); these stubs
// satisfy the reference without newlib's heap. A real firmware would log and reset.
void operator delete(void*) noexcept {
  for (;;) {
  }
}
void operator delete(void*, std::size_t) noexcept {
  for (;;) {
  }
}

int main() {
  firmware::WallEngineConfig config;
  config.wall = core::paper_wall();
  config.r_energy = core::r_exp(config.wall);
  if (g_engine.init(config) != firmware::WallEngineError::ok) return 1;

  firmware::SensorSampleQ sample;
  sample << core::AccelQ7_24{}, core::AccelQ7_24{}, core::AccelQ7_24{};
  g_engine.reset(sample);
  constexpr int kSamples = 8 * kTableSamples;  // 4 s
  for (int n = 0; n < kSamples; ++n) {
    sample(0) = input_sample(n);
    const firmware::WallEngineOutput& out = g_engine.process(sample);
    g_impacts = g_impacts + out.step.impacts_total;
    g_level = static_cast<std::uint8_t>(out.alarm.level);
    if (out.step.collapsed) {
      g_collapses = g_collapses + 1;
      g_engine.reset(sample);
    }
  }
  if (g_collapses == 0) return 2;

  // The monitor loop on the same engine, fed encoded messages at 200 Hz.
  firmware::MonitorSettings settings;
  settings.engine = config;
  settings.sample_rate_hz = 200.0;
  CountingTransport transport;  // on the stack: a static one would register its destructor with atexit
  if (g_loop.init(settings, g_engine, transport) != firmware::MonitorError::ok) return 3;
  constexpr std::int64_t kPeriodUs = 5000;
  for (int n = 0; n < kSamples; ++n) {
    rockwatch::ground_accel_t m;
    m.utime = std::int64_t{n} * kPeriodUs;
    m.seq = n;
    m.schema_version = rockwatch::ground_accel_t::SCHEMA_VERSION;
    m.ug_mps2 = input_sample(n).to_double();
    m.vg_mps2 = 0.0;
    m.sensor_status = 0;
    const int size = m.encode(g_message, 0, static_cast<int>(sizeof g_message));
    if (size <= 0) return 4;
    g_loop.on_message(settings.channels.accel, g_message, static_cast<std::size_t>(size), m.utime + 1000);
    g_level = static_cast<std::uint8_t>(g_loop.alarm_level());
  }
  g_loop.publish_status(std::int64_t{kSamples} * kPeriodUs);
  if (g_loop.counters().samples_processed != kSamples) return 5;

  // The loop with the observer: the transducer reads the fixed-point engine's own displacement (the model of the
  // first pass) with a 1 mm offset, the accelerometer the ground; both go through wall_sensor_t.
  // Through int32 constants: arm-none-eabi-g++ 12 warns (-Wconversion) on `VALID_X | VALID_A` of lcm-gen's enums.
  constexpr std::int32_t kValidX = rockwatch::wall_sensor_t::VALID_X, kValidA = rockwatch::wall_sensor_t::VALID_A;
  constexpr std::int32_t kValidXA = kValidX | kValidA;
  firmware::MonitorSettings observed = settings;
  observed.engine.observer_enabled = true;
  if (g_observed_loop.init(observed, g_observed, transport) != firmware::MonitorError::ok) return 6;
  for (int n = 0; n < kSamples; ++n) {
    const std::int64_t utime = std::int64_t{n} * kPeriodUs;
    rockwatch::wall_sensor_t s;
    s.utime = utime;
    s.seq = n;
    s.schema_version = rockwatch::wall_sensor_t::SCHEMA_VERSION;
    s.x_mid_m = g_observed.stepper().x_m().to_double() + 1e-3;
    s.a_mid_mps2 = input_sample(n).to_double();
    s.valid = kValidXA;
    s.sensor_status = 0;
    int size = s.encode(g_message, 0, static_cast<int>(sizeof g_message));
    if (size <= 0) return 7;
    g_observed_loop.on_message(observed.channels.wall_sensor, g_message, static_cast<std::size_t>(size), utime + 500);
    rockwatch::ground_accel_t m;
    m.utime = utime;
    m.seq = n;
    m.schema_version = rockwatch::ground_accel_t::SCHEMA_VERSION;
    m.ug_mps2 = input_sample(n).to_double();
    m.vg_mps2 = 0.0;
    m.sensor_status = 0;
    size = m.encode(g_message, 0, static_cast<int>(sizeof g_message));
    if (size <= 0) return 4;
    g_observed_loop.on_message(observed.channels.accel, g_message, static_cast<std::size_t>(size), utime + 1000);
    g_level = static_cast<std::uint8_t>(g_observed_loop.alarm_level());
  }
  g_observed_loop.publish_status(std::int64_t{kSamples} * kPeriodUs);
  return g_observed_loop.counters().estimates_published == kSamples ? 0 : 8;
}
