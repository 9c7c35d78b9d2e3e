// The speed law (tactile_servo/speed_law.hpp): each input alone lowers the
// slide speed as its admissible fraction says, the slowest input decides, the
// speed falls at once and rises at most at accel_mps2, non-finite input holds
// v_min, the ranges are named, and step() does not allocate.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "alloc_counter.hpp"
#include "tactile_servo/speed_law.hpp"
#include "tactile_types/conventions.hpp"

using namespace tactile;

namespace {

// Settled: 10 s at 100 Hz, far beyond v_max / accel (1 s at the defaults).
double settle(SpeedLaw& law, const SpeedLawInput& in) {
  for (int k = 0; k < 1000; ++k) law.step(in, 0.01);
  return law.speed();
}

SpeedLaw configured() {
  SpeedLaw law;
  EXPECT_TRUE(law.configure(SpeedLawParams{}).ok());
  return law;
}

}  // namespace

TEST(SpeedLaw, NothingToSlowForIsTheSafetyLimit) {
  SpeedLaw law = configured();
  EXPECT_DOUBLE_EQ(law.speed(), 0.002);  // starts at v_min
  EXPECT_NEAR(settle(law, SpeedLawInput{}), 0.05, 1e-12);
  EXPECT_EQ(law.step(SpeedLawInput{}, 0.01), SpeedLawStatus::Full);
  EXPECT_EQ(law.limiter(), SpeedLimiter::None);
}

// Each input alone, at half its reference: v = v_max (1 - 1/2); at its
// reference or beyond: v_min. Exact (the law is piecewise linear).
TEST(SpeedLaw, EachInputAloneLowersTheSpeedByItsFraction) {
  const SpeedLawParams p;
  struct Case {
    const char* name;
    SpeedLawInput half, full;
    SpeedLimiter limiter;
  };
  auto with = [](auto set) {
    SpeedLawInput in;
    set(in);
    return in;
  };
  const Case cases[] = {
      {"force error", with([](SpeedLawInput& i) { i.force_error_n = 0.25; }),
       with([](SpeedLawInput& i) { i.force_error_n = -0.5; }), SpeedLimiter::Force},
      {"force error rate (predicted 0.2 s ahead)", with([](SpeedLawInput& i) { i.force_error_rate = 1.25; }),
       with([](SpeedLawInput& i) { i.force_error_rate = -2.5; }), SpeedLimiter::Force},
      {"edge angle rate", with([](SpeedLawInput& i) { i.angle_rate = -0.25; }),
       with([](SpeedLawInput& i) { i.angle_rate = 0.5; }), SpeedLimiter::AngleRate},
      {"edge line curvature", with([](SpeedLawInput& i) { i.curvature = 2.75; }),
       with([](SpeedLawInput& i) { i.curvature = -6.0; }), SpeedLimiter::Curvature},
      {"image extent", with([](SpeedLawInput& i) { i.extent_m = 0.5 * (0.0476 + 0.0119); }),
       with([](SpeedLawInput& i) { i.extent_m = 0.0119; }), SpeedLimiter::Extent},
      {"wrench excess", with([](SpeedLawInput& i) { i.wrench_excess_n = 0.6; }),
       with([](SpeedLawInput& i) { i.wrench_excess_n = 1.2; }), SpeedLimiter::WrenchExcess},
  };
  for (const Case& c : cases) {
    SpeedLaw law = configured();
    EXPECT_NEAR(settle(law, c.half), 0.5 * p.v_max, 1e-12) << c.name;
    EXPECT_EQ(law.limiter(), c.limiter) << c.name;
    EXPECT_EQ(law.step(c.half, 0.01), SpeedLawStatus::Limited) << c.name;
    EXPECT_NEAR(settle(law, c.full), p.v_min, 1e-12) << c.name;
  }
  // A force error that is closing (e + h de/dt = 0) does not slow the slide.
  SpeedLaw law = configured();
  SpeedLawInput closing;
  closing.force_error_n = 0.4;
  closing.force_error_rate = -2.0;
  EXPECT_NEAR(settle(law, closing), p.v_max, 1e-12);
  // A wrench below the taxels' force (negative excess) does not either.
  SpeedLawInput below;
  below.wrench_excess_n = -3.0;
  EXPECT_NEAR(settle(law, below), p.v_max, 1e-12);
}

