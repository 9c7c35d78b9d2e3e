// tactile::WtsComponent: thin RTT wrapper around tactile::wts::WtsDriver (the
// Weiss WTS0614 serial protocol, reconnection). Output `raw_frame`, the same
// port the LWR simulator offers, so a deployment swaps one loadComponent line.
//
// Interface (documented with .doc() in the constructor):
//   property param_file (string)   optional YAML with a `wts:` map (tactile_wts/params_io.hpp); empty = defaults
//   property device (string)       optional override of the serial device path
//   property poll_timeout (double) s, (0, 1]: longest wait for bytes per updateHook
//   out  raw_frame (/tactile/RawTactileFrame)  each new frame, stamped with RTT's TimeService
//   attr read_status (int)   wts::ReadStatus of the last poll (0 new frame, 1 no data, 5 disconnected...)
//   attr frames (int)        frames written since start
//   op   string lastError(), string statusName()
//
// Execution: preferably a NON-periodic activity; the device paces it (periodic
// mode): each updateHook polls the driver once (bounded by poll_timeout), writes
// a new frame, and trigger()s itself (while unplugged it waits poll_timeout
// between reconnection checks instead of spinning). With a periodic activity
// each period polls once without waiting. start() opens the port and starts the
// acquisition (not real-time); stop() closes it. With a SlaveActivity (tests)
// each update() polls once. Per cycle: no heap allocation, no exceptions, no logging.
#pragma once

#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include <atomic>
#include <string>

#include "tactile_types/types.hpp"
#include "tactile_wts/driver.hpp"

namespace tactile {

class WtsComponent : public RTT::TaskContext {
 public:
  explicit WtsComponent(const std::string& name);

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void stopHook() override;

  std::string lastError() const { return last_error_; }
  std::string statusName() const;

 private:
  std::string param_file_;
  std::string device_;
  double poll_timeout_ = 0.05;
  std::string last_error_;
  int read_status_ = static_cast<int>(wts::ReadStatus::NotConfigured);
  std::atomic<int> status_shadow_{static_cast<int>(wts::ReadStatus::NotConfigured)};
  int frames_ = 0;

  RTT::OutputPort<RawTactileFrame> raw_out_;

  wts::WtsDriver driver_;
  RawTactileFrame raw_;
};

}  // namespace tactile
