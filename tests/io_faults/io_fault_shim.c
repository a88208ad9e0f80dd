/* An LD_PRELOAD write-error injector for rockwatch-monitor's `--log` (tests/io_faults/monitor_disk_full.cpp).
 *
 * Interposes the calls a log writer uses — write, pwrite, pwrite64, writev, pwritev, fsync, fdatasync — and, for a
 * file descriptor whose path (readlink /proc/self/fd/N) ends with $ROCKWATCH_IOFAULT_MATCH, does what the first word
 * of the control file $ROCKWATCH_IOFAULT_CONTROL says, read at every such call (the test rewrites it while the
 * monitor runs):
 *
 *   (no file, empty)  pass through
 *   EIO | ENOSPC      every write call fails with that errno, nothing written
 *   short-EIO         a write of n > 1 bytes writes n/2 (for real) and returns n/2; the next write call fails with
 *                     EIO (a write torn mid-buffer: the writer must cut the file back to its last complete event)
 *   fsync-EIO         writes pass; fsync and fdatasync fail with EIO (nothing written is lost here: the page cache
 *                     keeps it, as after a transient device error)
 *
 * $ROCKWATCH_IOFAULT_DURABLE (power-loss test, tests/io_faults/power_loss.py): after each fsync or fdatasync of the
 * file under test that succeeded, one line "<file size>" is appended to that file: the bytes a power cut cannot take.
 *
 * Each injected failure appends one line to $ROCKWATCH_IOFAULT_RECORD: "<call> <errno name>" for a failed call,
 * "<call> short <written> of <asked>" for a short write — so the test reconciles the monitor's counters with exactly
 * what was done. Other descriptors (stdout, stderr, sockets) are never touched.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

typedef ssize_t (*write_fn)(int, const void*, size_t);
typedef ssize_t (*pwrite_fn)(int, const void*, size_t, off_t);
typedef ssize_t (*pwrite64_fn)(int, const void*, size_t, off64_t);
typedef ssize_t (*writev_fn)(int, const struct iovec*, int);
typedef ssize_t (*pwritev_fn)(int, const struct iovec*, int, off_t);
typedef int (*sync_fn)(int);

static write_fn real_write;
static pwrite_fn real_pwrite;
static pwrite64_fn real_pwrite64;
static writev_fn real_writev;
static pwritev_fn real_pwritev;
static sync_fn real_fsync, real_fdatasync;

static void resolve(void) {
  if (real_write != NULL) return;
  real_pwrite = (pwrite_fn)dlsym(RTLD_NEXT, "pwrite");
  real_pwrite64 = (pwrite64_fn)dlsym(RTLD_NEXT, "pwrite64");
  real_writev = (writev_fn)dlsym(RTLD_NEXT, "writev");
  real_pwritev = (pwritev_fn)dlsym(RTLD_NEXT, "pwritev");
  real_fsync = (sync_fn)dlsym(RTLD_NEXT, "fsync");
  real_fdatasync = (sync_fn)dlsym(RTLD_NEXT, "fdatasync");
  real_write = (write_fn)dlsym(RTLD_NEXT, "write");
}

/* Whether fd is the file under test. */
static int targeted(int fd) {
  const char* match = getenv("ROCKWATCH_IOFAULT_MATCH");
  if (match == NULL || match[0] == '\0' || fd < 0) return 0;
  char link[64], path[4096];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, path, sizeof path - 1);
  if (n <= 0) return 0;
  path[n] = '\0';
  const size_t lm = strlen(match), lp = (size_t)n;
  return lp >= lm && strcmp(path + lp - lm, match) == 0;
}

enum mode { kPass, kEio, kEnospc, kShortEio, kFsyncEio };

