// A sampling profiler for one step of the replay (scripts/m4-replay.sh --m4-profile SAMPLE): SysTick, on the same
// 25 MHz clock as the instruction clock, interrupts every `interval_ticks` while it runs, and its handler (startup.S)
// records the interrupted instruction's address. Under -icount the interrupts arrive at exact instruction counts, so
// the profile is deterministic; the script maps the addresses to functions. The handler's own instructions disturb
// the counts of the profiled step, so the script profiles in a second run, apart from the measured one.
// The addresses go to the board's PSRAM (16 MB at 0x21000000), outside the image's memory: no RAM of the image.
#pragma once

#include <cstdint>

namespace rockwatch::m4 {

inline constexpr std::uint32_t kProfileCapacity = 1u << 20;  // addresses (4 MB of PSRAM)

void profiler_start(std::uint32_t interval_ticks);
void profiler_stop();
std::uint32_t profiler_count();           // addresses recorded (at most kProfileCapacity)
std::uint32_t profiler_dropped();         // ticks beyond the capacity
const std::uint32_t* profiler_addresses();

}  // namespace rockwatch::m4
