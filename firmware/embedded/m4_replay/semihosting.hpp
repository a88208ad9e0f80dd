// ARM semihosting (the "Angel" interface) for the replay image: a `bkpt 0xAB` with the operation in r0 and its
// argument in r1 traps to the debugger — here QEMU itself (-semihosting-config enable=on,target=native), which does
// the file I/O on the host and ends the emulation on SYS_EXIT_EXTENDED with the given status. Operation numbers and
// argument blocks: "Semihosting for AArch32 and AArch64", version 2.0. The calls run outside the measured windows.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rockwatch::m4 {

namespace semihosting_op {
inline constexpr std::uint32_t open = 0x01;
inline constexpr std::uint32_t close = 0x02;
inline constexpr std::uint32_t write0 = 0x04;
inline constexpr std::uint32_t write = 0x05;
inline constexpr std::uint32_t read = 0x06;
inline constexpr std::uint32_t get_cmdline = 0x15;
inline constexpr std::uint32_t exit_extended = 0x20;
}  // namespace semihosting_op

inline constexpr std::uint32_t kOpenReadBinary = 1;   // fopen mode "rb"
inline constexpr std::uint32_t kOpenWriteBinary = 5;  // fopen mode "wb"

inline std::int32_t semihost(std::uint32_t op, const void* arg) {
  register std::uint32_t r0 asm("r0") = op;
  register const void* r1 asm("r1") = arg;
  asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return static_cast<std::int32_t>(r0);
}

// A NUL-terminated message on the host's console (QEMU's stderr/stdout).
inline void host_print(const char* text) { semihost(semihosting_op::write0, text); }

// Opens a host file; the handle, or -1.
inline std::int32_t host_open(const char* path, std::size_t length, std::uint32_t mode) {
  const std::uint32_t block[3] = {reinterpret_cast<std::uintptr_t>(path), mode, static_cast<std::uint32_t>(length)};
  return semihost(semihosting_op::open, block);
}

inline void host_close(std::int32_t handle) {
  const std::uint32_t block[1] = {static_cast<std::uint32_t>(handle)};
  semihost(semihosting_op::close, block);
}

// Reads up to `size` bytes; the number read (0 at the end of the file), or -1.
inline std::int32_t host_read(std::int32_t handle, void* data, std::size_t size) {
  const std::uint32_t block[3] = {static_cast<std::uint32_t>(handle), reinterpret_cast<std::uintptr_t>(data),
                                  static_cast<std::uint32_t>(size)};
  const std::int32_t not_read = semihost(semihosting_op::read, block);
  if (not_read < 0 || static_cast<std::size_t>(not_read) > size) return -1;
  return static_cast<std::int32_t>(size) - not_read;
}

// Writes all `size` bytes; false on failure.
inline bool host_write(std::int32_t handle, const void* data, std::size_t size) {
  const std::uint32_t block[3] = {static_cast<std::uint32_t>(handle), reinterpret_cast<std::uintptr_t>(data),
                                  static_cast<std::uint32_t>(size)};
  return semihost(semihosting_op::write, block) == 0;
}

// The command line QEMU was given (-kernel IMAGE -append ARGS: "IMAGE ARGS"), NUL-terminated; false if it does not fit.
inline bool host_command_line(char* buffer, std::size_t size) {
  std::uint32_t block[2] = {reinterpret_cast<std::uintptr_t>(buffer), static_cast<std::uint32_t>(size)};
  return semihost(semihosting_op::get_cmdline, block) == 0;
}

// Ends the emulation: QEMU exits with `status`.
[[noreturn]] inline void host_exit(std::uint32_t status) {
  constexpr std::uint32_t kApplicationExit = 0x20026;  // ADP_Stopped_ApplicationExit
  const std::uint32_t block[2] = {kApplicationExit, status};
  semihost(semihosting_op::exit_extended, block);
  for (;;) {
  }
}

}  // namespace rockwatch::m4
