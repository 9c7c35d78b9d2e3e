#include "alloc_counter.hpp"

#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<std::size_t> g_allocs{0};
thread_local std::size_t t_allocs = 0;  // constant-initialised: no allocation on first use

struct Slot {
  std::atomic<long> tid{0};
  std::atomic<std::size_t> count{0};
};
constexpr std::size_t kSlots = 256;
Slot g_slots[kSlots];
thread_local Slot* t_slot = nullptr;
thread_local bool t_no_slot = false;

void countThread() {
  ++t_allocs;
  if (!t_slot && !t_no_slot) {
    const long me = static_cast<long>(::syscall(SYS_gettid));
    for (Slot& s : g_slots) {
      long expected = 0;
      if (s.tid.compare_exchange_strong(expected, me)) {
        t_slot = &s;
        break;
      }
    }
    t_no_slot = t_slot == nullptr;
  }
  if (t_slot) t_slot->count.fetch_add(1, std::memory_order_relaxed);
}

void* countedAlloc(std::size_t n) {
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  countThread();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* countedAlignedAlloc(std::size_t n, std::size_t al) {
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  countThread();
  const std::size_t size = ((n ? n : 1) + al - 1) / al * al;
  if (void* p = std::aligned_alloc(al, size)) return p;
  throw std::bad_alloc();
}
}  // namespace

namespace tactile {
namespace test {
std::size_t allocationCount() { return g_allocs.load(std::memory_order_relaxed); }
std::size_t threadAllocationCount() { return t_allocs; }
std::size_t allThreadAllocations(ThreadAllocations* out, std::size_t max) {
  std::size_t n = 0;
  for (const Slot& s : g_slots) {
    const long tid = s.tid.load();
    if (tid == 0 || n >= max) continue;
    out[n++] = ThreadAllocations{tid, s.count.load(std::memory_order_relaxed)};
  }
  return n;
}
}  // namespace test
}  // namespace tactile

void* operator new(std::size_t n) { return countedAlloc(n); }
void* operator new[](std::size_t n) { return countedAlloc(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  countThread();
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  countThread();
  return std::malloc(n ? n : 1);
}
void* operator new(std::size_t n, std::align_val_t a) { return countedAlignedAlloc(n, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return countedAlignedAlloc(n, static_cast<std::size_t>(a)); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
