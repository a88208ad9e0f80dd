// The clock the replay image measures its per-sample work with: TIMER0 of the mps2-an386 (an ARM CMSDK APB timer at
// 0x40000000, a 32-bit down-counter clocked by the board's 25 MHz system clock in QEMU), free-running from
// 0xFFFFFFFF. Under QEMU's `-icount shift=S` the virtual clock advances exactly 2^S ns per executed instruction and a
// timer read happens at an exact instruction count, so a tick difference is a deterministic function of the
// instructions executed between the two reads: scripts/m4-replay.sh converts ticks to instructions (S = 8: 256 ns per
// instruction, 6.4 ticks of 40 ns, so the tick rounding of either read, < 1 tick, cannot change the rounded count).
// A real Cortex-M4 would use DWT->CYCCNT, which QEMU does not model.
#pragma once

#include <cstdint>

namespace rockwatch::m4 {

struct CmsdkTimer {
  volatile std::uint32_t ctrl;       // 0x00: bit 0 enable
  volatile std::uint32_t value;      // 0x04: current value (counts down)
  volatile std::uint32_t reload;     // 0x08: reload value
  volatile std::uint32_t intstatus;  // 0x0C
};

inline CmsdkTimer& timer0() { return *reinterpret_cast<CmsdkTimer*>(std::uintptr_t{0x40000000}); }

inline void start_instruction_clock() {
  CmsdkTimer& t = timer0();
  t.ctrl = 0;
  t.reload = 0xFFFFFFFFu;
  t.value = 0xFFFFFFFFu;
  t.ctrl = 1;
}

// The counter now. The "memory" clobbers keep the compiler from moving the measured work across the read.
inline std::uint32_t clock_now() {
  asm volatile("" ::: "memory");
  const std::uint32_t v = timer0().value;
  asm volatile("" ::: "memory");
  return v;
}

// Ticks from `before` to `after` (a down-counter: modulo 2^32, one wrap at most, i.e. < 171 s of virtual time).
inline std::uint32_t ticks_between(std::uint32_t before, std::uint32_t after) { return before - after; }

}  // namespace rockwatch::m4