static enum mode current_mode(void) {
  const char* control = getenv("ROCKWATCH_IOFAULT_CONTROL");
  if (control == NULL) return kPass;
  const int fd = open(control, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return kPass;
  char word[32] = {0};
  const ssize_t n = read(fd, word, sizeof word - 1);
  close(fd);
  if (n <= 0) return kPass;
  word[strcspn(word, " \t\r\n")] = '\0';
  if (strcmp(word, "EIO") == 0) return kEio;
  if (strcmp(word, "ENOSPC") == 0) return kEnospc;
  if (strcmp(word, "short-EIO") == 0) return kShortEio;
  if (strcmp(word, "fsync-EIO") == 0) return kFsyncEio;
  return kPass;
}

static void record(const char* line) {
  const char* path = getenv("ROCKWATCH_IOFAULT_RECORD");
  if (path == NULL) return;
  const int fd = open(path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return;
  (void)real_write(fd, line, strlen(line));
  close(fd);
}

static int short_pending = 0; /* the previous write call of short-EIO was short: this one fails */

/* What a write call of `bytes` on fd does: -1 pass through, 0 fail (errno set), or k > 0: write only k bytes. */
static ssize_t decide(int fd, size_t bytes, const char* call) {
  resolve();
  if (!targeted(fd)) return -1;
  const enum mode m = current_mode();
  char line[128];
  if (m == kEio || m == kEnospc) {
    snprintf(line, sizeof line, "%s %s\n", call, m == kEio ? "EIO" : "ENOSPC");
    record(line);
    errno = m == kEio ? EIO : ENOSPC;
    return 0;
  }
  if (m == kShortEio) {
    if (short_pending || bytes < 2) {
      short_pending = 0;
      snprintf(line, sizeof line, "%s EIO\n", call);
      record(line);
      errno = EIO;
      return 0;
    }
    short_pending = 1;
    snprintf(line, sizeof line, "%s short %zu of %zu\n", call, bytes / 2, bytes);
    record(line);
    return (ssize_t)(bytes / 2);
  }
  short_pending = 0;
  return -1;
}

ssize_t write(int fd, const void* buf, size_t n) {
  const ssize_t d = decide(fd, n, "write");
  if (d == 0) return -1;
  return real_write(fd, buf, d > 0 ? (size_t)d : n);
}

ssize_t pwrite(int fd, const void* buf, size_t n, off_t off) {
  const ssize_t d = decide(fd, n, "pwrite");
  if (d == 0) return -1;
  return real_pwrite(fd, buf, d > 0 ? (size_t)d : n, off);
}

ssize_t pwrite64(int fd, const void* buf, size_t n, off64_t off) {
  const ssize_t d = decide(fd, n, "pwrite");
  if (d == 0) return -1;
  return real_pwrite64(fd, buf, d > 0 ? (size_t)d : n, off);
}

static size_t iov_bytes(const struct iovec* iov, int count) {
  size_t total = 0;
  for (int i = 0; i < count; ++i) total += iov[i].iov_len;
  return total;
}

/* Vectored writes: a short write becomes the first iovec alone (enough to tear a buffer). */
ssize_t writev(int fd, const struct iovec* iov, int count) {
  const ssize_t d = decide(fd, iov_bytes(iov, count), "writev");
  if (d == 0) return -1;
  if (d > 0 && count > 0) return real_write(fd, iov[0].iov_base, iov[0].iov_len < (size_t)d ? iov[0].iov_len : (size_t)d);
  return real_writev(fd, iov, count);
}

ssize_t pwritev(int fd, const struct iovec* iov, int count, off_t off) {
  const ssize_t d = decide(fd, iov_bytes(iov, count), "pwritev");
  if (d == 0) return -1;
  if (d > 0 && count > 0) {
    return real_pwrite(fd, iov[0].iov_base, iov[0].iov_len < (size_t)d ? iov[0].iov_len : (size_t)d, off);
  }
  return real_pwritev(fd, iov, count, off);
}

static int sync_call(int fd, sync_fn real, const char* call) {
  resolve();
  if (targeted(fd) && current_mode() == kFsyncEio) {
    char line[64];
    snprintf(line, sizeof line, "%s EIO\n", call);
    record(line);
    errno = EIO;
    return -1;
  }
  const int rc = real(fd);
  const char* durable = getenv("ROCKWATCH_IOFAULT_DURABLE");
  if (rc == 0 && durable != NULL && targeted(fd)) {
    struct stat st;
    if (fstat(fd, &st) == 0) {
      const int out = open(durable, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
      if (out >= 0) {
        char line[32];
        snprintf(line, sizeof line, "%lld\n", (long long)st.st_size);
        (void)real_write(out, line, strlen(line));
        close(out);
      }
    }
  }
  return rc;
}

/* resolve() before reading real_*: a sync may be the first call the shim sees (a restarted monitor cuts a torn log
 * and syncs before it writes anything). */
int fsync(int fd) {
  resolve();
  return sync_call(fd, real_fsync, "fsync");
}
int fdatasync(int fd) {
  resolve();
  return sync_call(fd, real_fdatasync, "fdatasync");
}
