#include "tactile_lab/world_plant.hpp"

#include <cmath>

#include "tactile_types/kdl_pose.hpp"

namespace tactile {
namespace lab {

namespace {
/// Schedule length (s): long enough for any lab session (the WTS schedule
/// only; the world's time is not bounded by it).
constexpr double kScheduleSpanS = 1.0e7;
}  // namespace

ConfigResult WorldPlant::configure(const sim::Scene& scene) {
  configured_ = false;
  scene_ = scene;
  world_params_ = sim::worldParams(scene);
  h_ = world_params_.physics_step_s;
  ConfigResult r = world_.configure(world_params_);
  if (!r) return ConfigResult::failure(scene.file + ": " + r.message());
  if (!(r = response_.configure(sim::responseParams(scene))))
    return ConfigResult::failure(scene.file + ": sensor: " + r.message());
  if (!(r = schedule_.configure(scene.rates, kScheduleSpanS))) return ConfigResult::failure(scene.file + ": " + r.message());
  if (!(r = est_wrench_.configure(scene.wrench_error, scene.seed, scene.faults)))
    return ConfigResult::failure(scene.file + ": " + r.message());
  configured_ = true;
  reset(KDL::Frame::Identity());
  return ConfigResult::success();
}

void WorldPlant::reset(const KDL::Frame& /*initial_pose: the scene's*/) {
  if (!configured_) return;
  world_.configure(world_params_);  // validated by configure(): the scene's start again
  response_.reseed(scene_.seed);
  schedule_.reset();
  state_ = world_.state();
  initial_pose_ = state_.T_ge;
  est_wrench_.start(state_);
  est_wrench_.fill(state_, wrench_);
  acq_ = sim::SensorTruth();
  stats_ = WorldPlantStats{};
  raw_seq_ = 0;
  {
    std::lock_guard<std::mutex> lk(frame_mu_);
    have_latest_ = false;
  }
  acquireIfDue();  // tick 0: the image of the start
}

void WorldPlant::acquireIfDue() {
  // The loop's rule (core/sim/runner loop.hpp, as the runner): the acquisition of
  // tick i images the state after the step that led to it; with a transfer
  // delay the frame reaches the reader when its transfer has ended.
  const double t = schedule_.time();
  if (response_.faults().streams()) {  // the link's faults by time, for the device thread
    link_down_.store(response_.faults().linkDown(t));
    stalled_.store(response_.faults().stalled(t));
  }
  bool got = false;
  if (schedule_.fires().wts) {
    world_.acquireForces(forces_, acq_);
    ++stats_.acquisitions;
    got = response_.acquire(forces_, t, raw_);
  }
  if (!got && response_.delayed()) got = response_.deliver(t, raw_);
  if (!got) return;
  raw_.seq = raw_seq_++;
  raw_.device_time_ms = static_cast<uint32_t>(std::llround(raw_.time_s * 1000.0));
  ++stats_.frames;
  std::lock_guard<std::mutex> lk(frame_mu_);
  latest_ = raw_;
  have_latest_ = true;
}

void WorldPlant::fill(fri::PlantState& out) {
  for (int j = 0; j < fri::kNumJoints; ++j) out.q[static_cast<std::size_t>(j)] = state_.q(j);
  out.pose = state_.T_ge;
  est_wrench_.fill(state_, wrench_);  // estExtTcpFT: the simulated arm's estimated_wrench
  out.wrench = wrench_.w;
}

void WorldPlant::step(const KDL::Frame& commanded, double dt, fri::PlantState& out) {
  if (!configured_) return;
  if (dt > 0.0 && std::isfinite(dt)) {
    const long n = std::max(1L, std::lround(dt / h_));
    const Pose cmd = toPose(commanded);
    for (long i = 0; i < n; ++i) {
      const sim::SimStatus st = world_.step(cmd, h_, state_);
      ++stats_.physics_steps;
      if (st == sim::SimStatus::NotConverged) ++stats_.not_converged;
      if (st == sim::SimStatus::InvalidCommand) ++stats_.invalid_commands;
      if (sim::fatal(st)) {
        if (stats_.fatal_steps++ == 0) {
          stats_.first_fatal = st;
          stats_.first_fatal_t = state_.time_s;
        }
      }
      schedule_.advance();
      acquireIfDue();
    }
  }
  fill(out);
}

KDL::Frame WorldPlant::holdPose(const fri::PlantState& /*measured*/) const {
  return toFrame(world_.state().command_g);  // the set point the arm holds (the last valid command)
}

bool WorldPlant::latestFrame(RawTactileFrame& out) const {
  std::lock_guard<std::mutex> lk(frame_mu_);
  if (!have_latest_) return false;
  out = latest_;
  return true;
}

}  // namespace lab
}  // namespace tactile
