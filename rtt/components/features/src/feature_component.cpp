#include "tactile_features_rtt/feature_component.hpp"

#include "tactile_types_rtt/atomic_attribute.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>

#include <yaml-cpp/yaml.h>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/params_io.hpp"

namespace tactile {

FeatureComponent::FeatureComponent(const std::string& name)
    : Component(name, PreOperational),
      raw_in_("raw_frame"),
      frame_in_("frame"),
      frame_out_("calibrated_frame"),
      features_out_("features") {
  addProperty("param_file", param_file_)
      .doc("YAML parameter file with `features:` (FeatureParams) and `calibration:` (CalibrationParams) maps; "
           "read by configure() and reload().");
  addAtomicAttribute(*provides(), "last_status", last_status_);
  addAtomicAttribute(*provides(), "frames", frames_);
  addEventPort(raw_in_).doc("Raw sensor frame (12-bit counts, {s} layout): calibrated, then features extracted.");
  addEventPort(frame_in_).doc("Calibrated frame (N per taxel, {s} layout): features extracted (used when no raw frame is new).");
  addPort(frame_out_).doc("Calibrated frame computed from raw_frame (N per taxel).");
  addPort(features_out_).doc("Contact features in {s} (Sec. 3, App. B); status tells whether they are usable.");
  addOperation("tare", &FeatureComponent::tare, this, RTT::ClientThread)
      .doc("Request a tare: the next raw frame becomes the zero offset of every taxel. "
           "False when not configured.");
  addOperation("reload", &FeatureComponent::reload, this, RTT::ClientThread)
      .doc("Re-read param_file and reconfigure the cores. Refused (false) while running or when the file is invalid.");
  addOperation("lastError", &FeatureComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure() or reload().");
}

bool FeatureComponent::load() {
  FeatureParams fp;
  CalibrationParams cp;
  ConfigResult r = loadSensorParamFile(param_file_, fp, cp);
  if (r) r = stage_.configure(fp, cp);
  if (!verdict(r, last_error_)) return false;
  // Preallocate the output samples (fixed-size types: this sizes the port buffers).
  frame_ = TactileFrame();
  frame_.rows = static_cast<uint16_t>(fp.rows);
  frame_.cols = static_cast<uint16_t>(fp.cols);
  features_ = ContactFeatures();
  frame_out_.setDataSample(frame_);
  features_out_.setDataSample(features_);
  return true;
}

bool FeatureComponent::configureHook() { return load(); }

bool FeatureComponent::reload() {
  if (isRunning()) {
    last_error_ = "reload() refused while running: stop() first";
    RTT::log(RTT::Warning) << getName() << ": " << last_error_ << RTT::endlog();
    return false;
  }
  return load();
}

bool FeatureComponent::tare() {
  if (!isConfigured()) return false;
  tare_requested_.store(true);
  return true;
}

bool FeatureComponent::startHook() {
  stage_.reset();
  record(frames_, 0);
  record(last_status_, static_cast<int>(FeatureStatus::NotConfigured));
  return true;
}

void FeatureComponent::updateHook() {
  const HookScope hook(*this);  // the other hooks' writes before this update (component.hpp)
  if (raw_in_.read(raw_, false) == RTT::NewData) {
    if (tare_requested_.exchange(false)) stage_.requestTare();
    bool frame_ok = false;
    stage_.step(raw_, frame_, features_, frame_ok);
    if (frame_ok) frame_out_.write(frame_);
  } else if (frame_in_.read(frame_, false) == RTT::NewData) {
    stage_.stepCalibrated(frame_, features_);
  } else {
    return;
  }
  record(last_status_, static_cast<int>(features_.status));
  bump(frames_);
  features_out_.write(features_);
}

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::FeatureComponent)
