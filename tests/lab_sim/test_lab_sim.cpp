// lab_sim's core without the wall clock: the world as the simulated KRC's
// plant (tactile::lab::WorldPlant), the KRC script as SimKrc's schedule, and
// the SimKrc additions it needs (a closed interface, advertised sample times,
// the plant's own set point outside CMD), the last ones over UDP on loopback
// in SimKrc's fast mode (ephemeral ports).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tactile_fri/krc_model.hpp"
#include "tactile_fri/protocol.hpp"
#include "tactile_fri/sim_krc.hpp"
#include "tactile_fri/udp.hpp"
#include "tactile_lab/krc_schedule.hpp"
#include "tactile_lab/world_plant.hpp"
#include "tactile_config/registry.hpp"
#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_runner/scene.hpp"
#include "tactile_types/kdl_pose.hpp"

using namespace tactile;

namespace {

const std::string kSource = TACTILE_SOURCE_DIR;
const std::string kPressScene = kSource + "/params/lab_scenes/bringup_press.yaml";
const std::string kEdgeScene = kSource + "/params/scenes/edge_exploration.yaml";

// The scene with the program the registry binds to it (lab_sim's default).
sim::Scene loadOrFail(const std::string& file) {
  sim::Scene s;
  sim::RunFiles files{file, "", ""};
  ConfigResult r = config::programForScene(kSource + "/experiments.yaml", file, files.program);
  if (r) r = sim::loadRun(files, s);
  EXPECT_TRUE(r.ok()) << r.message();
  return s;
}

double trueForce(const sim::SimState& s) { return -s.wrench_s[2]; }

}  // namespace

// The scene starts pressed: the sensor carries a load, and the set point the
// arm holds (holdPose) is not where the flange stands: the impedance's
// deflection F / K along z_g (contact pushes the flange up, Eq. 11).
TEST(WorldPlant, PressSceneStartsPressedWithTheSetPointBelowTheFlange) {
  const sim::Scene scene = loadOrFail(kPressScene);
  lab::WorldPlant plant;
  ASSERT_TRUE(plant.configure(scene).ok());
  fri::PlantState ps;
  plant.step(plant.initialPose(), 0.0, ps);  // dt 0: the state, no step
  EXPECT_EQ(plant.stats().physics_steps, 0u);
  const double f = trueForce(plant.state());
  EXPECT_GT(f, 1.0);  // "lightly pressed": the scene is sized for ~1.8 N
  EXPECT_LT(f, 3.0);
  const KDL::Frame hold = plant.holdPose(ps);
  const double k = scene.world.arm.k_trans;
  // Quasi-static equilibrium K (x_d - x) + F = 0; tolerance 0.05 mm: the
  // contact's moment couples a little rotation into the translation.
  EXPECT_NEAR(ps.pose.p.z() - hold.p.z(), f / k, 5e-5);
  EXPECT_NEAR(ps.pose.p.x(), hold.p.x(), 5e-5);
}

// Outside CMD the KRC steps the plant toward holdPose(): the arm does not
// move and stays pressed. The control: stepping toward the measured pose
// (a plant without its own set point, FirstOrderPlant's hold) lets the arm
// back off and the force drop, so this test sees the difference.
TEST(WorldPlant, HoldingItsSetPointKeepsThePadPressed) {
  const sim::Scene scene = loadOrFail(kPressScene);
  lab::WorldPlant plant;
  ASSERT_TRUE(plant.configure(scene).ok());
  fri::PlantState ps;
  plant.step(plant.initialPose(), 0.0, ps);
  const KDL::Vector p0 = ps.pose.p;
  const double f0 = trueForce(plant.state());
  for (int i = 0; i < 1000; ++i) plant.step(plant.holdPose(ps), 0.001, ps);
  // 5 um: the dynamic world starts at the quasi-static balance of its command
  // (start_in_equilibrium) and settles 1.1 um from it within 0.3 s.
  EXPECT_LT((ps.pose.p - p0).Norm(), 5e-6);
  EXPECT_NEAR(trueForce(plant.state()), f0, 1e-3);      // 1 mN

  lab::WorldPlant relax;
  ASSERT_TRUE(relax.configure(scene).ok());
  fri::PlantState rs;
  relax.step(relax.initialPose(), 0.0, rs);
  for (int i = 0; i < 1000; ++i) relax.step(rs.pose, 0.001, rs);  // the measured pose as the set point
  EXPECT_GT((rs.pose.p - p0).Norm(), 5e-4);               // backed off by more than 0.5 mm
  EXPECT_LT(trueForce(relax.state()), 0.5 * f0);
}

