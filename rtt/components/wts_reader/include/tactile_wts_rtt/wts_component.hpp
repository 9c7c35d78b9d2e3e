// tactile::WtsComponent: thin RTT wrapper around tactile::wts::WtsDriver (the
// Weiss WTS0614 serial protocol, reconnection). Output `raw_frame`, the same
// port the LWR simulator offers, so a deployment swaps one loadComponent line.
//
// Interface (documented with .doc() in the constructor):
//   property param_file (string)   optional YAML with a `wts:` map (tactile_wts/params_io.hpp); empty = defaults
//   property device (string)       optional override of the serial device path
//   property poll_timeout (double) s, (0, 1]: the FileDescriptorActivity's timeout (longest
//                                  time without a byte before the hook runs anyway)
//   property stop_timeout (double) s, [1, 60], default 5: the longest wait of stop() for the
//                                  FileDescriptorActivity's thread (its select() on a tty can wait
//                                  in the kernel for the tty's worker thread)
//   out  raw_frame (/tactile/RawTactileFrame)  each new frame; time_s is when the device took it, on RTT's
//                                  TimeService: its arrival minus its delay (tactile_wts/device_clock.hpp)
//   attr read_status (int)   wts::ReadStatus of the last poll (0 new frame, 1 no data, 5 disconnected...)
//   attr frames (int)        frames written since start
//   attr timeouts (int)      FileDescriptorActivity wake-ups by poll_timeout (no byte for poll_timeout s)
//   attr fd_activity (bool)  the activity is a FileDescriptorActivity (set by configure/start)
//   attr frame_delay (double), frame_delay_max (double)  s: the last frame's delay in the link and the
//                            tty (arrival minus when taken, from the device's clock), and the largest
//   op   string lastError(), string statusName()
//
// Execution: no hook waits. Each updateHook polls the driver once with a zero
// timeout (reads what is there, decodes, reconnects when due by the time it is
// given: RTT's TimeService) and writes a new frame.
//  * RTT::extras::FileDescriptorActivity (the deployments): paced by the
//    device. start() watches the serial port's descriptor and sets the
//    activity's timeout to poll_timeout; the hook runs when bytes are readable
//    or after poll_timeout without any (read_status NoData, `timeouts` counted).
//    Unplugged, the port is closed and unwatched: the timeout wakes the hook
//    every poll_timeout, the driver re-opens the device every
//    wts.reconnect_period_s (read_status Disconnected, then Reconnected) and
//    the new descriptor is watched. stop() unwatches and closes it.
//  * A periodic activity: each period polls once.
//  * SlaveActivity (tests, simulation): each update() polls once.
//  A non-periodic activity of any other kind is refused by start() (it would
//  either spin or never read). start() opens the port and starts the
//  acquisition (not real-time). Per cycle: no heap allocation, no exceptions,
//  no logging, no waiting.
#pragma once

#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include "tactile_types_rtt/component.hpp"
#include <rtt/extras/FileDescriptorActivityInterface.hpp>

#include <atomic>
#include <string>

#include "tactile_types/types.hpp"
#include "tactile_wts/driver.hpp"

namespace tactile {

class WtsComponent : public Component {
 public:
  explicit WtsComponent(const std::string& name);
  ~WtsComponent() override { haltActivity(); }  // stops its thread while its ports exist (component.hpp)

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void stopHook() override;

  std::string lastError() const { return last_error_; }
  std::string statusName() const;

 private:
  /// The activity as a FileDescriptorActivity, or nullptr (any other activity).
  RTT::extras::FileDescriptorActivityInterface* fdActivity();
  /// Watches the driver's current descriptor (it changes on unplug / re-open).
  void syncWatch();

  std::string param_file_;
  std::string device_;
  double poll_timeout_ = 0.05;
  double stop_timeout_ = 5.0;
  std::string last_error_;
  // The component's record, written by the activity and read by any thread
  // (attributes over atomics: tactile_types_rtt/atomic_attribute.hpp).
  std::atomic<int> read_status_{static_cast<int>(wts::ReadStatus::NotConfigured)};
  std::atomic<int> frames_{0};
  std::atomic<int> timeouts_{0};
  std::atomic<bool> fd_activity_attr_{false};
  std::atomic<double> frame_delay_{0.0};
  std::atomic<double> frame_delay_max_{0.0};
  RTT::extras::FileDescriptorActivityInterface* fd_activity_ = nullptr;  // set by startHook while running
  int watched_fd_ = -1;

  RTT::OutputPort<RawTactileFrame> raw_out_;

  wts::WtsDriver driver_;
  RawTactileFrame raw_;
};

}  // namespace tactile
