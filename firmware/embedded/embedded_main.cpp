// Minimal Cortex-M4 image for the embedded build proof (scripts/embedded-build.sh): initialises a WallEngine for
// the design paper's wall and runs it over a short built-in synthetic input, so that the linker keeps everything
// a real firmware would (init in double, process() per sample) and arm-none-eabi-size reports a realistic
// footprint. Not run on a target; linked against newlib-nano with nosys stubs.
//
// The input is a table computed at compile time (constexpr Taylor series; no libm, no floating point per
// sample): one period of a 2 Hz sine at 0.30 g, replayed for 4 s with an integer gain that grows every second
// (0.3, 0.6, 0.9, 1.2 g): the wall rocks with impacts, then collapses (reset() and again).
#include <array>
#include <cstdint>

#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/firmware/wall_engine.hpp"

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

}  // namespace

// Eigen's assertions (the embedded build keeps them: no NDEBUG) end here instead of in newlib's __assert_func,
// which would pull fiprintf and the whole stdio into the image. A real firmware would log and reset.
extern "C" [[noreturn]] void __assert_func(const char*, int, const char*, const char*) {
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
    const core::AccelQ7_24 gain(1 + n / (2 * kTableSamples));  // 1 … 4, one step per second
    const core::AccelQ7_24 unit = core::AccelQ7_24::from_raw(kSine[std::size_t(n % kTableSamples)]);
    sample(0) = core::fixed_mul<core::AccelQ7_24>(gain, unit);
    const firmware::WallEngineOutput& out = g_engine.process(sample);
    g_impacts = g_impacts + out.step.impacts_total;
    g_level = static_cast<std::uint8_t>(out.alarm.level);
    if (out.step.collapsed) {
      g_collapses = g_collapses + 1;
      g_engine.reset(sample);
    }
  }
  return g_collapses > 0 ? 0 : 2;
}
