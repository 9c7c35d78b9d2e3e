// Extremes and safety: zero/huge gains, NaN/Inf, dt = 0 and negative, stale
// features, force ceiling, contact-loss recovery, workspace box, phase
// requests, transitions, zero heap allocation per step.
#include <cstdio>
#include <limits>
#include <random>

#include "alloc_counter.hpp"
#include "servo_test_util.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

struct Rig {
  TactileServo s;
  ServoInput in;
  ServoOutput out;
  double t = 0.0;
  explicit Rig(const ServoParams& p) {
    const ConfigResult r = s.configure(p);
    EXPECT_TRUE(r.ok()) << r.message();
    in.flange_measured = toPose(KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.5, 0.1, 0.3)));
    in.features = makeFeatures(0, 0.004, -0.003, 0.002, 0.001, -0.001, 0.1);
  }
  // The start cycle: the first valid measured pose is commanded unchanged.
  void start() {
    in.time_s = in.features.time_s = t;
    EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);
    EXPECT_EQ(out.command.pose.p, in.flange_measured.p);
  }
  // One step with fresh features (time-stamped now); integrated mode: the robot follows.
  ServoStatus step(double dt = 0.01) {
    t += dt > 0 && std::isfinite(dt) ? dt : 0.0;
    in.time_s = t;
    in.features.time_s = t;
    const ServoStatus st = s.step(in, dt, out);
    if (out.valid) in.flange_measured = out.command.pose;
    return st;
  }
  // Sensor origin displacement since `T_ge0`, expressed in {s} of T_ge0.
  KDL::Vector sensorShift(const Pose& from) const {
    const KDL::Frame T_es = s.params().sensor_mount;
    const KDL::Frame a = toFrame(from) * T_es, b = toFrame(out.command.pose) * T_es;
    return a.M.Inverse() * (b.p - a.p);
  }
};

}  // namespace

TEST(ServoSafety, NotConfiguredReportsAndDoesNotCommand) {
  TactileServo s;
  ServoInput in;
  ServoOutput out;
  EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::NotConfigured);
  EXPECT_FALSE(out.valid);
  EXPECT_FALSE(s.requestPhase("x"));
}

TEST(ServoSafety, ZeroGainsNoMotion) {
  Rig r(singlePhase(identityPhase("p", 0.0, 0.0)));
  const Pose start = r.in.flange_measured;
  r.start();
  for (int k = 0; k < 100; ++k) EXPECT_EQ(r.step(), ServoStatus::Ok);
  // Only the quaternion <-> rotation matrix round trip (double precision).
  EXPECT_LT(transDist(r.out.command.pose, start), 1e-12);
  EXPECT_LT(rotDist(r.out.command.pose, start), 1e-12);
  EXPECT_EQ(r.out.u_s, Vec6::Zero());
}

TEST(ServoSafety, HugeGainsBoundedByStepLimits) {
  ServoParams p = singlePhase(identityPhase("p", 1e12, 1e12));
  p.phases[0].u_max = Vec6::Constant(1e9);
  p.phases[0].integral_limit = Vec6::Constant(1e9);
  p.safety.max_trans_speed = 0.05;            // 0.5 mm per 10 ms cycle
  p.safety.max_rot_speed = 50.0 * kPi / 180;  // 0.5 deg per cycle
  Rig r(p);
  r.start();
  for (int k = 0; k < 50; ++k) {
    Pose before = r.in.flange_measured;
    EXPECT_EQ(r.step(), ServoStatus::Limited);
    ASSERT_TRUE(poseFinite(r.out.command.pose));
    EXPECT_LE(r.out.u_s.head<3>().norm(), 0.0005 * (1 + 1e-12));
    EXPECT_LE(r.out.u_s.tail<3>().norm(), 0.5 * kPi / 180 * (1 + 1e-12));
    EXPECT_LE(rotDist(before, r.out.command.pose), 0.5 * kPi / 180 * (1 + 1e-9));
  }
}

