// tactile::SafetySupervisor alone: step limits, workspace box, force-ceiling
// latch and retreat, stale data, contact-loss recovery, configuration errors.
#include <limits>

#include "alloc_counter.hpp"
#include "servo_test_util.hpp"
#include "tactile_servo/safety_supervisor.hpp"

using namespace tactile;
using namespace servo_test;

namespace {
SafetySupervisor configured(const SafetyParams& s) {
  ServoParams p = singlePhase(identityPhase("p", 0, 0));
  p.safety = s;
  SafetySupervisor sup;
  const ConfigResult r = sup.configure(p);
  EXPECT_TRUE(r.ok()) << r.message();
  return sup;
}
}  // namespace

TEST(SafetySupervisor, StepLimitsScaleKeepingTheDirection) {
  SafetyParams s;
  s.max_trans_speed = 0.05;  // m/s: 0.5 mm per 10 ms cycle
  s.max_rot_speed = 1.0;     // rad/s: 0.01 rad per cycle
  const SafetySupervisor sup = configured(s);
  Vec6 u;
  u << 0.003, 0.004, 0.0, 0.0, 0.0, 0.02;  // 5 mm, 0.02 rad
  Vec6 v = u;
  EXPECT_TRUE(sup.limitStep(u, 0.01));
  EXPECT_NEAR(u(kX), 0.0003, 1e-15);
  EXPECT_NEAR(u(kY), 0.0004, 1e-15);
  EXPECT_NEAR(u(kWZ), 0.01, 1e-15);
  // The same speed over a 1 ms cycle: a tenth of the step.
  EXPECT_TRUE(sup.limitStep(v, 0.001));
  EXPECT_NEAR(v(kX), 0.00003, 1e-15);
  EXPECT_NEAR(v(kY), 0.00004, 1e-15);
  EXPECT_NEAR(v(kWZ), 0.001, 1e-15);
  // A stalled loop (dt = 5 s) moves at most max_step_dt (0.1 s) worth.
  Vec6 w;
  w << 0.3, 0.4, 0, 0, 0, 0;
  EXPECT_TRUE(sup.limitStep(w, 5.0));
  EXPECT_NEAR(w.head<3>().norm(), 0.005, 1e-15);
  Vec6 small = Vec6::Constant(1e-5);
  const Vec6 keep = small;
  EXPECT_FALSE(sup.limitStep(small, 0.01));
  EXPECT_EQ(small, keep);
}

TEST(SafetySupervisor, WorkspaceBoxClipsButNeverJumpsOntoIt) {
  SafetyParams s;
  s.workspace_min = {0.0, 0.0, 0.3};
  s.workspace_max = {1.0, 1.0, 1.0};
  const SafetySupervisor sup = configured(s);
  KDL::Frame T(KDL::Vector(0.5, 0.5, 0.29));
  EXPECT_TRUE(sup.clipWorkspace(KDL::Vector(0.5, 0.5, 0.31), T));
  EXPECT_EQ(T.p.z(), 0.3);
  // From outside (z = 0.1): moving back towards the box is allowed, further out is not.
  KDL::Frame in(KDL::Vector(0.5, 0.5, 0.12));
  EXPECT_FALSE(sup.clipWorkspace(KDL::Vector(0.5, 0.5, 0.1), in));
  EXPECT_EQ(in.p.z(), 0.12);
  KDL::Frame out(KDL::Vector(0.5, 0.5, 0.09));
  EXPECT_TRUE(sup.clipWorkspace(KDL::Vector(0.5, 0.5, 0.1), out));
  EXPECT_EQ(out.p.z(), 0.1);
}

TEST(SafetySupervisor, ForceCeilingLatchesRetreatsThenHolds) {
  SafetyParams s;
  s.force_ceiling = 20.0;
  s.ceiling_retreat = 0.0012;
  s.max_trans_speed = 0.05;  // 0.5 mm per 10 ms cycle
  SafetySupervisor sup = configured(s);
  ContactFeatures f = makeFeatures(0, 0, 0, 0.002, 0, 0, 0);
  f.force = 19.0;
  double r = -1.0;
  EXPECT_FALSE(sup.forceCeiling(f, true, 0.01, r));
  EXPECT_EQ(r, 0.0);
  f.force = 25.0;
  ContactFeatures bad = f;
  bad.status = FeatureStatus::InvalidInput;  // unusable features do not trip it
  EXPECT_FALSE(sup.forceCeiling(bad, true, 0.01, r));
  EXPECT_FALSE(sup.forceCeiling(f, false, 0.01, r));  // nor non-finite ones
  double total = 0.0;
  std::vector<double> steps;
  for (int k = 0; k < 6; ++k) {
    EXPECT_TRUE(sup.forceCeiling(f, true, 0.01, r));
    steps.push_back(r);
    total += r;
    f.force = 1.0;  // latched: the force going back down changes nothing
  }
  EXPECT_NEAR(steps[0], 0.0005, 1e-15);
  EXPECT_NEAR(steps[1], 0.0005, 1e-15);
  EXPECT_NEAR(steps[2], 0.0002, 1e-15);
  EXPECT_EQ(steps[3], 0.0);
  EXPECT_NEAR(total, 0.0012, 1e-15);
  EXPECT_TRUE(sup.ceilingLatched());
  sup.clearCeiling();
  EXPECT_FALSE(sup.forceCeiling(f, true, 0.01, r));
}

