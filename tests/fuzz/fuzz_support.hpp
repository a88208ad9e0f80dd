// Shared by the fuzz targets: the input as a file (the readers and the config parser take paths) and the check macro.
//
// Contract checked by every target: a parser either returns a value that satisfies its documented invariants or
// throws its documented error type (records::RecordError, options::UsageError). Any other exception escapes
// LLVMFuzzerTestOneInput, libFuzzer reports it as a crash ("deadly signal" after std::terminate); a violated
// invariant calls __builtin_trap(). Sanitizer reports, leaks, timeouts and out-of-memory are reported by libFuzzer.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace rockwatch::fuzz {

// A memory-backed file (memfd) whose content is replaced by each input, named by /proc/self/fd/N so the code under
// test opens it by path as it would a record or configuration file. One per process, no disk I/O per input.
class InputFile {
 public:
  explicit InputFile(const char* name) {
    fd_ = memfd_create(name, MFD_CLOEXEC);
    if (fd_ < 0) {
      std::perror("memfd_create");
      std::abort();
    }
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  ~InputFile() { close(fd_); }

  const std::string& write(const std::uint8_t* data, std::size_t size) {
    if (ftruncate(fd_, 0) != 0) fail("ftruncate");
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = pwrite(fd_, data + done, size - done, static_cast<off_t>(done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) fail("pwrite");
      done += static_cast<std::size_t>(n);
    }
    return path_;
  }
  const std::string& path() const { return path_; }

 private:
  [[noreturn]] static void fail(const char* what) {
    std::perror(what);
    std::abort();
  }
  int fd_ = -1;
  std::string path_;
};

// A violated invariant: a crash libFuzzer records with the input (the message says which one).
#define ROCKWATCH_FUZZ_CHECK(condition)                                                          \
  do {                                                                                           \
    if (!(condition)) {                                                                          \
      std::fprintf(stderr, "fuzz invariant violated: %s (%s:%d)\n", #condition, __FILE__, __LINE__); \
      __builtin_trap();                                                                          \
    }                                                                                            \
  } while (false)

}  // namespace rockwatch::fuzz
