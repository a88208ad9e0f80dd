#include "profiler.hpp"

namespace rockwatch::m4 {

namespace {

struct SysTick {
  volatile std::uint32_t csr;   // 0xE000E010: bit 0 enable, bit 1 interrupt, bit 2 processor clock
  volatile std::uint32_t rvr;   // reload value
  volatile std::uint32_t cvr;   // current value (a write clears it)
  volatile std::uint32_t calib;
};

SysTick& systick() { return *reinterpret_cast<SysTick*>(std::uintptr_t{0xE000E010}); }
std::uint32_t* psram() { return reinterpret_cast<std::uint32_t*>(std::uintptr_t{0x21000000}); }

volatile std::uint32_t g_count = 0;
volatile std::uint32_t g_dropped = 0;

}  // namespace

void profiler_start(std::uint32_t interval_ticks) {
  SysTick& s = systick();
  s.csr = 0;
  s.rvr = interval_ticks - 1;
  s.cvr = 0;
  s.csr = 7;
}

void profiler_stop() { systick().csr = 0; }
std::uint32_t profiler_count() { return g_count; }
std::uint32_t profiler_dropped() { return g_dropped; }
const std::uint32_t* profiler_addresses() { return psram(); }

}  // namespace rockwatch::m4

extern "C" void m4_profile_tick(std::uint32_t pc) {
  const std::uint32_t n = rockwatch::m4::g_count;
  if (n < rockwatch::m4::kProfileCapacity) {
    rockwatch::m4::psram()[n] = pc;
    rockwatch::m4::g_count = n + 1;
  } else {
    rockwatch::m4::g_dropped = rockwatch::m4::g_dropped + 1;
  }
}