// The wrench's excess past its dead band: nothing up to it, then linear to
// v_min at excess_ref_n (1.6 and 4 N: bent_bar_speed_law.yaml's). Exact.
TEST(SpeedLaw, TheWrenchExcessSlowsOnlyPastItsDeadBand) {
  SpeedLawParams p;
  p.excess_deadband_n = 1.6;
  p.excess_ref_n = 4.0;
  SpeedLaw law;
  ASSERT_TRUE(law.configure(p).ok());
  SpeedLawInput in;
  in.wrench_excess_n = 1.6;  // what the firing threshold hides: full speed
  EXPECT_NEAR(settle(law, in), p.v_max, 1e-12);
  EXPECT_EQ(law.limiter(), SpeedLimiter::None);
  in.wrench_excess_n = 2.8;  // half way from the dead band to the reference
  EXPECT_NEAR(settle(law, in), 0.5 * p.v_max, 1e-12);
  EXPECT_EQ(law.limiter(), SpeedLimiter::WrenchExcess);
  in.wrench_excess_n = 4.0;
  EXPECT_NEAR(settle(law, in), p.v_min, 1e-12);
}

// A short image's dead band grows with its extent (40 N/m up to 40 mm:
// bent_bar_speed_law.yaml's); a longer image (a line along the pad, two spots
// at its ends) keeps the base dead band. Exact.
TEST(SpeedLaw, AShortImagesExcessDeadBandGrowsWithItsExtent) {
  SpeedLawParams p;
  p.excess_deadband_n = 1.6;
  p.excess_ref_n = 4.0;
  p.excess_deadband_per_m = 40.0;
  p.excess_short_max_m = 0.04;
  p.extent_min_m = 0.0;
  p.extent_full_m = 0.016;  // the extent's own input does not slow any of these
  SpeedLaw law;
  ASSERT_TRUE(law.configure(p).ok());
  SpeedLawInput in;
  in.wrench_excess_n = 2.8;
  in.extent_m = 0.03;  // dead band 1.6 + 1.2 N: the taxels miss 2.8 N of a convex bend's load
  EXPECT_NEAR(settle(law, in), p.v_max, 1e-12);
  EXPECT_EQ(law.limiter(), SpeedLimiter::None);
  in.wrench_excess_n = 4.0;  // 1.2 N past it, half of excess_ref_n - excess_deadband_n
  EXPECT_NEAR(settle(law, in), 0.5 * p.v_max, 1e-12);
  EXPECT_EQ(law.limiter(), SpeedLimiter::WrenchExcess);
  in.extent_m = 0.04;  // the longest image that grows it: 1.6 + 1.6 N
  EXPECT_NEAR(settle(law, in), (1.0 - 0.8 / 2.4) * p.v_max, 1e-12);
  in.extent_m = 0.0476;  // a line along the whole pad: 1.6 N, 4 N stops it
  EXPECT_NEAR(settle(law, in), p.v_min, 1e-12);
  in.extent_m = 0.07;  // two spots at the pad's ends: a bridged trough
  EXPECT_NEAR(settle(law, in), p.v_min, 1e-12);
  in.wrench_excess_n = 2.8;
  EXPECT_NEAR(settle(law, in), 0.5 * p.v_max, 1e-12);
  p.excess_deadband_per_m = 0.0;  // off: the extent does not matter
  ASSERT_TRUE(law.configure(p).ok());
  in.extent_m = 0.03;
  EXPECT_NEAR(settle(law, in), 0.5 * p.v_max, 1e-12);
}

TEST(SpeedLaw, TheSlowestInputDecides) {
  SpeedLaw law = configured();
  SpeedLawInput in;
  in.force_error_n = 0.1;   // 0.8
  in.curvature = 2.2;       // 0.6
  in.angle_rate = 0.15;     // 0.7
  EXPECT_NEAR(settle(law, in), 0.6 * 0.05, 1e-12);
  EXPECT_EQ(law.limiter(), SpeedLimiter::Curvature);
}

// Slow down at once (before the bend), speed up at most at accel_mps2.
TEST(SpeedLaw, DownAtOnceUpAtTheAccelerationLimit) {
  for (double dt : {0.01, 0.001}) {
    SpeedLaw law = configured();
    settle(law, SpeedLawInput{});
    SpeedLawInput bend;
    bend.angle_rate = 0.4;  // 0.2 of v_max
    law.step(bend, dt);
    EXPECT_NEAR(law.speed(), 0.01, 1e-12) << dt;
    // Back to nothing: +0.05 m/s^2, so 0.01 -> 0.05 m/s takes 0.8 s.
    const int n = static_cast<int>(std::lround(0.4 / dt));
    for (int k = 0; k < n; ++k) law.step(SpeedLawInput{}, dt);
    EXPECT_NEAR(law.speed(), 0.01 + 0.05 * 0.4, 1e-9) << dt;
    EXPECT_NEAR(law.target(), 0.05, 1e-12) << dt;
  }
}