TEST(ServoSafety, NanAndInfInputsHoldAFiniteCommand) {
  Rig r(singlePhase(identityPhase("p", 0.05, 0.1)));
  for (int k = 0; k < 5; ++k) r.step();
  const Pose held = r.out.command.pose;
  double* fields[] = {&r.in.features.cop_x, &r.in.features.cop_y, &r.in.features.d_z, &r.in.features.coc_x,
                      &r.in.features.coc_y, &r.in.features.alpha_z, &r.in.features.force, &r.in.features.dzmp_y};
  for (double bad : {kNaN, kInf, -kInf}) {
    for (double* f : fields) {
      const double keep = *f;
      *f = bad;
      EXPECT_EQ(r.step(), ServoStatus::InvalidInput);
      EXPECT_TRUE(poseFinite(r.out.command.pose));
      EXPECT_EQ(r.out.command.pose.p, held.p);
      *f = keep;
    }
    // Bad measured pose (position, quaternion, zero quaternion).
    const Pose good = r.in.flange_measured;
    r.in.flange_measured.p[1] = bad;
    EXPECT_EQ(r.step(), ServoStatus::InvalidInput);
    EXPECT_EQ(r.out.command.pose.p, held.p);
    r.in.flange_measured = good;
    r.in.flange_measured.q[3] = bad;
    EXPECT_EQ(r.step(), ServoStatus::InvalidInput);
    EXPECT_EQ(r.out.command.pose.p, held.p);
    r.in.flange_measured = good;
  }
  r.in.flange_measured.q = {0, 0, 0, 0};
  EXPECT_EQ(r.step(), ServoStatus::InvalidInput);
  EXPECT_EQ(r.out.command.pose.p, held.p);
  // Enormous but finite features overflow inside Eq. 7-13: still no NaN out.
  ServoInput huge = r.in;
  huge.flange_measured = held;
  huge.features.cop_x = 1e308;
  huge.features.coc_x = -1e308;
  ServoOutput o;
  r.s.step(huge, 0.01, o);
  EXPECT_TRUE(poseFinite(o.command.pose));
}

TEST(ServoSafety, NanPoseAtFirstCycleGivesNoValidCommand) {
  Rig r(singlePhase(identityPhase("p", 0.05, 0.1)));
  r.in.flange_measured.p[0] = kNaN;
  EXPECT_EQ(r.step(), ServoStatus::InvalidInput);
  EXPECT_FALSE(r.out.valid);
  EXPECT_TRUE(poseFinite(r.out.command.pose));
}

TEST(ServoSafety, ZeroNegativeAndNanDtHold) {
  Rig r(singlePhase(identityPhase("p", 0.05, 0.1)));
  for (int k = 0; k < 5; ++k) r.step();
  const Pose held = r.out.command.pose;
  for (double dt : {0.0, -0.01, kNaN, kInf}) {
    EXPECT_EQ(r.step(dt), ServoStatus::InvalidInput) << dt;
    EXPECT_EQ(r.out.command.pose.p, held.p);
    EXPECT_EQ(r.out.u_s, Vec6::Zero());
  }
  EXPECT_EQ(r.step(0.01), ServoStatus::Ok);  // and recovers
}

