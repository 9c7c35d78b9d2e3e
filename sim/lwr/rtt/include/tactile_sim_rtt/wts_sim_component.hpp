// tactile::WtsSimComponent: the simulated SENSOR (the WTS0614's electronics):
// thin RTT wrapper around tactile::sim::TaxelResponse. It turns the simulated
// arm's true taxel forces into raw 12-bit counts on `raw_frame`, the port of
// the real reader (tactile::WtsComponent), by inverting the calibration the
// reader uses (the scene's features_file, components/features/params/wts0614.yaml's
// `calibration:` block), with the scene's noise (seeded by the scene's seed),
// firing threshold, 12-bit quantisation and saturation.
//
// Interface (documented with .doc() in the constructor):
//   property scene_file (string)   scene YAML: features_file (calibration), sensor.noise_counts,
//                                  sensor.threshold, seed, effects (the sensor's keys)
//   in   taxel_forces (/tactile/TactileFrame)  SIM ONLY, from tactile::LwrSimComponent (event port)
//   out  raw_frame (/tactile/RawTactileFrame)  counts, stamped with RTT's TimeService (s)
//   attr frames (int)   frames written since start
//   op   string lastError()
//
// Each update with a new force image: acquire -> raw_frame (seq counts from
// 0 at start); with the scene's effects.wts_transfer_delay_s the frame is
// written when its transfer ends (tactile::SimClock then updates the sensor
// every tick). start() reseeds the noise and clears the sensor's state. No
// heap allocation per cycle.
#pragma once

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include <string>

#include "tactile_sim/taxel_response.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class WtsSimComponent : public RTT::TaskContext {
 public:
  explicit WtsSimComponent(const std::string& name);

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

  std::string lastError() const { return last_error_; }

 private:
  std::string scene_file_;
  std::string last_error_;
  int frames_ = 0;

  RTT::InputPort<TactileFrame> forces_in_;
  RTT::OutputPort<RawTactileFrame> raw_out_;

  sim::TaxelResponse response_;
  TactileFrame forces_;
  RawTactileFrame raw_;
  uint32_t seq_ = 0;
};

}  // namespace tactile