TEST(SpeedLaw, NonFiniteInputHoldsVMin) {
  SpeedLaw law = configured();
  settle(law, SpeedLawInput{});
  SpeedLawInput bad;
  bad.curvature = std::nan("");
  EXPECT_EQ(law.step(bad, 0.01), SpeedLawStatus::InvalidInput);
  EXPECT_DOUBLE_EQ(law.speed(), 0.002);
  EXPECT_EQ(law.step(SpeedLawInput{}, -1.0), SpeedLawStatus::InvalidInput);
  SpeedLaw none;
  EXPECT_EQ(none.step(SpeedLawInput{}, 0.01), SpeedLawStatus::NotConfigured);
}

TEST(SpeedLaw, RangesNameTheKey) {
  struct Bad {
    const char* key;
    void (*set)(SpeedLawParams&);
  };
  const Bad bad[] = {
      {"speed_law.v_max", [](SpeedLawParams& p) { p.v_max = 0.0; }},
      {"speed_law.v_min", [](SpeedLawParams& p) { p.v_min = 0.1; }},
      {"speed_law.accel_mps2", [](SpeedLawParams& p) { p.accel_mps2 = -1.0; }},
      {"speed_law.force_budget_n", [](SpeedLawParams& p) { p.force_budget_n = 0.0; }},
      {"speed_law.horizon_s", [](SpeedLawParams& p) { p.horizon_s = std::nan(""); }},
      {"speed_law.angle_rate_ref", [](SpeedLawParams& p) { p.angle_rate_ref = 0.0; }},
      {"speed_law.curvature_ref", [](SpeedLawParams& p) { p.curvature_ref = -1.0; }},
      {"speed_law.extent_full_m", [](SpeedLawParams& p) { p.extent_full_m = 0.01; }},
      {"speed_law.excess_ref_n", [](SpeedLawParams& p) { p.excess_ref_n = 0.0; }},
      {"speed_law.excess_deadband_n", [](SpeedLawParams& p) { p.excess_deadband_n = p.excess_ref_n; }},
      {"speed_law.excess_deadband_n", [](SpeedLawParams& p) { p.excess_deadband_n = -0.1; }},
      {"speed_law.excess_deadband_per_m", [](SpeedLawParams& p) { p.excess_deadband_per_m = -1.0; }},
      {"speed_law.excess_deadband_per_m", [](SpeedLawParams& p) { p.excess_deadband_per_m = std::nan(""); }},
      {"speed_law.excess_short_max_m", [](SpeedLawParams& p) { p.excess_short_max_m = 1.5; }},
      {"speed_law.drive_fraction", [](SpeedLawParams& p) { p.drive_fraction = 1.1; }},
      {"speed_law.guard_excess_n", [](SpeedLawParams& p) { p.guard_excess_n = 0.0; }},
      {"speed_law.guard_accel_mps2", [](SpeedLawParams& p) { p.guard_accel_mps2 = 0.0; }},
      {"speed_law.crawl_mps", [](SpeedLawParams& p) { p.crawl_mps = p.v_max + 0.01; }},
      {"speed_law.crawl_after_s", [](SpeedLawParams& p) { p.crawl_after_s = -1.0; }},
  };
  for (const Bad& b : bad) {
    SpeedLawParams p;
    b.set(p);
    SpeedLaw law;
    const ConfigResult r = law.configure(p);
    ASSERT_FALSE(r.ok()) << b.key;
    EXPECT_NE(r.message().find(b.key), std::string::npos) << r.message();
    EXPECT_EQ(law.step(SpeedLawInput{}, 0.01), SpeedLawStatus::NotConfigured) << b.key;
  }
}

// ---- slide(): the rate along the slide axis from the phase's pull ----------