TEST(ServoSafety, StaleOrUnusableFeaturesHold) {
  ServoParams p = singlePhase(identityPhase("p", 0.05, 0.1));
  p.safety.stale_timeout = 0.05;
  Rig r(p);
  for (int k = 0; k < 5; ++k) r.step();
  // Features stop arriving: their timestamp stays while time goes on.
  const double t_last = r.t;
  int holds = 0;
  for (int k = 0; k < 10; ++k) {
    const Pose prev = r.out.command.pose;
    r.t += 0.01;
    r.in.time_s = r.t;
    r.in.features.time_s = t_last;
    const ServoStatus st = r.s.step(r.in, 0.01, r.out);
    if (r.t - t_last > 0.05 + 1e-9) {  // older than stale_timeout: hold the last command
      EXPECT_EQ(st, ServoStatus::Holding);
      EXPECT_EQ(r.out.command.pose.p, prev.p);
      EXPECT_EQ(r.out.command.pose.q, prev.q);
      ++holds;
    } else if (r.t - t_last < 0.05 - 1e-9) {
      EXPECT_EQ(st, ServoStatus::Ok);
    }
  }
  EXPECT_GE(holds, 4);
  r.in.features.status = FeatureStatus::InvalidInput;
  EXPECT_EQ(r.step(), ServoStatus::Holding);
  r.in.features.status = FeatureStatus::BadDimensions;
  EXPECT_EQ(r.step(), ServoStatus::Holding);
  r.in.features.status = FeatureStatus::Ok;
  EXPECT_EQ(r.step(), ServoStatus::Ok);
}

TEST(ServoSafety, ForceCeilingRetreatsAlongMinusZsAndLatches) {
  ServoParams p = singlePhase(identityPhase("p", 0.05, 0.1));
  p.phases[0].name = "servo";
  p.safety.force_ceiling = 20.0;
  p.safety.ceiling_retreat = 0.004;
  p.safety.max_trans_speed = 0.05;  // 0.5 mm per 10 ms cycle
  p.sensor_mount = KDL::Frame(KDL::Rotation::RotY(0.3), KDL::Vector(0.01, 0, 0.03));
  Rig r(p);
  r.step();
  const Pose before = r.out.command.pose;
  r.in.features.force = 25.0;
  for (int k = 0; k < 20; ++k) EXPECT_EQ(r.step(), ServoStatus::ForceCeiling);
  // Retreated exactly 4 mm along -z_s, no other motion (8 steps of 0.5 mm, then hold).
  const KDL::Vector d = r.sensorShift(before);
  EXPECT_NEAR(d.z(), -0.004, 1e-12);
  EXPECT_NEAR(d.x(), 0.0, 1e-12);
  EXPECT_NEAR(d.y(), 0.0, 1e-12);
  EXPECT_LT(rotDist(before, r.out.command.pose), 1e-12);
  // Latched even when the force is back to normal...
  r.in.features.force = 1.0;
  EXPECT_EQ(r.step(), ServoStatus::ForceCeiling);
  // ...until an explicit phase request.
  EXPECT_TRUE(r.s.requestPhase("servo"));
  EXPECT_EQ(r.step(), ServoStatus::Ok);
}

TEST(ServoSafety, ContactLossHoldBackoffSearch) {
  for (ContactLossMode mode : {ContactLossMode::Hold, ContactLossMode::Backoff, ContactLossMode::Search}) {
    ServoParams p = singlePhase(identityPhase("p", 0.05, 0.1));
    p.safety.contact_loss = mode;
    p.safety.backoff_distance = 0.003;
    p.safety.search_speed = 0.02;          // 0.2 mm per 10 ms cycle
    p.safety.search_max_distance = 0.002;
    p.safety.max_trans_speed = 0.05;       // 0.5 mm per cycle
    Rig r(p);
    r.step();
    const Pose before = r.out.command.pose;
    r.in.features = makeFeatures(r.t, 0, 0, 0, 0, 0, 0, ContactType::None);
    for (int k = 0; k < 30; ++k) EXPECT_EQ(r.step(), ServoStatus::ContactLost);
    const KDL::Vector d = r.sensorShift(before);
    const double expect = mode == ContactLossMode::Hold ? 0.0 : mode == ContactLossMode::Backoff ? -0.003 : 0.002;
    EXPECT_NEAR(d.z(), expect, 1e-12) << int(mode);
    EXPECT_NEAR(d.x(), 0.0, 1e-12);
    EXPECT_NEAR(d.y(), 0.0, 1e-12);
    if (mode == ContactLossMode::Search) {  // speed: 0.2 mm per cycle, not the 0.5 mm step limit
      r.step();
      EXPECT_EQ(r.out.u_s(kZ), 0.0);
    }
    // Contact returns: servoing resumes.
    r.in.features = makeFeatures(r.t, 0.001, 0, 0.002, 0.001, 0, 0);
    EXPECT_EQ(r.step(), ServoStatus::Ok);
  }
}

