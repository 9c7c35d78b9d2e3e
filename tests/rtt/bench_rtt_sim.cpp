// Cost of the RTT layer around the simulator: one LwrSimComponent cycle (write
// pose_command, update(), read flange_pose; force images at 140 Hz of simulated
// time) against the same World::step + World::acquireForces calls made directly, in the same
// run, on the same command sequence (edge exploration scene, sensor pressed on
// the bar, the command sliding 0.1 mm back and forth so the quasi-static solve
// runs every step).
#include <benchmark/benchmark.h>

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>

#include <cmath>
#include <string>

#include "tactile_sim_runner/scene.hpp"
#include "tactile_sim_lwr/world.hpp"
#include "tactile_sim_rtt/lwr_sim_component.hpp"
#include "rtt_benchmark_main.hpp"

namespace {

const std::string kScene = TACTILE_SCENE_DIR "/edge_exploration.yaml";
const std::string kProgram = TACTILE_SCENE_DIR "/../programs/edge_exploration.yaml";  // the registry's for kScene

// Flange command k: pressed 3 mm into the bar below the start pose (the bar is
// about 27 mm below the sensor), sliding +-0.1 mm along x with a 200-step period.
tactile::Pose command(const tactile::Pose& start, long k) {
  tactile::Pose p = start;
  p.p[2] -= 0.030;
  p.p[0] += 1e-4 * std::sin(2.0 * 3.141592653589793 * static_cast<double>(k % 200) / 200.0);
  return p;
}

void BM_WorldDirect(benchmark::State& state) {
  tactile::sim::Scene scene;
  if (!tactile::sim::loadRun({kScene, kProgram, ""}, scene).ok()) {
    state.SkipWithError("scene");
    return;
  }
  tactile::sim::WorldParams wp = scene.world;
  wp.seed = scene.seed;
  tactile::sim::World world;
  if (!world.configure(wp).ok()) {
    state.SkipWithError("configure");
    return;
  }
  const double dt = 1.0 / scene.rates.sim, wts = 1.0 / 140.0;
  tactile::sim::SimState st = world.state();
  const tactile::Pose start = st.flange_g;
  tactile::sim::SensorTruth truth;
  tactile::TactileFrame frame;
  double next = 0.0;
  long k = 0;
  for (auto _ : state) {
    world.step(command(start, k++), dt, st);
    if (st.time_s + 0.25 * dt >= next) {
      next += wts;
      world.acquireForces(frame, truth);
    }
    benchmark::DoNotOptimize(st);
    benchmark::DoNotOptimize(frame);
  }
  state.counters["contact_N"] = st.normal_force;
}
BENCHMARK(BM_WorldDirect);

void BM_LwrSimComponentCycle(benchmark::State& state) {
  tactile::LwrSimComponent comp("sim");
  comp.setActivity(new RTT::extras::SlaveActivity(0.001));
  comp.properties()->getPropertyType<std::string>("scene_file")->set(kScene);
  comp.properties()->getPropertyType<std::string>("program_file")->set(kProgram);
  RTT::OutputPort<tactile::PoseCommand> cmd_out("cmd_out");
  RTT::InputPort<tactile::Pose> pose_in("pose_in");
  RTT::InputPort<tactile::TactileFrame> frame_in("frame_in");
  cmd_out.connectTo(comp.ports()->getPort("pose_command"));
  comp.ports()->getPort("flange_pose")->connectTo(&pose_in);
  comp.ports()->getPort("taxel_forces")->connectTo(&frame_in);
  if (!comp.configure() || !comp.start()) {
    state.SkipWithError("configure/start");
    return;
  }
  const tactile::Pose start = comp.world().state().flange_g;
  tactile::PoseCommand pc;
  cmd_out.setDataSample(pc);
  tactile::Pose pose;
  tactile::TactileFrame frame;
  long k = 0;
  for (auto _ : state) {
    pc.pose = command(start, k++);
    cmd_out.write(pc);
    comp.update();
    pose_in.read(pose, false);
    frame_in.read(frame, false);
    benchmark::DoNotOptimize(pose);
  }
  state.counters["contact_N"] = comp.world().state().normal_force;
  comp.stop();
}
BENCHMARK(BM_LwrSimComponentCycle);

}  // namespace

int main(int argc, char** argv) { return tactile::test::rttBenchmarkMain(argc, argv); }
