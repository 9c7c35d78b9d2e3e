// The simulated world as the robot behind a simulated KRC, and as the source
// of the simulated WTS0614's frames: lab_sim's core (docs/lab_sim.md).
//
// WorldPlant implements tactile::fri::Plant over tactile::sim::World (the LWR
// 4+ under the KRC's Cartesian impedance, Eq. 11, the scene's objects, the
// elastic pad, Eq. 2), so that tactile::fri::SimKrc (UDP, pacing, the KRC
// model) drives the same world the headless runner and the simulated arm
// component step:
//
//   step(commanded {g}T{e}, dt):  dt / physics_step world steps toward the
//     commanded pose (dt a whole number of physics steps: the KRC's cycle is
//     a whole number of the robot's 1 ms control cycles); after each, on the
//     scene's WTS schedule (sim::Schedule, the loop's rule: rates.wts, on the
//     physics tick), World::acquireForces -> sim::TaxelResponse (the sensor's
//     electronics, the scene's calibration file inverted, noise, effects,
//     transfer delay) -> the latest raw frame, handed over to the WTS device
//     thread (latestFrame(), under a mutex: the world itself is touched by
//     the KRC's thread only);
//   out: measured joints q, flange pose {g}T{e}, and the external wrench the
//     KRC's estExtTcpFT reports: sim::EstimatedWrench, the rule the runner
//     and the simulated arm component publish as `estimated_wrench` (contact
//     wrench at the flange origin, {g} axes, with the scene's
//     effects.wrench_error), so that the FRI bridge's estimated_wrench port
//     carries what the simulated arm's does;
//   the scene's pad faults (`faults:`) act in the sensor's electronics and
//     on its frames (TaxelResponse); the link's (disconnect, stale) are also
//     reported by time (sensorLinkDown(), sensorStalled()) for the device
//     thread: lab_sim unplugs or holds the PTY device for their windows;
//   holdPose(): the world's last command. While the KRC applies no command
//     (MON, drives off, closed, CMD before the first command) the robot holds
//     the set point it had: a pad pressed on an object at the start stays
//     pressed (the measured pose differs from the set point by the contact
//     force over the stiffness).
//
// Test equipment (lab_sim): configure() and reset() allocate; step() does not
// allocate but takes a mutex per acquisition. Not part of a production library.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>

#include <kdl/frames.hpp>

#include "tactile_fri/sim_krc.hpp"
#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_runner/scene.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"
#include "tactile_sim_lwr/world.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace lab {

/// What the world did since reset() (read in the KRC's thread).
struct WorldPlantStats {
  uint64_t physics_steps = 0;
  uint64_t acquisitions = 0;        ///< WTS acquisitions (the scene's rate)
  uint64_t frames = 0;              ///< raw frames handed over (acquisitions, or deliveries after a transfer delay)
  uint64_t not_converged = 0;       ///< quasi-static steps at their iteration cap
  uint64_t invalid_commands = 0;    ///< steps whose command the world refused (the last valid one held)
  uint64_t fatal_steps = 0;         ///< steps with a fatal status (joint limit, singularity, force ceiling, NaN)
  sim::SimStatus first_fatal = sim::SimStatus::Ok;
  double first_fatal_t = 0.0;       ///< world time of first_fatal (s)
};

class WorldPlant : public fri::Plant {
 public:
  /// The world (sim::worldParams(scene): the scene's seed and physics step
  /// 1 / rates.sim), the sensor's electronics (sim::responseParams(scene)),
  /// the estimated wrench's error (effects.wrench_error) and the WTS schedule
  /// (rates.wts). Errors name the scene file and the key. Then reset().
  ConfigResult configure(const sim::Scene& scene);

  /// Back to the scene's start: the world configured again (its initial
  /// flange pose, objects, tray), the sensor reseeded, the tick-0 acquisition
  /// made. The argument is ignored: the start is the scene's initial_flange
  /// (initialPose()).
  void reset(const KDL::Frame& initial_pose) override;
  /// dt (s) must be a whole number of physics steps (to 1e-9 relative);
  /// dt <= 0 fills `out` from the current state without stepping.
  void step(const KDL::Frame& commanded, double dt, fri::PlantState& out) override;
  KDL::Frame holdPose(const fri::PlantState& measured) const override;

  /// The newest raw frame (its rows x cols those of the scene's features),
  /// for the WTS device's thread. False (and `out` untouched) before the
  /// first frame. Thread-safe.
  bool latestFrame(RawTactileFrame& out) const;

  /// The sensor's link faults at the world's time (the scene's `faults:`,
  /// tactile_sim_faults/sensor_faults.hpp): inside a disconnect's window (lab_sim
  /// unplugs the WTS device for it) or a stale window (the device sends no
  /// frame). Thread-safe.
  bool sensorLinkDown() const { return link_down_.load(); }
  bool sensorStalled() const { return stalled_.load(); }

  /// The world's measured start pose {g}T{e} (SimKrcParams::initial_pose).
  KDL::Frame initialPose() const { return initial_pose_; }
  double physicsStep() const { return h_; }
  /// KRC's thread only:
  const sim::SimState& state() const { return state_; }
  const sim::SensorTruth& lastAcquisition() const { return acq_; }
  /// The estimated wrench reported with the last step (what estExtTcpFT carries).
  const Wrench& estimatedWrench() const { return wrench_; }
  const WorldPlantStats& stats() const { return stats_; }

 private:
  void acquireIfDue();
  void fill(fri::PlantState& out);

  sim::Scene scene_;
  sim::WorldParams world_params_;
  sim::World world_;
  sim::TaxelResponse response_;
  sim::EstimatedWrench est_wrench_;
  sim::Schedule schedule_;
  double h_ = 0.001;
  KDL::Frame initial_pose_ = KDL::Frame::Identity();
  sim::SimState state_;
  sim::SensorTruth acq_;
  TactileFrame forces_;
  RawTactileFrame raw_;
  Wrench wrench_;
  uint32_t raw_seq_ = 0;
  WorldPlantStats stats_;
  bool configured_ = false;

  std::atomic<bool> link_down_{false}, stalled_{false};
  mutable std::mutex frame_mu_;  // guards latest_, have_latest_ (the WTS device's thread reads them)
  RawTactileFrame latest_;
  bool have_latest_ = false;
};

}  // namespace lab
}  // namespace tactile
