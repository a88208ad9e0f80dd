/* An LD_PRELOAD heap-call counter for the soak of rockwatch-monitor (tests/soak/soak_monitor.cpp).
 *
 * Interposes malloc, calloc, realloc, free, memalign, posix_memalign, aligned_alloc, valloc, pvalloc and the C++
 * operator new/delete family (libstdc++'s own would call malloc anyway; interposing them directly gives the C++
 * caller), forwarding to glibc's __libc_* entry points (no dlsym: it allocates itself).
 *
 * Windows: the process that loads it is not told anything. SIGUSR2 (the monitor neither uses nor blocks it) writes a
 * "mark" line with the counts so far to $ROCKWATCH_ALLOC_REPORT; the first mark arms stack recording, the second
 * disarms it. While armed, each distinct call stack (up to kFrames return addresses, glibc backtrace(), warmed up in
 * the constructor so it does not allocate later) of an allocating call is counted in a fixed table. At exit (a
 * destructor: not signal context) the final counts and the recorded stacks are written, with dladdr() names.
 *
 * The signal handler only reads atomics, formats into a stack buffer and calls open/write/close: async-signal-safe.
 * Recursion (backtrace() inside malloc) is stopped by a thread-local guard.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <execinfo.h>
#include <fcntl.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

extern void* __libc_malloc(size_t);
extern void* __libc_calloc(size_t, size_t);
extern void* __libc_realloc(void*, size_t);
extern void __libc_free(void*);
extern void* __libc_memalign(size_t, size_t);

enum { kMalloc, kCalloc, kRealloc, kAligned, kNew, kFree, kDelete, kKinds };
static const char* const kKindNames[kKinds] = {"malloc", "calloc", "realloc", "aligned", "new", "free", "delete"};

static volatile uint64_t g_count[kKinds];
static volatile int g_armed = 0;
static volatile int g_marks = 0;
static char g_report[512];

enum { kFrames = 8, kStacks = 128 };
struct Stack {
  volatile uint64_t count;
  volatile int used;  /* 0 free, 1 being written, 2 valid */
  int kind;
  int depth;
  void* frames[kFrames];
};
static struct Stack g_stacks[kStacks];
static volatile uint64_t g_stacks_dropped = 0;
static __thread int t_in_hook = 0;

static void count(int kind) { __atomic_add_fetch(&g_count[kind], 1, __ATOMIC_RELAXED); }

static void record(int kind) {
  if (!__atomic_load_n(&g_armed, __ATOMIC_RELAXED) || t_in_hook) return;
  t_in_hook = 1;
  void* frames[kFrames + 2];
  int n = backtrace(frames, kFrames + 2);
  /* Frame 0 is record(), frame 1 the interposed function: keep the callers. */
  int skip = n > 2 ? 2 : n;
  int depth = n - skip;
  uint64_t h = (uint64_t)kind * 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < depth; ++i) h = (h ^ (uint64_t)(uintptr_t)frames[skip + i]) * 0x100000001B3ull;
  for (int probe = 0; probe < kStacks; ++probe) {
    struct Stack* s = &g_stacks[(h + (uint64_t)probe) % kStacks];
    int used = __atomic_load_n(&s->used, __ATOMIC_ACQUIRE);
    if (used == 0) {
      int expected = 0;
      if (__atomic_compare_exchange_n(&s->used, &expected, 1, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) {
        s->kind = kind;
        s->depth = depth;
        for (int i = 0; i < depth; ++i) s->frames[i] = frames[skip + i];
        __atomic_add_fetch(&s->count, 1, __ATOMIC_RELAXED);
        __atomic_store_n(&s->used, 2, __ATOMIC_RELEASE);
        t_in_hook = 0;
        return;
      }
      used = __atomic_load_n(&s->used, __ATOMIC_ACQUIRE);
    }
    if (used == 2 && s->kind == kind && s->depth == depth &&
        memcmp(s->frames, frames + skip, sizeof(void*) * (size_t)depth) == 0) {
      __atomic_add_fetch(&s->count, 1, __ATOMIC_RELAXED);
      t_in_hook = 0;
      return;
    }
  }
  __atomic_add_fetch(&g_stacks_dropped, 1, __ATOMIC_RELAXED);
  t_in_hook = 0;
}

