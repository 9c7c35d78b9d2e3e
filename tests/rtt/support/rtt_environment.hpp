// The RTT OS layer around a gtest binary: __os_init before the first test,
// __os_exit after the last. With Clock::Manual the TimeService advances only
// through secondsChange(), so tests control time deterministically.
#pragma once

#include <gtest/gtest.h>
#include <rtt/os/TimeService.hpp>
#include <rtt/os/main.h>

namespace tactile {
namespace test {

enum class Clock { System, Manual };

class RttEnvironment : public ::testing::Environment {
 public:
  explicit RttEnvironment(Clock clock = Clock::System) : clock_(clock) {}
  void SetUp() override {
    __os_init(0, nullptr);
    if (clock_ == Clock::Manual) RTT::os::TimeService::Instance()->enableSystemClock(false);
  }
  void TearDown() override { __os_exit(); }

 private:
  Clock clock_;
};

}  // namespace test
}  // namespace tactile
