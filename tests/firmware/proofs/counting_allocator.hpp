// Counting replacements of every allocation function of the process, shared by the allocation proofs
// (test_engine_allocations, test_monitor_allocations): malloc/calloc/realloc/free and the aligned variants,
// forwarding to glibc's __libc_* implementations, and every global operator new/delete. Include it in exactly one
// translation unit of a program; not with sanitizers (they replace malloc themselves).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

extern "C" {
// glibc's own implementations, which its malloc/free are aliases of.
void* __libc_malloc(std::size_t size) noexcept;
void* __libc_calloc(std::size_t n, std::size_t size) noexcept;
void* __libc_realloc(void* p, std::size_t size) noexcept;
void __libc_free(void* p) noexcept;
void* __libc_memalign(std::size_t alignment, std::size_t size) noexcept;
}

namespace {

// Every call of an allocation function, including free() and delete (also of nullptr).
std::uint64_t g_calls = 0;

void* counted_malloc(std::size_t size) {
  ++g_calls;
  return __libc_malloc(size == 0 ? 1 : size);
}

void* counted_memalign(std::size_t alignment, std::size_t size) {
  ++g_calls;
  return __libc_memalign(alignment < sizeof(void*) ? sizeof(void*) : alignment, size == 0 ? 1 : size);
}

void counted_free(void* p) noexcept {
  ++g_calls;
  __libc_free(p);
}

}  // namespace

extern "C" {
void* malloc(std::size_t size) noexcept {
  ++g_calls;
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) noexcept {
  ++g_calls;
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) noexcept {
  ++g_calls;
  return __libc_realloc(p, size);
}
void free(void* p) noexcept {
  ++g_calls;
  __libc_free(p);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  ++g_calls;
  return __libc_memalign(alignment, size);
}
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  ++g_calls;
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept {
  ++g_calls;
  void* p = __libc_memalign(alignment, size);
  if (p == nullptr) return 12;  // ENOMEM
  *out = p;
  return 0;
}
}

void* operator new(std::size_t size) {
  if (void* p = counted_malloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = counted_malloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return counted_malloc(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return counted_malloc(size); }
void* operator new(std::size_t size, std::align_val_t a) {
  if (void* p = counted_memalign(static_cast<std::size_t>(a), size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t a) {
  if (void* p = counted_memalign(static_cast<std::size_t>(a), size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_memalign(static_cast<std::size_t>(a), size);
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_memalign(static_cast<std::size_t>(a), size);
}
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete[](void* p) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { counted_free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { counted_free(p); }

namespace counting_allocator {

// Through volatile function pointers, so the optimiser can neither drop nor merge the deliberate allocations.
inline void* (*volatile g_malloc)(std::size_t) = std::malloc;
inline void (*volatile g_free)(void*) = std::free;

// The counters must see a deliberate allocation, else a count of 0 would prove nothing.
inline bool self_check() {
  const std::uint64_t before = g_calls;
  void* p = g_malloc(24);
  g_free(p);
  const std::uint64_t c_malloc = g_calls - before;
  const std::uint64_t before_new = g_calls;
  std::vector<int>* volatile v = new std::vector<int>(16, 1);  // operator new twice (object, buffer)
  delete v;
  const std::uint64_t c_new = g_calls - before_new;
  std::printf("self-check: malloc+free counted %llu calls (expect 2), new+delete of a vector counted %llu (expect 4)\n",
              static_cast<unsigned long long>(c_malloc), static_cast<unsigned long long>(c_new));
  return c_malloc == 2 && c_new == 4;
}

}  // namespace counting_allocator
