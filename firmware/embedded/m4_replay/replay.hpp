// The replay the Cortex-M4 image runs (replay_main.cpp): firmware::WallEngine over an engine-input file
// (rockwatch/firmware/engine_input_format.hpp) read through semihosting, per sample the alarm level and the ticks of
// the instruction clock the step took, written to an output file (format in replay_main.cpp).
#pragma once

#include <cstdint>

namespace rockwatch::m4 {

// The image's exit status (QEMU's), read by scripts/m4-replay.sh.
namespace replay_status {
inline constexpr std::uint32_t ok = 0;
inline constexpr std::uint32_t usage = 3;          // the command line does not name the two files
inline constexpr std::uint32_t input_open = 4;     // the input file cannot be opened
inline constexpr std::uint32_t input_format = 5;   // the input is not an engine-input file, or is truncated
inline constexpr std::uint32_t engine_init = 6;    // WallEngine::init refused the configuration
inline constexpr std::uint32_t output = 7;         // the output file cannot be opened or written
inline constexpr std::uint32_t mismatch = 8;       // the two engines (seam and direct) disagreed: a defect
inline constexpr std::uint32_t fault = 9;          // a CPU fault or a call that must never happen
inline constexpr std::uint32_t assertion = 10;     // an Eigen assertion failed
}  // namespace replay_status

// Runs the replay; the status. `stack_used_bytes` reports the deepest stack use so far (written at the end).
std::uint32_t run_replay(std::uint32_t (*stack_used_bytes)());

}  // namespace rockwatch::m4