TEST(SafetySupervisor, StaleOrUnusableFeatures) {
  SafetyParams s;
  s.stale_timeout = 0.05;
  const SafetySupervisor sup = configured(s);
  ContactFeatures f = makeFeatures(1.0, 0, 0, 0.002, 0, 0, 0);
  EXPECT_FALSE(sup.stale(f, 1.0));
  EXPECT_FALSE(sup.stale(f, 1.049));
  EXPECT_TRUE(sup.stale(f, 1.051));
  EXPECT_TRUE(sup.stale(f, 0.949));  // from the future
  f.status = FeatureStatus::BadDimensions;
  EXPECT_TRUE(sup.stale(f, 1.0));
  f.status = FeatureStatus::NoContact;  // usable: no contact is information
  EXPECT_FALSE(sup.stale(f, 1.0));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ContactFeatures g = makeFeatures(1.0, 0, 0, 0.002, 0, 0, 0);
  EXPECT_TRUE(SafetySupervisor::featuresFinite(g));
  g.alpha_z = nan;
  EXPECT_FALSE(SafetySupervisor::featuresFinite(g));
}

TEST(SafetySupervisor, ContactLossHoldBackoffSearch) {
  for (ContactLossMode mode : {ContactLossMode::Hold, ContactLossMode::Backoff, ContactLossMode::Search}) {
    SafetyParams s;
    s.contact_loss = mode;
    s.max_trans_speed = 0.05;  // 0.5 mm per 10 ms cycle
    s.backoff_distance = 0.0012;
    s.search_speed = 0.02;  // 0.2 mm per 10 ms
    s.search_max_distance = 0.0005;
    SafetySupervisor sup = configured(s);
    double moved = 0.0;
    int moves = 0;
    for (int k = 0; k < 10; ++k) {
      const double dz = sup.contactLoss(0.01);
      moved += dz;
      if (dz != 0.0) ++moves;
    }
    if (mode == ContactLossMode::Hold) {
      EXPECT_EQ(moves, 0);
    } else if (mode == ContactLossMode::Backoff) {
      EXPECT_NEAR(moved, -0.0012, 1e-15);  // away from the object, at the step limit: 3 moves
      EXPECT_EQ(moves, 3);
    } else {
      EXPECT_NEAR(moved, 0.0005, 1e-15);  // towards it at the search speed: 0.2, 0.2, 0.1 mm
      EXPECT_EQ(moves, 3);
    }
    sup.resetRecovery();  // contact came back: a later loss recovers again
    EXPECT_EQ(sup.contactLoss(0.01) != 0.0, mode != ContactLossMode::Hold);
  }
}

TEST(SafetySupervisor, ConfigurationErrorsNameTheKeyAndRange) {
  ServoParams p = singlePhase(identityPhase("p", 0, 0));
  p.source = "prog.yaml";
  SafetySupervisor sup;
  ServoParams q = p;
  q.safety.max_trans_speed = 2.0;
  EXPECT_NE(sup.configure(q).message().find("prog.yaml: safety.max_trans_speed = 2: must be in (0, 1] m/s"),
            std::string::npos) << sup.configure(q).message();
  q = p;
  q.safety.workspace_min[1] = 3.0;
  EXPECT_NE(sup.configure(q).message().find("safety.workspace"), std::string::npos);
  q = p;
  q.safety.search_speed = -1.0;
  EXPECT_NE(sup.configure(q).message().find("safety.contact_loss.search_speed"), std::string::npos);
  EXPECT_FALSE(sup.configured());
  EXPECT_TRUE(sup.configure(p).ok());
}

