// tactile::wts::DeviceClock against synthetic streams whose true capture
// times are known: a steady link, a burst held up in the tty, a device clock
// slower than the host's, a device restart, a device without timestamps, the
// 32-bit millisecond wrap.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "tactile_wts/device_clock.hpp"

using tactile::wts::DeviceClock;

namespace {

// The device stamps in whole milliseconds: an estimate is exact to 1 ms.
constexpr double kStampResolution = 1e-3;
// The link's smallest delay is not observable from the stamps (it is the
// offset's floor): estimates are late by it. The streams below use 2 ms.
constexpr double kFloor = 2e-3;

struct Stream {
  double t0 = 100.0;       // host time of device time 0
  double period = 0.01;    // 100 Hz
  double skew = 0.0;       // device clock runs (1 - skew) as fast as the host's
  uint32_t ms0 = 0;        // device counter at device time 0
  // frame k: true capture time on the host, the device's stamp
  double truth(int k) const { return t0 + k * period; }
  uint32_t stamp(int k) const {
    return ms0 + static_cast<uint32_t>(std::floor(1e3 * k * period * (1.0 - skew)));
  }
};

// Deterministic jitter in [0, 0.5 ms).
double jitter(int k) { return 5e-4 * ((k * 7919) % 97) / 97.0; }

}  // namespace

TEST(DeviceClock, SteadyLinkGivesTheCaptureTimeToTheStampResolution) {
  DeviceClock c;
  Stream s;
  for (int k = 0; k < 1000; ++k) {
    const double arrival = s.truth(k) + kFloor + jitter(k);
    const double t = c.capture(s.stamp(k), arrival);
    EXPECT_LE(t, arrival) << k;
    // the first frame has no history: stamped at arrival (its jitter included)
    EXPECT_NEAR(t, s.truth(k) + kFloor, kStampResolution + 5e-4) << k;
  }
  EXPECT_LT(c.stats().delay_max_s, kStampResolution + 5e-4);
  EXPECT_EQ(c.stats().restarts, 0u);
}

TEST(DeviceClock, FramesHeldUpInTheTtyKeepTheirCaptureTime) {
  DeviceClock c;
  Stream s;
  double last = 0.0;
  for (int k = 0; k < 400; ++k) {
    double arrival = s.truth(k) + kFloor + jitter(k);
    if (k >= 100 && k < 170) arrival = s.truth(170) + kFloor;  // 0.7 s of frames arrive at once
    const double t = c.capture(s.stamp(k), arrival);
    EXPECT_NEAR(t, s.truth(k) + kFloor, kStampResolution + 5e-4) << k;
    if (k == 100) {
      EXPECT_GT(arrival - t, 0.69);  // the oldest of the burst: 0.7 s old on arrival
    }
    EXPECT_GE(t, last) << k;
    last = t;
  }
  EXPECT_GT(c.stats().delay_max_s, 0.69);
  EXPECT_LT(c.stats().delay_last_s, kStampResolution + 5e-4);
}

TEST(DeviceClock, FollowsADeviceClockSlowerThanTheHosts) {
  // 200 ppm slow for 10 min: without the offset's rise the delay would grow to 0.12 s.
  DeviceClock c(1e-3);
  Stream s;
  s.skew = 2e-4;
  for (int k = 0; k < 60000; ++k) c.capture(s.stamp(k), s.truth(k) + kFloor + jitter(k));
  EXPECT_LT(c.stats().delay_max_s, 2 * kStampResolution);
  DeviceClock no_rise(0.0);
  for (int k = 0; k < 60000; ++k) no_rise.capture(s.stamp(k), s.truth(k) + kFloor + jitter(k));
  EXPECT_GT(no_rise.stats().delay_max_s, 0.1);  // the same stream, the skew not followed
}

TEST(DeviceClock, ADeviceRestartOrNoStampsFallsBackToTheArrival) {
  DeviceClock c;
  Stream s;
  for (int k = 0; k < 50; ++k) c.capture(s.stamp(k), s.truth(k) + kFloor);
  // the device restarted: its counter starts again at 0
  EXPECT_DOUBLE_EQ(c.capture(0, 200.0), 200.0);
  EXPECT_EQ(c.stats().restarts, 1u);
  // 10 ms later by the device's clock; the offset rose by max_skew x 10.5 ms meanwhile
  EXPECT_NEAR(c.capture(10, 200.0105), 200.010, 1e-3 * 0.0105 + 1e-9);
  // a device that does not stamp (always 0): every frame at its arrival
  DeviceClock z;
  for (int k = 0; k < 20; ++k) EXPECT_DOUBLE_EQ(z.capture(0, 300.0 + 0.01 * k), 300.0 + 0.01 * k);
  EXPECT_EQ(z.stats().restarts, 19u);
  EXPECT_DOUBLE_EQ(z.stats().delay_max_s, 0.0);
}

TEST(DeviceClock, UnwrapsTheMillisecondCounter) {
  DeviceClock c;
  Stream s;
  s.ms0 = 0xFFFFFFFFu - 250;  // wraps after 25 frames
  for (int k = 0; k < 100; ++k) {
    const double t = c.capture(s.stamp(k), s.truth(k) + kFloor);
    EXPECT_NEAR(t, s.truth(k) + kFloor, kStampResolution) << k;
  }
  EXPECT_EQ(c.stats().restarts, 0u);
}

TEST(DeviceClock, ResetForgetsTheOffset) {
  DeviceClock c;
  Stream s;
  for (int k = 0; k < 10; ++k) c.capture(s.stamp(k), s.truth(k));
  c.reset();
  // a new connection to a device whose clock is 5 s further: no restart counted, stamped at arrival
  EXPECT_DOUBLE_EQ(c.capture(s.stamp(10) + 5000, 150.0), 150.0);
  EXPECT_EQ(c.stats().restarts, 0u);
}