TEST(ServoSafety, SearchSpeedPerCycle) {
  ServoParams p = singlePhase(identityPhase("p", 0.05, 0.1));
  p.safety.contact_loss = ContactLossMode::Search;
  p.safety.search_speed = 0.02;
  p.safety.search_max_distance = 0.01;
  Rig r(p);
  r.step();
  r.in.features = makeFeatures(r.t, 0, 0, 0, 0, 0, 0, ContactType::None);
  r.step(0.01);
  EXPECT_NEAR(r.out.u_s(kZ), 0.0002, 1e-15);  // 0.02 m/s * 0.01 s, along +z_s (towards the object)
}

TEST(ServoSafety, WorkspaceBoxClipsThePosition) {
  ServoParams p = singlePhase(identityPhase("p", 0.0, 0.0));
  p.phases[0].feedforward << 0, 0, 0.05, 0, 0, 0;  // along z_s = -z_g (sensor mounted flipped below)
  p.safety.workspace_min = {0.0, 0.0, 0.29};
  p.safety.workspace_max = {1.0, 1.0, 1.0};
  Rig r(p);  // flange at z = 0.3 with Rx(180): z_s points down
  ServoStatus last = ServoStatus::Ok;
  for (int k = 0; k < 50; ++k) last = r.step();
  EXPECT_EQ(last, ServoStatus::Limited);
  EXPECT_NEAR(r.out.command.pose.p[2], 0.29, 1e-15);
}

TEST(ServoSafety, RequestPhaseByName) {
  ServoParams p = singlePhase(identityPhase("first", 0.05, 0.1));
  PhaseParams b = identityPhase("second", 0.0, 0.0);
  p.phases[0].transitions.push_back(TransitionParams());
  p.phases[0].transitions[0].on = TransitionEvent::Timeout;
  p.phases[0].transitions[0].timeout_s = 100.0;
  p.phases[0].transitions[0].to = "second";
  p.phases.push_back(b);
  Rig r(p);
  r.step();
  EXPECT_EQ(std::string(r.out.phase.name.data()), "first");
  EXPECT_FALSE(r.s.requestPhase("third"));
  EXPECT_FALSE(r.s.requestPhase(nullptr));
  r.step();
  EXPECT_EQ(r.out.phase.index, 0);
  EXPECT_TRUE(r.s.requestPhase("second"));
  r.step();
  EXPECT_EQ(std::string(r.out.phase.name.data()), "second");
  EXPECT_EQ(r.out.phase.index, 1);
  EXPECT_DOUBLE_EQ(r.out.phase.t_enter_s, r.t);
  r.s.reset();
  r.step();
  EXPECT_EQ(r.out.phase.index, 0);
}