// The wrench in the KRC's packet (estExtTcpFT) is the simulated arm's
// estimated_wrench: sim::EstimatedWrench of the scene (edge exploration:
// bias and noise), the same value for the same state.
TEST(WorldPlant, ReportsTheSimulatedArmsEstimatedWrench) {
  const sim::Scene scene = loadOrFail(kPressScene);
  lab::WorldPlant plant;
  ASSERT_TRUE(plant.configure(scene).ok());
  fri::PlantState ps;
  plant.step(plant.holdPose(ps), 0.001, ps);
  sim::EstimatedWrench ref;
  ref.configure(scene.wrench_error, scene.seed);
  sim::SimState s0;
  ref.start(s0);  // no wrench error in this scene: the start does not matter
  Wrench w;
  ref.fill(plant.state(), w);
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(ps.wrench[static_cast<std::size_t>(i)], w.w[static_cast<std::size_t>(i)]) << i;
  EXPECT_NEAR(ps.wrench[2], trueForce(plant.state()), 1e-9);  // the pad pushes the flange up (+z_g)

  const sim::Scene edge = loadOrFail(kEdgeScene);
  ASSERT_TRUE(edge.wrench_error.any());
  lab::WorldPlant ep;
  ASSERT_TRUE(ep.configure(edge).ok());
  fri::PlantState es;
  for (int i = 0; i < 5; ++i) ep.step(ep.holdPose(es), 0.001, es);
  sim::EstimatedWrench eref;
  eref.configure(edge.wrench_error, edge.seed);
  sim::SimState start;
  start.T_ge = ep.initialPose();
  eref.start(start);
  eref.fill(ep.state(), w);
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(es.wrench[static_cast<std::size_t>(i)], w.w[static_cast<std::size_t>(i)]) << i;
  EXPECT_NEAR(es.wrench[2], edge.wrench_error.bias_n[2], 4 * 0.5 + 1e-9);  // free: the bias, 0.5 N noise (4 sigma)
}

// A KRC cycle of two world steps steps the world twice; the WTS frames come
// at the scene's rate on the physics ticks (140 Hz: 140 in 1 s, plus the
// tick-0 image) and carry the press: taxels fire on the bar's row only.
TEST(WorldPlant, StepsWholePhysicsStepsAndHandsOverFramesAtTheWtsRate) {
  const sim::Scene scene = loadOrFail(kPressScene);
  lab::WorldPlant plant;
  ASSERT_TRUE(plant.configure(scene).ok());
  RawTactileFrame f;
  ASSERT_TRUE(plant.latestFrame(f));  // the tick-0 acquisition
  fri::PlantState ps;
  for (int i = 0; i < 500; ++i) plant.step(plant.holdPose(ps), 0.002, ps);
  EXPECT_EQ(plant.stats().physics_steps, 1000u);
  EXPECT_NEAR(plant.state().time_s, 1.0, 1e-9);
  EXPECT_EQ(plant.stats().acquisitions, 141u);
  EXPECT_EQ(plant.stats().frames, 141u);
  ASSERT_TRUE(plant.latestFrame(f));
  EXPECT_EQ(f.seq, 140u);
  EXPECT_EQ(f.rows, scene.features.rows);
  EXPECT_EQ(f.cols, scene.features.cols);
  int firing = 0;
  for (int r = 0; r < f.rows; ++r)
    for (int c = 0; c < f.cols; ++c)
      if (f.counts[static_cast<std::size_t>(r * f.cols + c)] > 0) {
        ++firing;
        EXPECT_EQ(r, 3) << "taxel (" << r << ", " << c << ") fires off the bar's row";
      }
  EXPECT_GE(firing, 3);
}

// The KRC script in KRL's words as SimKrc's cycle schedule.
TEST(KrcSchedule, ScriptToCycles) {
  fri::KrcScript script;
  ASSERT_TRUE(script
                  .parse("0:friOpen,1.0:friStart,6.0:quality=BAD,6.3:quality=PERFECT,8.0:friStop,8.5:friStart,"
                         "9:power=off,9.5:friClose",
                         "--krc")
                  .ok());
  fri::StateEvent initial;
  std::vector<fri::StateEvent> sched;
  std::vector<lab::ScheduledWord> words;
  lab::scheduleFromScript(script, 0.002, initial, sched, words);
  EXPECT_TRUE(initial.open);
  EXPECT_EQ(initial.state, fri::State::Mon);
  ASSERT_EQ(words.size(), 8u);
  EXPECT_EQ(words[1].word, "friStart");
  EXPECT_EQ(words[1].cycle, 500u);
  EXPECT_EQ(words[2].word, "quality=BAD");
  ASSERT_EQ(sched.size(), 8u);
  EXPECT_EQ(sched[1].cycle, 500u);
  EXPECT_EQ(sched[1].state, fri::State::Cmd);
  EXPECT_EQ(sched[2].cycle, 3000u);
  EXPECT_EQ(sched[2].quality, fri::Quality::Bad);
  EXPECT_EQ(sched[2].state, fri::State::Cmd);
  EXPECT_EQ(sched[3].quality, fri::Quality::Perfect);
  EXPECT_EQ(sched[4].state, fri::State::Mon);
  EXPECT_EQ(sched[5].state, fri::State::Cmd);
  EXPECT_EQ(sched[6].power, 0u);
  EXPECT_TRUE(sched[6].open);
  EXPECT_FALSE(sched[7].open);
  EXPECT_EQ(sched[7].state, fri::State::Off);

  fri::KrcScript empty;
  ASSERT_TRUE(empty.parse("", "--krc").ok());
  lab::scheduleFromScript(empty, 0.001, initial, sched, words);
  EXPECT_TRUE(initial.open);  // command mode from the start
  EXPECT_EQ(initial.state, fri::State::Cmd);
  EXPECT_TRUE(sched.empty());

  fri::KrcScript late;
  ASSERT_TRUE(late.parse("2:friOpen,2:friStart", "--krc").ok());
  lab::scheduleFromScript(late, 0.001, initial, sched, words);
  EXPECT_FALSE(initial.open);  // silent before friOpen
  ASSERT_EQ(sched.size(), 1u);  // both events of cycle 2000: the later state
  EXPECT_EQ(sched[0].cycle, 2000u);
  EXPECT_EQ(sched[0].state, fri::State::Cmd);
  EXPECT_EQ(words.size(), 2u);
}