/* ---- async-signal-safe formatting ---- */
static char* put_str(char* p, char* end, const char* s) {
  while (*s && p < end) *p++ = *s++;
  return p;
}
static char* put_u64(char* p, char* end, uint64_t v) {
  char digits[24];
  int n = 0;
  do {
    digits[n++] = (char)('0' + v % 10);
    v /= 10;
  } while (v != 0);
  while (n > 0 && p < end) *p++ = digits[--n];
  return p;
}
static char* put_hex(char* p, char* end, uint64_t v) {
  static const char kHex[] = "0123456789abcdef";
  p = put_str(p, end, "0x");
  char digits[20];
  int n = 0;
  do {
    digits[n++] = kHex[v & 15];
    v >>= 4;
  } while (v != 0);
  while (n > 0 && p < end) *p++ = digits[--n];
  return p;
}
static char* put_counts(char* p, char* end) {
  for (int k = 0; k < kKinds; ++k) {
    p = put_str(p, end, " ");
    p = put_str(p, end, kKindNames[k]);
    p = put_str(p, end, "=");
    p = put_u64(p, end, __atomic_load_n(&g_count[k], __ATOMIC_RELAXED));
  }
  return p;
}
static void write_all(int fd, const char* data, size_t size) {
  while (size > 0) {
    ssize_t n = write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    data += n;
    size -= (size_t)n;
  }
}
static int open_report(void) {
  if (g_report[0] == '\0') return -1;
  return open(g_report, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
}

static void on_mark(int signal_number) {
  (void)signal_number;
  const int saved_errno = errno;
  const int mark = __atomic_add_fetch(&g_marks, 1, __ATOMIC_RELAXED);
  /* Count first, then arm/disarm: the line says exactly where the window starts and ends. */
  char line[512];
  char* p = line;
  char* end = line + sizeof line - 1;
  p = put_str(p, end, "mark ");
  p = put_u64(p, end, (uint64_t)mark);
  p = put_counts(p, end);
  *p++ = '\n';
  __atomic_store_n(&g_armed, mark == 1 ? 1 : 0, __ATOMIC_RELAXED);
  const int fd = open_report();
  if (fd >= 0) {
    write_all(fd, line, (size_t)(p - line));
    close(fd);
  }
  errno = saved_errno;
}

__attribute__((constructor)) static void shim_init(void) {
  const char* path = getenv("ROCKWATCH_ALLOC_REPORT");
  if (path == NULL) return;
  strncpy(g_report, path, sizeof g_report - 1);
  void* warm[4];
  t_in_hook = 1;
  (void)backtrace(warm, 4);  /* loads libgcc_s now, not inside a counted call */
  t_in_hook = 0;
  struct sigaction action;
  memset(&action, 0, sizeof action);
  action.sa_handler = on_mark;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGUSR2, &action, NULL);
  const int fd = open_report();
  if (fd >= 0) {
    char line[512];
    char* p = line;
    char* end = line + sizeof line - 1;
    p = put_str(p, end, "start pid=");
    p = put_u64(p, end, (uint64_t)getpid());
    p = put_counts(p, end);
    *p++ = '\n';
    write_all(fd, line, (size_t)(p - line));
    close(fd);
  }
}

__attribute__((destructor)) static void shim_fini(void) {
  const int fd = open_report();
  if (fd < 0) return;
  t_in_hook = 1;  /* dladdr may allocate: not counted in a stack */
  char line[1024];
  char* p = line;
  char* end = line + sizeof line - 1;
  p = put_str(p, end, "exit");
  p = put_counts(p, end);
  p = put_str(p, end, " stacks_dropped=");
  p = put_u64(p, end, g_stacks_dropped);
  *p++ = '\n';
  write_all(fd, line, (size_t)(p - line));
  for (int i = 0; i < kStacks; ++i) {
    const struct Stack* s = &g_stacks[i];
    if (s->used != 2) continue;
    p = line;
    p = put_str(p, end, "stack ");
    p = put_str(p, end, kKindNames[s->kind]);
    p = put_str(p, end, " count=");
    p = put_u64(p, end, s->count);
    *p++ = '\n';
    write_all(fd, line, (size_t)(p - line));
    for (int f = 0; f < s->depth; ++f) {
      Dl_info info;
      memset(&info, 0, sizeof info);
      p = line;
      p = put_str(p, end, "  frame ");
      p = put_hex(p, end, (uint64_t)(uintptr_t)s->frames[f]);
      if (dladdr(s->frames[f], &info) != 0 && info.dli_fname != NULL) {
        p = put_str(p, end, " ");
        p = put_str(p, end, info.dli_fname);
        p = put_str(p, end, " +");
        p = put_hex(p, end, (uint64_t)((uintptr_t)s->frames[f] - (uintptr_t)info.dli_fbase));
        if (info.dli_sname != NULL) {
          p = put_str(p, end, " ");
          p = put_str(p, end, info.dli_sname);
        }
      }
      *p++ = '\n';
      write_all(fd, line, (size_t)(p - line));
    }
  }
  close(fd);
}

