// tactile::WtsSimComponent: the simulated SENSOR (the WTS0614's electronics):
// thin RTT wrapper around tactile::sim::TaxelResponse. It turns the simulated
// arm's true taxel forces into raw 12-bit counts on `raw_frame`, the port of
// the real reader (tactile::WtsComponent), by inverting the calibration the
// reader uses (the scene's features_file, params/sensors/wts0614.yaml's
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
// Fault injection (off by default, nothing done when off: the schedule of
// tactile::sim::TaxelResponse, tactile_sim_faults/sensor_faults.hpp): the scene's
// `faults:` list (the pad's: stuck, dead, tare_creep, calibration,
// saturated, stale, repeat, disconnect), and one more fault by property
// (tests only):
//   property fault (string)          '' | stale | disconnect | nan | saturated
//   property fault_start (double)    s, simulated time of the fault
//   property fault_duration (double) s, the window of stale and disconnect
//   out  fault_frame (/tactile/TactileFrame)  the nan fault's frame (calibrated, N, one NaN taxel),
//                                             for FeatureComponent's `frame` input
//   attr link_status (int)   tactile::sim::SensorLink (the reader's read_status names: 0 NewFrame,
//                            5 Disconnected, 4 Reconnected); op string statusName()
//   attr fault_seq (int)     seq of the frame the fault hit (nan, saturated) or of the first frame
//                            after its window (stale, disconnect); -1 before
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

#include "tactile_types_rtt/component.hpp"

#include <atomic>
#include <string>

#include "tactile_sim_faults/sensor_faults.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class WtsSimComponent : public Component {
 public:
  explicit WtsSimComponent(const std::string& name);
  ~WtsSimComponent() override { haltActivity(); }  // stops its thread while its ports exist (component.hpp)

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

  std::string lastError() const { return last_error_; }
  std::string statusName() const { return sim::toString(static_cast<sim::SensorLink>(link_status_.load())); }

 private:
  /// The fault schedule's record after an acquisition or a delivery (`delivered`: a frame goes out).
  void noteFault(bool delivered);

  std::string scene_file_;
  std::string fault_;
  double fault_start_ = 0.0;
  double fault_duration_ = 0.0;
  std::atomic<int> link_status_{0};  // the record, read by any thread (atomic_attribute.hpp)
  std::atomic<int> fault_seq_{-1};
  bool withheld_ = false;
  std::string last_error_;
  std::atomic<int> frames_{0};

  RTT::InputPort<TactileFrame> forces_in_;
  RTT::OutputPort<RawTactileFrame> raw_out_;
  RTT::OutputPort<TactileFrame> fault_frame_out_;

  sim::TaxelResponse response_;
  int shots_ = 0;  // the schedule's one-shot hits recorded in fault_seq
  TactileFrame nan_frame_;
  TactileFrame forces_;
  RawTactileFrame raw_;
  uint32_t seq_ = 0;
};

}  // namespace tactile