// A stream that re-sends its last frame (new seq and time stamp, the same
// image) while the arm slides: held as stale once the image has stood for
// frozen_image_s and the flange moved more than frozen_image_travel; a new
// image or the end of the contact releases it.
TEST(SafetySupervisor, AFrozenImageWhileTheArmMovesIsHeld) {
  SafetyParams s;
  s.frozen_image_travel = 0.002;  // m
  s.frozen_image_s = 0.1;         // s
  SafetySupervisor sup = configured(s);
  ContactFeatures f = makeFeatures(0.0, 0.001, 0.0017, 0.0028, 0.0, 0.0017, 0.035);
  f.area = 13;
  f.lambda1 = 1.6e-4;
  const double v = 0.0105, dt = 0.01;  // m/s along x_g: the slide; s, one frame a cycle
  int first_held = -1;
  for (int k = 0; k < 40; ++k) {
    f.seq = static_cast<uint32_t>(k + 1);
    f.time_s = k * dt;
    const bool held = sup.frozenImage(f, KDL::Vector(v * k * dt, 0.0, 0.3), k * dt);
    if (held && first_held < 0) first_held = k;
    if (first_held >= 0) {
      EXPECT_TRUE(held) << "latched until the image changes, cycle " << k;
    }
  }
  // 2 mm at 10.5 mm/s: the first frame past 2 mm of travel (2.1 mm, after 0.2 s >= 0.1 s) is held.
  EXPECT_EQ(first_held, 20);
  // The same frame again (no new seq) keeps the verdict; a new image releases it.
  EXPECT_TRUE(sup.frozenImage(f, KDL::Vector(0.4, 0.0, 0.3), 0.5));
  f.seq = 100;
  f.force += 1e-6;
  EXPECT_FALSE(sup.frozenImage(f, KDL::Vector(0.4, 0.0, 0.3), 0.5));
}

TEST(SafetySupervisor, ARepeatedImageWithoutMotionOrWithoutContactIsNotFrozen) {
  SafetyParams s;
  s.frozen_image_travel = 0.002;
  SafetySupervisor sup = configured(s);
  ContactFeatures f = makeFeatures(0.0, 0.001, 0.0017, 0.0028, 0.0, 0.0017, 0.035);
  f.area = 13;
  for (int k = 0; k < 200; ++k) {  // 2 s of one image, the arm still (a frame re-sent while nothing moves)
    f.seq = static_cast<uint32_t>(k + 1);
    EXPECT_FALSE(sup.frozenImage(f, KDL::Vector(0.5, 0.0, 0.3), 0.01 * k));
  }
  ContactFeatures none = makeFeatures(0.0, 0, 0, 0, 0, 0, 0, ContactType::None);
  for (int k = 0; k < 200; ++k) {  // no contact: all-zero frames repeat, the arm moves
    none.seq = static_cast<uint32_t>(1000 + k);
    EXPECT_FALSE(sup.frozenImage(none, KDL::Vector(0.01 * k, 0.0, 0.3), 2.0 + 0.01 * k));
  }
  // Off (travel 0, the default): never.
  SafetySupervisor off = configured(SafetyParams{});
  for (int k = 0; k < 100; ++k) {
    f.seq = static_cast<uint32_t>(5000 + k);
    EXPECT_FALSE(off.frozenImage(f, KDL::Vector(0.01 * k, 0.0, 0.3), 0.01 * k));
  }
}

TEST(SafetySupervisor, NoAllocationPerCycle) {
  SafetyParams s;
  s.contact_loss = ContactLossMode::Search;
  s.frozen_image_travel = 0.002;
  SafetySupervisor sup = configured(s);
  ContactFeatures f = makeFeatures(0, 0, 0, 0.002, 0, 0, 0);
  tactile::test::AllocationScope scope;
  double sink = 0.0;
  for (int k = 0; k < 1000; ++k) {
    double r = 0.0;
    f.force = k % 100 == 50 ? 100.0 : 5.0;
    sup.forceCeiling(f, true, 0.01, r);
    if (k % 200 == 0) sup.clearCeiling();
    Vec6 u = Vec6::Constant(0.001 * (k % 5));
    sup.limitStep(u, 0.001 * (k % 20));
    KDL::Frame T(KDL::Vector(0.0, 0.0, 3.0));
    sup.clipWorkspace(KDL::Vector(), T);
    sink += r + u.sum() + T.p.z() + sup.contactLoss(0.01) + (sup.stale(f, 0.01 * k) ? 1.0 : 0.0);
    f.seq = static_cast<uint32_t>(k);
    sink += sup.frozenImage(f, KDL::Vector(0.001 * k, 0.0, 0.0), 0.01 * k) ? 1.0 : 0.0;
    if (k % 10 == 0) sup.resetRecovery();
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_TRUE(std::isfinite(sink));
}