TEST(ServoSafety, TransitionsOnEvents) {
  auto phase = [](const std::string& n, TransitionEvent on, const std::string& to) {
    PhaseParams ph = identityPhase(n, 0.0, 0.0);
    ph.requires_contact = false;
    TransitionParams t;
    t.on = on;
    t.to = to;
    ph.transitions.push_back(t);
    return ph;
  };
  ServoParams p;
  p.safety.force_ceiling = 100;
  p.phases.push_back(phase("a", TransitionEvent::Contact, "b"));
  p.phases.push_back(phase("b", TransitionEvent::Edge, "c"));
  p.phases.push_back(phase("c", TransitionEvent::Aligned, "d"));
  p.phases[2].transitions[0].for_s = 0.05;  // 5 cycles of 10 ms
  p.phases[2].transitions[0].tolerance[kTolAlphaZ] = 0.01;
  p.phases[2].transitions[0].tolerance[kTolForce] = 0.5;
  p.phases.push_back(phase("d", TransitionEvent::ForceAbove, "e"));
  p.phases[3].transitions[0].force_n = 8.0;
  p.phases.push_back(phase("e", TransitionEvent::Timeout, "f"));
  p.phases[4].transitions[0].timeout_s = 0.1;
  p.phases.push_back(phase("f", TransitionEvent::ContactLost, "g"));
  p.phases[5].transitions[0].for_s = 0.03;  // 3 cycles
  p.phases.push_back(identityPhase("g", 0, 0));
  p.phases.back().terminal = true;
  Rig r(p);
  auto name = [&] { return std::string(r.out.phase.name.data()); };
  r.in.features = makeFeatures(0, 0, 0, 0, 0, 0, 0, ContactType::None);
  r.step();
  EXPECT_EQ(name(), "a");
  r.in.features = makeFeatures(0, 0, 0, 0.002, 0, 0, 0.2, ContactType::Point);
  r.step();
  EXPECT_EQ(name(), "b");
  r.in.features.contact = ContactType::Edge;
  r.step();
  EXPECT_EQ(name(), "c");
  // aligned: |Δα_z| <= 0.01 and |Δf| <= 0.5 N (s_d = 0 -> force must be <= 0.5 N) for 5 cycles.
  r.in.features = makeFeatures(0, 0, 0, 0.0002, 0, 0, 0.005, ContactType::Edge);  // 0.36 N
  for (int k = 0; k < 4; ++k) {
    r.step();
    EXPECT_EQ(name(), "c");
  }
  r.in.features.alpha_z = 0.02;  // breaks the streak
  r.step();
  r.in.features.alpha_z = 0.0;
  for (int k = 0; k < 4; ++k) r.step();
  EXPECT_EQ(name(), "c");
  r.step();
  EXPECT_EQ(name(), "d");
  r.in.features.force = 9.0;
  r.step();
  EXPECT_EQ(name(), "e");
  const double t_e = r.t;
  while (r.t + 0.01 < t_e + 0.095) {
    r.step();
    EXPECT_EQ(name(), "e");
  }
  r.step();
  r.step();
  EXPECT_EQ(name(), "f");
  r.in.features = makeFeatures(0, 0, 0, 0, 0, 0, 0, ContactType::None);
  r.step();
  r.step();
  EXPECT_EQ(name(), "f");
  EXPECT_EQ(r.step(), ServoStatus::Done);
  EXPECT_EQ(name(), "g");
}

