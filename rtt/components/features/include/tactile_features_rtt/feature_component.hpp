// tactile::FeatureComponent: thin RTT wrapper around tactile::SensorStage
// (tactile::Calibration, App. A, and tactile::FeatureExtractor, Sec. 3, App. B),
// the same stage the headless runner steps. No algorithm lives here: the
// hooks move data between ports and the stage.
//
// Interface (all documented with .doc() in the constructor):
//   property  param_file (string)  YAML file with `features:` and `calibration:`
//                                  maps (same files as the headless tools)
//   in   raw_frame (/tactile/RawTactileFrame)  raw counts -> calibration -> features
//   in   frame     (/tactile/TactileFrame)     calibrated frame -> features
//   out  calibrated_frame (/tactile/TactileFrame)  output of the calibration
//   out  features  (/tactile/ContactFeatures)
//   op   bool tare()    the next raw frame becomes the tare offset (App. A)
//   op   bool reload()  re-read param_file (only when not running)
//   attr last_status (int)  FeatureStatus of the last frame (for scripts)
//        frames (int)       frames processed since start
//
// updateHook: a new raw frame is processed first; otherwise a new calibrated
// frame. Nothing is written when no new data arrived. Per cycle: no heap
// allocation (ports are preallocated with setDataSample), no exceptions, no
// logging.
#pragma once

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include "tactile_types_rtt/component.hpp"

#include <atomic>
#include <string>

#include "tactile_features/calibration.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_features/sensor_stage.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class FeatureComponent : public Component {
 public:
  explicit FeatureComponent(const std::string& name);
  ~FeatureComponent() override { haltActivity(); }  // stops its thread while its ports exist (component.hpp)

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

  bool tare();
  bool reload();

  /// Message of the last failed configure()/reload() (empty when it succeeded).
  std::string lastError() const { return last_error_; }

 private:
  bool load();

  // properties / attributes
  std::string param_file_;
  std::string last_error_;
  // Written by the activity, read by any thread (atomic_attribute.hpp).
  std::atomic<int> last_status_{static_cast<int>(FeatureStatus::NotConfigured)};
  std::atomic<int> frames_{0};

  // ports
  RTT::InputPort<RawTactileFrame> raw_in_;
  RTT::InputPort<TactileFrame> frame_in_;
  RTT::OutputPort<TactileFrame> frame_out_;
  RTT::OutputPort<ContactFeatures> features_out_;

  // the loop's sensor stage (Calibration + FeatureExtractor) and preallocated samples
  SensorStage stage_;
  RawTactileFrame raw_;
  std::atomic<bool> tare_requested_{false};
  TactileFrame frame_;
  ContactFeatures features_;
};

}  // namespace tactile
