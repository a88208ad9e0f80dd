// The input layout of fuzz_monitor_loop, shared with the seed generator (make_monitor_seeds.cpp):
//
//   input   := settings-byte message*
//   message := selector-byte length(2 bytes, little-endian) payload(length bytes; fewer if the input ends)
//
// settings-byte: bits 0-1 max_bridge_samples {10, 0, 1, 1000}; bits 2-3 restart_window {1000, 1, 64, 10^9};
//   bits 4-5 sample_rate_hz {200, 1000, 50, 10000}; bit 6 {sensor_range_mps2 80 and restitution exp (the defaults),
//   sensor_range_mps2 5, energy ratio 1 (no loss at impact) and the wall observer on}; bit 7 engine {fixed point
//   (linear model), double precision with the full model}.
// selector-byte: bit 0 channel {ROCKWATCH_ACCEL, ROCKWATCH_ACCEL_BATCH}; bit 1 publish_status() before the message;
//   bit 2 the transport refuses every publish of this message; bit 3 the message arrives on another channel
//   (ignored), with bit 0 too on ROCKWATCH_WALL_SENSOR (an input with the observer, ignored without);
//   bits 4-7 receive clock advance before the message, in 2 ms steps (0 … 30 ms).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rockwatch::fuzz::monitor_input {

inline constexpr std::int64_t kReceiveClockStartUs = 1700000000001000;  // 1 ms after the seeds' first sample time
inline constexpr std::int64_t kClockStepUs = 2000;

inline constexpr std::uint8_t kBatch = 0x01;
inline constexpr std::uint8_t kStatusBefore = 0x02;
inline constexpr std::uint8_t kPublishFails = 0x04;
inline constexpr std::uint8_t kOtherChannel = 0x08;
inline constexpr std::uint8_t kWallSensor = kBatch | kOtherChannel;
inline constexpr std::uint8_t advance(int steps_of_2ms) { return static_cast<std::uint8_t>((steps_of_2ms & 0xF) << 4); }

inline void append_message(std::vector<std::uint8_t>& input, std::uint8_t selector,
                           const std::vector<std::uint8_t>& payload) {
  input.push_back(selector);
  input.push_back(static_cast<std::uint8_t>(payload.size() & 0xFF));
  input.push_back(static_cast<std::uint8_t>((payload.size() >> 8) & 0xFF));
  input.insert(input.end(), payload.begin(), payload.end());
}

}  // namespace rockwatch::fuzz::monitor_input