// Zero heap allocations per step, across every path: servoing, transitions,
// holds, NaN, ceiling, contact loss, phase requests.
TEST(ServoAllocation, StepNeverAllocates) {
  for (const char* program : {"edge_exploration.yaml", "co_manipulation.yaml"}) {  // force estimate fused / tactile
  SCOPED_TRACE(program);
  ServoParams p = loadShipped(program);
  Plant plant;
  plant.infinite_edge = true;
  plant.tilt_point = true;
  plant.T_go = KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.5, 0.0, 0.2));
  p.sensor_mount = KDL::Frame::Identity();
  TactileServo s;
  ASSERT_TRUE(s.configure(p).ok());
  KDL::Frame T_ge = plant.T_go * KDL::Frame(KDL::Rotation::RotY(0.087), KDL::Vector(0, 0.002, -0.005));
  ServoInput in;
  ServoOutput out;
  std::size_t count = 0;
  bool seen[16] = {};
  {
    tactile::test::AllocationScope scope;
    for (int k = 0; k < 3000; ++k) {
      in.time_s = 0.01 * (k + 1);
      in.flange_measured = toPose(T_ge);
      in.features = plant.features(T_ge, in.time_s);
      if (k % 97 == 5) in.features.cop_x = kNaN;
      if (k % 89 == 7) in.features.time_s -= 1.0;
      if (k == 1500) in.features.force = 100.0;
      if (k == 1600) s.requestPhase("edge_control");
      // The arm's estimated wrench (the force estimate's input): the plant's
      // force along z_s, sometimes stale or NaN.
      in.have_wrench = true;
      in.wrench.time_s = (k % 83 == 11) ? in.time_s - 1.0 : in.time_s;
      const KDL::Vector F = T_ge.M.UnitZ() * (-in.features.force - 0.5);
      in.wrench.w = {F.x(), F.y(), (k % 79 == 13) ? kNaN : F.z(), 0.0, 0.0, 0.0};
      const double dt = (k % 101 == 3) ? 0.0 : 0.01;
      seen[static_cast<int>(s.step(in, dt, out)) & 15] = true;
      T_ge = toFrame(out.command.pose);
    }
    count = scope.count();
  }
  EXPECT_EQ(count, 0u);
  EXPECT_TRUE(seen[static_cast<int>(ServoStatus::InvalidInput)]);
  EXPECT_TRUE(seen[static_cast<int>(ServoStatus::Holding)]);
  EXPECT_TRUE(seen[static_cast<int>(ServoStatus::ForceCeiling)]);
  EXPECT_TRUE(seen[static_cast<int>(ServoStatus::FreeMotion)]);
  }
}

// Fuzz: 200 000 random steps over the shipped programs with random features
// (including NaN/Inf, huge values, random statuses and contact types), random
// poses (including non-unit and zero quaternions), random dt (including 0,
// negative, NaN) and random phase requests. Invariants: the command is always
// finite, every increment respects the step limits, the command is a unit quaternion.
TEST(ServoFuzz, RandomInputsNeverProduceNanOrOversizedSteps) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double specials[] = {kNaN, kInf, -kInf, 1e300, -1e300, 0.0, 1e-300};
  auto value = [&](double scale) {
    const double r = u01(rng);
    if (r < 0.03) return specials[static_cast<std::size_t>(u01(rng) * 7) % 7];
    return (2 * u01(rng) - 1) * scale;
  };
  int steps = 0;
  for (const char* file : {"edge_exploration.yaml", "co_manipulation.yaml", "bent_bar.yaml", "hold_edge.yaml"}) {
    for (PoseUpdate mode : {PoseUpdate::Integrated, PoseUpdate::Measured}) {
      ServoParams p = loadShipped(file);
      p.pose_update = mode;
      TactileServo s;
      ASSERT_TRUE(s.configure(p).ok());
      ServoInput in;
      ServoOutput out;
      double t = 0.0;
      for (int k = 0; k < 200000 / 8; ++k, ++steps) {
        const double dt = u01(rng) < 0.05 ? value(0.1) : 0.01;
        t += 0.01;
        in.time_s = u01(rng) < 0.01 ? kNaN : t;
        ContactFeatures& f = in.features;
        f.time_s = u01(rng) < 0.05 ? t - 1.0 : t;
        f.cop_x = value(0.03);
        f.cop_y = value(0.015);
        f.d_z = value(0.01);
        f.coc_x = value(0.03);
        f.coc_y = value(0.015);
        f.alpha_z = value(1.6);
        f.dzmp_x = f.cop_y - f.coc_y;
        f.dzmp_y = f.cop_x - f.coc_x;
        f.force = value(60.0);
        f.contact = static_cast<ContactType>(static_cast<int>(u01(rng) * 3) % 3);
        const FeatureStatus st[] = {FeatureStatus::Ok, FeatureStatus::NoContact, FeatureStatus::Saturated,
                                    FeatureStatus::InvalidInput, FeatureStatus::BadDimensions};
        f.status = st[static_cast<std::size_t>(u01(rng) * 5) % 5];
        if (out.valid && u01(rng) < 0.9) {
          in.flange_measured = out.command.pose;  // the robot follows
          in.flange_measured.p[0] += value(0.001);
        } else {
          for (double& v : in.flange_measured.p) v = value(1.0);
          for (double& v : in.flange_measured.q) v = value(1.0);
        }
        if (u01(rng) < 0.002) s.requestPhase(static_cast<int>(u01(rng) * 5));
        // The arm's estimated wrench (the force estimate's input, force_estimate: fused).
        in.have_wrench = u01(rng) < 0.9;
        in.wrench.time_s = u01(rng) < 0.05 ? t - 1.0 : t;
        for (int i = 0; i < 6; ++i) in.wrench.w[static_cast<std::size_t>(i)] = value(60.0);
        const Pose before = out.command.pose;
        const bool was_valid = out.valid;
        s.step(in, dt, out);
        ASSERT_TRUE(poseFinite(out.command.pose)) << file << " step " << k;
        ASSERT_TRUE(out.u_s.allFinite());
        // The speed limits over this cycle (dt counted at most max_step_dt).
        const double cyc = dt > 0 ? std::min(dt, p.safety.max_step_dt) : 0.0;
        const double max_t = p.safety.max_trans_speed * cyc, max_r = p.safety.max_rot_speed * cyc;
        ASSERT_LE(out.u_s.head<3>().norm(), max_t * (1 + 1e-12));
        ASSERT_LE(out.u_s.tail<3>().norm(), max_r * (1 + 1e-12));
        const auto& q = out.command.pose.q;
        ASSERT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-9);
        if (was_valid && mode == PoseUpdate::Integrated) {  // Eq. 15: the command moves by at most one step
          // flange displacement <= translation step + lever arm |{e}p{s}| * rotation step
          ASSERT_LE(transDist(before, out.command.pose),
                    max_t + p.sensor_mount.p.Norm() * max_r + 1e-9) << toString(out.command.status)  << " u " << out.u_s.transpose() << " dt " << dt << " phase " << out.phase.name.data() << " before " << before.p[0] << " " << before.p[1] << " " << before.p[2] << " after " << out.command.pose.p[0] << " " << out.command.pose.p[1] << " " << out.command.pose.p[2];
          ASSERT_LE(rotDist(before, out.command.pose), max_r + 1e-9);
        }
      }
    }
  }
  std::printf("[ servo    ] fuzz: %d random steps, no NaN, no oversized step\n", steps);
}

