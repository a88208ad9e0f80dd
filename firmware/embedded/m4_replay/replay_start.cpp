// The run-time of the replay image between the reset handler (startup.S) and the replay (replay_main.cpp): the stack
// painted (to measure its deepest use), the static constructors, the instruction clock started, the replay, and the
// emulation ended through semihosting with the replay's status. Faults and the few library hooks the firmware can
// reach report themselves and end the emulation with a non-zero status instead of hanging it.
#include <cstddef>
#include <cstdint>

#include "instruction_clock.hpp"
#include "replay.hpp"
#include "semihosting.hpp"

extern "C" {
extern std::uint32_t _sstack;
extern std::uint32_t _estack;
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
[[noreturn]] void m4_replay_start();
[[noreturn]] void m4_replay_fault(std::uint32_t exception_number);
}

namespace {

constexpr std::uint32_t kStackPaint = 0xC0FFEE11u;

// Below the current stack pointer (less a margin for this function's own frame), every stack word gets the paint.
[[gnu::noinline]] void paint_stack() {
  std::uint32_t* const bottom = &_sstack;
  std::uint32_t* sp = nullptr;
  asm volatile("mov %0, sp" : "=r"(sp));
  for (std::uint32_t* p = bottom; p < sp - 64; ++p) *p = kStackPaint;
}

// Bytes of stack ever used: from the top down to the lowest word that lost its paint.
std::uint32_t stack_used_bytes() {
  const std::uint32_t* p = &_sstack;
  while (p < &_estack && *p == kStackPaint) ++p;
  return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(&_estack) - reinterpret_cast<std::uintptr_t>(p));
}

}  // namespace

extern "C" [[noreturn]] void m4_replay_start() {
  paint_stack();
  for (void (**f)() = __init_array_start; f < __init_array_end; ++f) (*f)();
  rockwatch::m4::start_instruction_clock();
  const std::uint32_t status = rockwatch::m4::run_replay(&stack_used_bytes);
  rockwatch::m4::host_exit(status);
}

extern "C" [[noreturn]] void m4_replay_fault(std::uint32_t exception_number) {
  // Exception numbers: 2 NMI, 3 HardFault, 4 MemManage, 5 BusFault, 6 UsageFault, 11 SVCall, 14 PendSV, 15 SysTick.
  char text[] = "m4-replay image: fault, exception number 00\n";
  text[sizeof text - 4] = static_cast<char>('0' + (exception_number / 10) % 10);
  text[sizeof text - 3] = static_cast<char>('0' + exception_number % 10);
  rockwatch::m4::host_print(text);
  rockwatch::m4::host_exit(rockwatch::m4::replay_status::fault);
}

// Eigen's assertions stay compiled in (no NDEBUG, as in the embedded build); newlib's __assert_func would pull in
// stdio. A failed assertion is reported with its place and ends the run.
extern "C" [[noreturn]] void __assert_func(const char* file, int line, const char*, const char* expression) {
  rockwatch::m4::host_print("m4-replay image: assertion failed: ");
  rockwatch::m4::host_print(expression != nullptr ? expression : "?");
  rockwatch::m4::host_print(" in ");
  rockwatch::m4::host_print(file != nullptr ? file : "?");
  (void)line;
  rockwatch::m4::host_print("\n");
  rockwatch::m4::host_exit(rockwatch::m4::replay_status::assertion);
}

// Transport's and SampleEngine's vtables may reference operator delete (deleting destructors); nothing is ever
// deleted (no heap). Reaching one is a defect: reported, and the run ends.
void operator delete(void*) noexcept {
  rockwatch::m4::host_print("m4-replay image: operator delete called\n");
  rockwatch::m4::host_exit(rockwatch::m4::replay_status::fault);
}
void operator delete(void*, std::size_t) noexcept {
  rockwatch::m4::host_print("m4-replay image: operator delete called\n");
  rockwatch::m4::host_exit(rockwatch::m4::replay_status::fault);
}