/* ---- the interposed functions ---- */
void* malloc(size_t size) {
  count(kMalloc);
  record(kMalloc);
  return __libc_malloc(size);
}
void* calloc(size_t n, size_t size) {
  count(kCalloc);
  record(kCalloc);
  return __libc_calloc(n, size);
}
void* realloc(void* p, size_t size) {
  count(kRealloc);
  record(kRealloc);
  return __libc_realloc(p, size);
}
void free(void* p) {
  if (p == NULL) return;
  count(kFree);
  __libc_free(p);
}
void* memalign(size_t alignment, size_t size) {
  count(kAligned);
  record(kAligned);
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(size_t alignment, size_t size) { return memalign(alignment, size); }
int posix_memalign(void** out, size_t alignment, size_t size) {
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0) return EINVAL;
  count(kAligned);
  record(kAligned);
  void* p = __libc_memalign(alignment, size);
  if (p == NULL) return ENOMEM;
  *out = p;
  return 0;
}
void* valloc(size_t size) { return memalign((size_t)sysconf(_SC_PAGESIZE), size); }
void* pvalloc(size_t size) {
  const size_t page = (size_t)sysconf(_SC_PAGESIZE);
  return memalign(page, (size + page - 1) / page * page);
}

/* operator new / delete (Itanium mangled names); the throwing forms call std::get_new_handler semantics only in
 * the sense that a null result aborts (the monitor never runs out of memory in a soak). */
static void* new_impl(size_t size) {
  count(kNew);
  record(kNew);
  void* p = __libc_malloc(size == 0 ? 1 : size);
  if (p == NULL) abort();
  return p;
}
static void* new_aligned_impl(size_t size, size_t alignment) {
  count(kNew);
  record(kNew);
  void* p = __libc_memalign(alignment, size == 0 ? 1 : size);
  if (p == NULL) abort();
  return p;
}
static void delete_impl(void* p) {
  if (p == NULL) return;
  count(kDelete);
  __libc_free(p);
}
void* _Znwm(size_t size) { return new_impl(size); }
void* _Znam(size_t size) { return new_impl(size); }
void* _ZnwmRKSt9nothrow_t(size_t size, const void* tag) { (void)tag; return new_impl(size); }
void* _ZnamRKSt9nothrow_t(size_t size, const void* tag) { (void)tag; return new_impl(size); }
void* _ZnwmSt11align_val_t(size_t size, size_t alignment) { return new_aligned_impl(size, alignment); }
void* _ZnamSt11align_val_t(size_t size, size_t alignment) { return new_aligned_impl(size, alignment); }
void _ZdlPv(void* p) { delete_impl(p); }
void _ZdaPv(void* p) { delete_impl(p); }
void _ZdlPvm(void* p, size_t size) { (void)size; delete_impl(p); }
void _ZdaPvm(void* p, size_t size) { (void)size; delete_impl(p); }
void _ZdlPvSt11align_val_t(void* p, size_t alignment) { (void)alignment; delete_impl(p); }
void _ZdaPvSt11align_val_t(void* p, size_t alignment) { (void)alignment; delete_impl(p); }
void _ZdlPvmSt11align_val_t(void* p, size_t size, size_t alignment) { (void)size; (void)alignment; delete_impl(p); }
void _ZdaPvmSt11align_val_t(void* p, size_t size, size_t alignment) { (void)size; (void)alignment; delete_impl(p); }
void _ZdlPvRKSt9nothrow_t(void* p, const void* tag) { (void)tag; delete_impl(p); }
void _ZdaPvRKSt9nothrow_t(void* p, const void* tag) { (void)tag; delete_impl(p); }