namespace {
/// A socket on 127.0.0.1 that the simulated KRC sends to; never replies.
struct Listener {
  fri::UdpSocket sock;
  Listener() {
    fri::UdpParams up;
    up.bind_address = "127.0.0.1";
    up.port = 0;
    EXPECT_TRUE(sock.open(up).ok());
  }
  int drain(fri::MsrPacket* last = nullptr) {
    std::array<uint8_t, 2048> buf{};
    int n = 0;
    std::size_t size = 0;
    while (sock.receive(buf.data(), buf.size(), size, 0) == fri::UdpStatus::Ok) {
      ++n;
      if (last != nullptr) {
        EXPECT_EQ(fri::decodeMeasurement(buf.data(), size, *last), fri::PacketStatus::Ok);
      }
    }
    return n;
  }
};
}  // namespace

// A closed interface sends nothing and counts its cycles; the advertised
// sample times are the ones configured, not the period; outside CMD the
// world plant holds its set point, which the KRC reports as cmdCartPos.
TEST(SimKrcForLab, ClosedInterfaceAdvertisedSampleTimesAndHeldSetPoint) {
  const sim::Scene scene = loadOrFail(kPressScene);
  lab::WorldPlant plant;
  ASSERT_TRUE(plant.configure(scene).ok());
  Listener remote;
  fri::SimKrcParams p;
  p.remote_port = remote.sock.localPort();
  p.period_s = 0.002;
  p.real_time = false;
  p.reply_timeout_s = 0.0;  // nobody answers: do not wait
  p.msr_sample_time_s = 0.005;
  p.cmd_sample_time_s = 0.004;
  p.initial_pose = plant.initialPose();
  p.initial.open = false;
  p.initial.state = fri::State::Off;
  fri::StateEvent open;
  open.cycle = 10;
  open.state = fri::State::Mon;
  p.schedule.push_back(open);
  fri::SimKrc krc;
  ASSERT_TRUE(krc.configure(p, plant).ok());
  const double f0 = trueForce(plant.state());
  krc.run(10);
  EXPECT_EQ(krc.stats().closed_cycles, 10u);
  EXPECT_EQ(krc.stats().sent, 0u);
  EXPECT_EQ(remote.drain(), 0);
  EXPECT_FALSE(krc.open());
  krc.run(5);
  EXPECT_TRUE(krc.open());
  EXPECT_EQ(krc.stats().sent, 5u);
  EXPECT_EQ(krc.stats().closed_cycles, 10u);
  EXPECT_EQ(plant.stats().physics_steps, 30u);  // 15 cycles of two world steps, closed or not
  fri::MsrPacket m;
  for (int i = 0; i < 200 && remote.drain(&m) == 0; ++i) {
  }
  EXPECT_FLOAT_EQ(m.intf.desired_msr_sample_time, 0.005f);
  EXPECT_FLOAT_EQ(m.intf.desired_cmd_sample_time, 0.004f);
  EXPECT_EQ(m.intf.state, static_cast<uint16_t>(fri::State::Mon));
  KDL::Frame cmd, msr;
  fri::toFrame(m.data.cmd_cart_pos, cmd);
  fri::toFrame(m.data.msr_cart_pos, msr);
  const KDL::Frame hold = toFrame(plant.state().command_g);
  EXPECT_LT((cmd.p - hold.p).Norm(), 1e-6);  // float on the wire
  EXPECT_GT((msr.p - cmd.p).Norm(), 1e-3);   // pressed: the flange 1.8 mm above its set point
  EXPECT_NEAR(trueForce(plant.state()), f0, 1e-3);  // still pressed after 15 cycles outside CMD (1 mN)
}