namespace {
SpeedLawParams slideParams() {
  SpeedLawParams p;
  p.v_max = 0.12;
  p.v_min = 0.005;
  p.accel_mps2 = 1.0;
  p.excess_ref_n = 4.0;
  p.excess_deadband_n = 1.6;
  p.drive_fraction = 0.6;
  p.guard_excess_n = 1.4;
  p.guard_accel_mps2 = 0.6;
  p.crawl_mps = 0.02;
  p.crawl_after_s = 0.2;
  return p;
}
}  // namespace

// Capped at +-speed(); below drive_fraction speed() the pull is raised to it,
// in its own direction; no pull, no slide. With drive_fraction 0 the law only
// caps (the pull passes below the cap unchanged).
TEST(SpeedLaw, TheSlideIsCappedAndDrivenInThePullsDirection) {
  SpeedLaw law;
  ASSERT_TRUE(law.configure(slideParams()).ok());
  ASSERT_NEAR(settle(law, SpeedLawInput{}), 0.12, 1e-12);
  EXPECT_FALSE(law.guarded());
  EXPECT_DOUBLE_EQ(law.slide(0.5, 0.01), 0.12);     // capped
  EXPECT_DOUBLE_EQ(law.slide(-0.5, 0.01), -0.12);
  EXPECT_DOUBLE_EQ(law.slide(0.1, 0.01), 0.1);      // above 0.6 x 0.12: as pulled
  EXPECT_DOUBLE_EQ(law.slide(0.03, 0.01), 0.072);   // a crest's weak pull: driven at 0.6 x 0.12
  EXPECT_DOUBLE_EQ(law.slide(-0.03, 0.01), -0.072);
  EXPECT_DOUBLE_EQ(law.slide(0.0, 0.01), 0.0);
  SpeedLawParams p = slideParams();
  p.drive_fraction = 0.0;
  SpeedLaw cap;
  ASSERT_TRUE(cap.configure(p).ok());
  settle(cap, SpeedLawInput{});
  EXPECT_DOUBLE_EQ(cap.slide(0.03, 0.01), 0.03);
  EXPECT_DOUBLE_EQ(cap.slide(0.5, 0.01), 0.12);
  // Non-finite pull or dt: no slide.
  EXPECT_EQ(law.slide(std::nan(""), 0.01), 0.0);
  EXPECT_EQ(law.slide(0.03, 0.0), 0.0);
}

// Guarded (the taxels miss more than guard_excess_n): no drive, and the
// slide's speed rises at most guard_accel_mps2 per second from the last
// cycle's, however the pull jumps; below the guard the drive is back.
TEST(SpeedLaw, TheGuardDropsTheDriveAndSlowsTheSlidesRise) {
  SpeedLaw law;
  ASSERT_TRUE(law.configure(slideParams()).ok());
  SpeedLawInput in;
  ASSERT_NEAR(settle(law, in), 0.12, 1e-12);
  EXPECT_DOUBLE_EQ(law.slide(0.03, 0.01), 0.072);  // driven
  in.wrench_excess_n = 1.5;  // above the guard, below the excess's dead band: the cap stays v_max
  law.step(in, 0.01);
  EXPECT_TRUE(law.guarded());
  EXPECT_DOUBLE_EQ(law.speed(), 0.12);
  EXPECT_DOUBLE_EQ(law.slide(0.03, 0.01), 0.03);  // not driven: falls at once
  // The pull jumps to 0.1 m/s (two spots at the pad's ends move the CoP):
  // the slide rises by 0.6 m/s^2 x 0.01 s a cycle.
  double v = 0.03;
  for (int k = 1; k <= 5; ++k) {
    law.step(in, 0.01);
    const double s = law.slide(0.1, 0.01);
    EXPECT_NEAR(s, v + 0.006, 1e-12) << k;
    v = s;
  }
  // It falls at once, and rises from there.
  law.step(in, 0.01);
  EXPECT_DOUBLE_EQ(law.slide(0.01, 0.01), 0.01);
  law.step(in, 0.01);
  EXPECT_NEAR(law.slide(0.1, 0.01), 0.016, 1e-12);
  // Below the guard: driven again, and the pull's jump is followed.
  in.wrench_excess_n = 1.3;
  law.step(in, 0.01);
  EXPECT_FALSE(law.guarded());
  EXPECT_DOUBLE_EQ(law.slide(0.03, 0.01), 0.072);
  law.step(in, 0.01);
  EXPECT_DOUBLE_EQ(law.slide(0.1, 0.01), 0.1);
  // Non-finite input: guarded (v_min and no drive).
  in.wrench_excess_n = std::nan("");
  EXPECT_EQ(law.step(in, 0.01), SpeedLawStatus::InvalidInput);
  EXPECT_TRUE(law.guarded());
}