// Safe start: no command before a valid measured pose (validPose: finite, unit
// quaternion); the first command is that pose, unchanged; the phase program
// starts then, not while waiting.
TEST(ServoStart, NoCommandBeforeAValidPoseThenExactlyTheMeasuredPose) {
  ServoParams p = singlePhase(identityPhase("first", 0.05, 0.1));
  p.phases.push_back(identityPhase("second", 0.05, 0.1));
  TransitionParams t;
  t.on = TransitionEvent::Timeout;
  t.timeout_s = 0.1;
  t.to = "second";
  p.phases[0].transitions.push_back(t);
  p.safety.max_trans_speed = 0.05;
  TactileServo s;
  ASSERT_TRUE(s.configure(p).ok());
  ServoInput in;  // flange_measured = kNoPose: nothing measured yet
  ServoOutput out;
  double t_now = 0.0;
  for (int k = 0; k < 100; ++k) {  // 1 s of waiting, fresh features
    t_now += 0.01;
    in.time_s = t_now;
    in.features = makeFeatures(t_now, 0.004, -0.003, 0.002, 0.001, -0.001, 0.1);
    ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::WaitingForPose) << k;
    ASSERT_FALSE(out.valid);
    ASSERT_EQ(out.command.status, ServoStatus::WaitingForPose);
    ASSERT_EQ(out.u_s, Vec6::Zero());
  }
  EXPECT_STREQ(toString(ServoStatus::WaitingForPose), "waiting_for_pose");
  // Not a unit quaternion (|q| = 1.01) or the default pose's zero quaternion
  // with a position: invalid input, still no command.
  const Pose measured = toPose(KDL::Frame(KDL::Rotation::RPY(3.0, 0.1, -0.4), KDL::Vector(0.5, -0.1, 0.4)));
  in.flange_measured = measured;
  for (double& q : in.flange_measured.q) q *= 1.01;
  EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::InvalidInput);
  EXPECT_FALSE(out.valid);
  in.flange_measured = measured;
  in.flange_measured.q = {0, 0, 0, 0};
  EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::InvalidInput);
  EXPECT_FALSE(out.valid);
  // The first valid pose: commanded unchanged, and the program starts now.
  t_now += 0.01;
  in.time_s = t_now;
  in.features.time_s = t_now;
  in.flange_measured = measured;
  ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);
  EXPECT_TRUE(out.valid);
  EXPECT_EQ(out.command.pose.p, measured.p);
  EXPECT_LT(rotDist(out.command.pose, measured), 1e-15);
  EXPECT_EQ(out.u_s, Vec6::Zero());
  EXPECT_STREQ(out.phase.name.data(), "first");
  EXPECT_DOUBLE_EQ(out.phase.t_enter_s, t_now);
  // Servoing from there: one step at most per cycle, and the 0.1 s timeout
  // counts from the start, not from the second of waiting.
  for (int k = 0; k < 5; ++k) {
    const Pose before = out.command.pose;
    t_now += 0.01;
    in.time_s = in.features.time_s = t_now;
    in.flange_measured = out.command.pose;
    EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::Ok);
    EXPECT_LE(transDist(before, out.command.pose), 0.0005 + 1e-12);
    EXPECT_STREQ(out.phase.name.data(), "first");
  }
  // reset(): waits again, starts again from the pose measured then.
  s.reset();
  in.flange_measured = kNoPose;
  EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::WaitingForPose);
  EXPECT_FALSE(out.valid);
  in.flange_measured = measured;
  EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);
  EXPECT_EQ(out.command.pose.p, measured.p);
}

