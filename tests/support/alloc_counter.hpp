// Counting global operator new, to prove that per-cycle paths do not allocate.
// Link tests/support/alloc_counter.cpp into the test executable; then
//   tactile::test::AllocationScope scope;  ...code...;  EXPECT_EQ(scope.count(), 0);
#pragma once

#include <cstddef>

namespace tactile {
namespace test {

std::size_t allocationCount();  ///< global count of operator new calls so far
/// Count of operator new calls made by the calling thread so far: what one
/// thread (e.g. a real-time loop's) allocated while others run.
std::size_t threadAllocationCount();

/// Per-thread counts by kernel thread id, for threads one cannot run code in
/// (e.g. a deployment's activities, found by name in /proc/self/task): a
/// thread gets a slot at its first allocation (up to 256 threads; a thread
/// that never allocated has none: count 0).
struct ThreadAllocations {
  long tid;
  std::size_t count;
};
/// Fills `out` with up to `max` slots; returns how many.
std::size_t allThreadAllocations(ThreadAllocations* out, std::size_t max);

class AllocationScope {
 public:
  AllocationScope() : start_(allocationCount()) {}
  std::size_t count() const { return allocationCount() - start_; }

 private:
  std::size_t start_;
};

}  // namespace test
}  // namespace tactile