// The crawl: once the excess has held the target at v_min (a_x = 0) for
// crawl_after_s, the excess allows crawl_mps; before, v_min, and an excess
// below excess_ref restarts the count; once crawling, only an excess that
// allows more than crawl_mps ends it. crawl_mps 0: v_min throughout.
TEST(SpeedLaw, AnExcessThatHasStoppedTheSlideAWhileLetsItCrawl) {
  SpeedLaw law;
  ASSERT_TRUE(law.configure(slideParams()).ok());
  SpeedLawInput in;
  settle(law, in);
  in.wrench_excess_n = 4.5;  // past excess_ref: a_x = 0
  int first_crawl = -1;
  for (int k = 1; k <= 100; ++k) {
    law.step(in, 0.01);
    if (first_crawl < 0 && law.target() > 0.005) first_crawl = k;
    if (first_crawl < 0) {
      EXPECT_DOUBLE_EQ(law.speed(), 0.005) << k;
      EXPECT_EQ(law.limiter(), SpeedLimiter::WrenchExcess);
    }
  }
  EXPECT_EQ(first_crawl, 20);  // 0.2 s stopped
  EXPECT_NEAR(law.speed(), 0.02, 1e-12);
  EXPECT_NEAR(law.target(), 0.02, 1e-12);
  // Crawling, an excess that allows less than the crawl (3.8 N: a_x 1/12,
  // 10 mm/s) keeps it, and so does the excess back past its reference.
  in.wrench_excess_n = 3.8;
  law.step(in, 0.01);
  EXPECT_NEAR(law.target(), 0.02, 1e-12);
  in.wrench_excess_n = 4.5;
  law.step(in, 0.01);
  EXPECT_NEAR(law.target(), 0.02, 1e-12);
  // An excess that allows more than the crawl (3 N: 50 mm/s) ends it; the
  // excess then stops the slide again: v_min anew.
  in.wrench_excess_n = 3.0;
  law.step(in, 0.01);
  in.wrench_excess_n = 4.5;
  law.step(in, 0.01);
  EXPECT_DOUBLE_EQ(law.speed(), 0.005);
  // Before the crawl, any excess below the reference starts the wait afresh:
  // after 0.1 s stopped, one cycle at 3.8 N, then 0.2 s more to the crawl.
  SpeedLaw again;
  ASSERT_TRUE(again.configure(slideParams()).ok());
  SpeedLawInput in2;
  settle(again, in2);
  in2.wrench_excess_n = 4.5;
  for (int k = 0; k < 10; ++k) again.step(in2, 0.01);
  in2.wrench_excess_n = 3.8;
  again.step(in2, 0.01);
  EXPECT_NEAR(again.target(), 0.01, 1e-12);
  in2.wrench_excess_n = 4.5;
  for (int k = 1; k <= 19; ++k) {
    again.step(in2, 0.01);
    EXPECT_DOUBLE_EQ(again.target(), 0.005) << k;
  }
  again.step(in2, 0.01);
  EXPECT_NEAR(again.target(), 0.02, 1e-12);
  SpeedLawParams p = slideParams();
  p.crawl_mps = 0.0;
  SpeedLaw off;
  ASSERT_TRUE(off.configure(p).ok());
  for (int k = 0; k < 100; ++k) off.step(in, 0.01);
  EXPECT_DOUBLE_EQ(off.speed(), 0.005);
}

TEST(SpeedLaw, StepDoesNotAllocate) {
  SpeedLaw law;
  ASSERT_TRUE(law.configure(slideParams()).ok());
  SpeedLawInput in;
  test::AllocationScope scope;
  for (int k = 0; k < 1000; ++k) {
    in.curvature = 0.01 * (k % 700);
    in.force_error_n = 0.001 * (k % 300);
    in.wrench_excess_n = 0.01 * (k % 500);
    law.step(in, 0.001);
    law.slide(0.0002 * (k % 400) - 0.04, 0.001);
  }
  EXPECT_EQ(scope.count(), 0u);
}

// ---- SpeedLawFilter: the raw signals of a cycle into the law's inputs ------