TEST(ServoStart, PhaseRequestedWhileWaitingIsEnteredAtTheStart) {
  ServoParams p = singlePhase(identityPhase("first", 0.05, 0.1));
  p.phases.push_back(identityPhase("second", 0.0, 0.0));
  TransitionParams t;
  t.on = TransitionEvent::Timeout;
  t.timeout_s = 100.0;
  t.to = "second";
  p.phases[0].transitions.push_back(t);
  TactileServo s;
  ASSERT_TRUE(s.configure(p).ok());
  ServoInput in;
  ServoOutput out;
  in.time_s = 1.0;
  EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::WaitingForPose);
  EXPECT_TRUE(s.requestPhase("second"));
  in.time_s = 2.0;
  in.flange_measured = toPose(KDL::Frame(KDL::Vector(0.4, 0.0, 0.3)));
  EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);
  EXPECT_STREQ(out.phase.name.data(), "second");
  EXPECT_DOUBLE_EQ(out.phase.t_enter_s, 2.0);
}

TEST(PoseValidity, OneRuleFiniteAndUnitQuaternion) {
  Pose p;
  EXPECT_TRUE(validPose(p));
  p.q = {0.0, 0.0, 0.0, 1.0 + 0.9e-3};
  EXPECT_TRUE(validPose(p));
  p.q = {0.0, 0.0, 0.0, 1.0 + 1.1e-3};
  EXPECT_FALSE(validPose(p));
  p.q = {0.0, 0.0, 0.0, 1.0 - 1.1e-3};
  EXPECT_FALSE(validPose(p));
  p = Pose();
  p.p[2] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(validPose(p));
  EXPECT_FALSE(validPose(kNoPose));
  EXPECT_TRUE(isNoPose(kNoPose));
  EXPECT_FALSE(isNoPose(Pose()));
}