// A force error rising at 2 N/s: after 10 tau the low-passed error lags the
// ramp by 2 N/s x tau (first-order lag of a ramp) and the rate is 2 N/s to
// within 1e-6 (the lag's transient decays as exp(-t/tau): e^-20 ~ 2e-9).
TEST(SpeedLawFilter, AForceRampGivesItsRate) {
  SpeedLawFilter flt;
  flt.configure(0.05);
  SpeedLawInput in;
  const double dt = 0.01;
  for (int k = 0; k <= 100; ++k) {
    SpeedLawSignals s;
    s.force_error_n = 2.0 * k * dt;
    flt.step(s, dt, in);
  }
  EXPECT_NEAR(in.force_error_rate, 2.0, 1e-6);
  // Discrete first-order lag of a ramp: rate x tau (exact for a = dt / (tau + dt)).
  EXPECT_NEAR(2.0 - in.force_error_n, 2.0 * 0.05, 1e-6);
}

// The wrench's excess is low-passed over its own time constant
// (speed_law.excess_tau_s), the other inputs over rate_tau_s; 0 means
// rate_tau_s. A step of 3 N in the excess and of 1 N in the force error:
// after n cycles the discrete first-order lag has 1 - (tau / (tau + dt))^n of it.
TEST(SpeedLawFilter, TheExcessHasItsOwnTimeConstant) {
  const double dt = 0.01;
  for (double excess_tau : {0.03, 0.0}) {
    SpeedLawFilter flt;
    flt.configure(0.1, excess_tau);
    SpeedLawInput in;
    SpeedLawSignals s;
    flt.step(s, dt, in);  // the first cycle initialises at 0
    s.wrench_excess_n = 3.0;
    s.force_error_n = 1.0;
    const double te = excess_tau > 0.0 ? excess_tau : 0.1;
    for (int n = 1; n <= 5; ++n) {
      flt.step(s, dt, in);
      EXPECT_NEAR(in.wrench_excess_n, 3.0 * (1.0 - std::pow(te / (te + dt), n)), 1e-12) << excess_tau << " " << n;
      EXPECT_NEAR(in.force_error_n, 1.0 - std::pow(0.1 / (0.1 + dt), n), 1e-12) << excess_tau << " " << n;
    }
  }
}

// The edge angle is defined modulo pi: a turn from +89 deg to -89 deg is 2 deg,
// not 178 deg; an undefined angle (held, not measured) gives no rate.
TEST(SpeedLawFilter, TheAngleRateIsTakenModuloPiAndOnlyWhenDefined) {
  constexpr double kDeg = kPi / 180.0;
  SpeedLawFilter flt;
  flt.configure(0.05);
  SpeedLawInput in;
  SpeedLawSignals s;
  s.alpha_defined = true;
  // 1 deg per 10 ms cycle = 100 deg/s = 1.745 rad/s, through the wrap at 90 deg.
  double a = 80 * kDeg;
  for (int k = 0; k < 60; ++k, a += 1 * kDeg) {
    s.alpha_z = std::remainder(a, kPi);
    flt.step(s, 0.01, in);
  }
  EXPECT_NEAR(in.angle_rate, 100 * kDeg, 1e-4);
  // Undefined from now on: the rate decays to 0 (no new measurement).
  s.alpha_defined = false;
  s.alpha_z = 0.3;  // a held value jumping must not count
  for (int k = 0; k < 100; ++k) flt.step(s, 0.01, in);
  EXPECT_NEAR(in.angle_rate, 0.0, 1e-6);
}

TEST(SpeedLawFilter, ANonFiniteSignalMakesTheLawHoldVMin) {
  SpeedLawFilter flt;
  flt.configure(0.05);
  SpeedLaw law = configured();
  SpeedLawInput in;
  SpeedLawSignals s;
  s.extent_m = 0.0476;  // an edge across the pad
  for (int k = 0; k < 500; ++k) {
    flt.step(s, 0.01, in);
    law.step(in, 0.01);
  }
  EXPECT_NEAR(law.speed(), 0.05, 1e-12);
  s.curvature = std::nan("");
  flt.step(s, 0.01, in);
  EXPECT_EQ(law.step(in, 0.01), SpeedLawStatus::InvalidInput);
  EXPECT_DOUBLE_EQ(law.speed(), 0.002);
  s.curvature = 0.0;  // the filter's state was kept: the next finite cycle is normal
  flt.step(s, 0.01, in);
  EXPECT_EQ(law.step(in, 0.01), SpeedLawStatus::Full);
}
