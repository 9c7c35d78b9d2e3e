#include "tactile_wts_rtt/wts_component.hpp"

#include "tactile_types_rtt/atomic_attribute.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/Thread.hpp>
#include <rtt/os/TimeService.hpp>

#include <algorithm>

#include "tactile_config/yaml_params.hpp"
#include "tactile_wts/params_io.hpp"

namespace tactile {

WtsComponent::WtsComponent(const std::string& name) : Component(name, PreOperational), raw_out_("raw_frame") {
  addProperty("param_file", param_file_)
      .doc("Optional YAML file with a `wts:` map (device, rows, cols, transpose, periodic_ms, ...); empty = defaults.");
  addProperty("device", device_).doc("Serial device path; overrides the file's wts.device when not empty.");
  addProperty("poll_timeout", poll_timeout_)
      .doc("FileDescriptorActivity timeout (s), (0, 1]: with no byte for this long the hook runs anyway "
           "(NoData; reconnection checks while unplugged). The hook itself never waits.");
  addProperty("stop_timeout", stop_timeout_)
      .doc("Longest wait of stop() for a FileDescriptorActivity's thread to leave its loop (s), [1, 60]: "
           "its select() on a tty can wait in the kernel for the tty's worker thread, which a loaded "
           "machine can hold for hundreds of milliseconds (RTT's default is 1 s).");
  addAtomicAttribute(*provides(), "read_status", read_status_);
  addAtomicAttribute(*provides(), "frames", frames_);
  addAtomicAttribute(*provides(), "timeouts", timeouts_);
  addAtomicAttribute(*provides(), "fd_activity", fd_activity_attr_);
  addAtomicAttribute(*provides(), "frame_delay", frame_delay_);
  addAtomicAttribute(*provides(), "frame_delay_max", frame_delay_max_);
  addPort(raw_out_).doc("Raw WTS frame (12-bit counts, {s} layout); time_s is when the device took it, on RTT's "
                        "TimeService (s): its arrival minus its delay (attribute frame_delay) in the link and the "
                        "tty, from the device's own clock.");
  addOperation("lastError", &WtsComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure() or start().");
  addOperation("statusName", &WtsComponent::statusName, this, RTT::ClientThread)
      .doc("ReadStatus of the last poll as text.");
}

bool WtsComponent::configureHook() {
  wts::WtsParams p;
  ConfigResult r = ConfigResult::success();
  if (!param_file_.empty()) {
    YAML::Node root;
    r = config::loadFile(param_file_, root);
    if (r) r = wts::loadWtsParams(root["wts"], config::Where{param_file_, "wts"}, p);
  }
  if (r && !device_.empty()) p.device = device_;
  if (r && !(poll_timeout_ > 0.0 && poll_timeout_ <= 1.0)) r = rangeError("poll_timeout", poll_timeout_, "(0, 1] s");
  if (r && !(stop_timeout_ >= 1.0 && stop_timeout_ <= 60.0)) r = rangeError("stop_timeout", stop_timeout_, "[1, 60] s");
  if (r) r = driver_.configure(p);
  if (!verdict(r, last_error_)) return false;
  raw_ = RawTactileFrame();
  raw_.rows = static_cast<uint16_t>(p.cells.rows);
  raw_.cols = static_cast<uint16_t>(p.cells.cols);
  raw_out_.setDataSample(raw_);
  auto* fda = fdActivity();
  record(fd_activity_attr_, fda != nullptr);
  if (fda) fda->setTimeout_us(static_cast<int>(poll_timeout_ * 1e6));
  return true;
}

RTT::extras::FileDescriptorActivityInterface* WtsComponent::fdActivity() {
  return dynamic_cast<RTT::extras::FileDescriptorActivityInterface*>(getActivity());
}

void WtsComponent::syncWatch() {
  const int fd = driver_.fd();
  if (fd == watched_fd_) return;
  if (watched_fd_ >= 0) fd_activity_->unwatch(watched_fd_);
  watched_fd_ = fd;
  if (fd >= 0) fd_activity_->watch(fd);
}

bool WtsComponent::startHook() {
  fd_activity_ = fdActivity();  // the activity cannot change while running
  record(fd_activity_attr_, fd_activity_ != nullptr);
  if (!fd_activity_ && getActivity() && !getActivity()->isPeriodic() &&
      dynamic_cast<RTT::extras::SlaveActivity*>(getActivity()) == nullptr) {
    last_error_ = "a non-periodic activity that is not a FileDescriptorActivity would spin or never read: "
                  "use a FileDescriptorActivity (paced by the device), a periodic activity or a SlaveActivity";
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    return false;
  }
  std::string why;
  const wts::CmdStatus st = driver_.open(&why);
  if (st != wts::CmdStatus::Ok) {
    last_error_ = driver_.params().device + ": " + wts::toString(st) + (why.empty() ? "" : ": " + why);
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    driver_.close();
    return false;
  }
  record(frames_, 0);
  record(timeouts_, 0);
  if (fd_activity_) {
    if (auto* thread = dynamic_cast<RTT::os::Thread*>(getActivity())) thread->setStopTimeout(stop_timeout_);
    // Clamped to [1 ms, 1 s] (the property may change after configure; 0 would mean no timeout).
    fd_activity_->setTimeout_us(static_cast<int>(1e6 * std::min(1.0, std::max(0.001, poll_timeout_))));
    watched_fd_ = -1;
    syncWatch();
  }
  return true;
}

void WtsComponent::stopHook() {
  if (fd_activity_ && watched_fd_ >= 0) fd_activity_->unwatch(watched_fd_);  // before the port closes it
  watched_fd_ = -1;
  fd_activity_ = nullptr;
  driver_.stopPeriodic();  // bounded by command_timeout_ms; ignored when unplugged (not real-time)
  driver_.close();
}

std::string WtsComponent::statusName() const {
  return wts::toString(static_cast<wts::ReadStatus>(read_status_.load(std::memory_order_relaxed)));
}

void WtsComponent::updateHook() {
  const HookScope hook(*this);  // the other hooks' writes before this update (component.hpp)
  const double now = RTT::os::TimeService::Instance()->secondsSince(0);  // the servo's clock
  if (fd_activity_ && fd_activity_->hasTimeout()) bump(timeouts_);  // no byte for poll_timeout s
  // Never waits: what arrived is read, decoded; reconnection is due by `now`.
  const wts::ReadStatus st = driver_.poll(now, 0, raw_);
  record(read_status_, static_cast<int>(st));
  if (st == wts::ReadStatus::NewFrame) {  // time_s: when taken, from the device's clock (device_clock.hpp)
    raw_out_.write(raw_);
    bump(frames_);
    record(frame_delay_, driver_.clockStats().delay_last_s);
    record(frame_delay_max_, driver_.clockStats().delay_max_s);
  }
  // The driver closes the port on unplug and re-opens it later: watch the
  // descriptor it has now (never a closed one: select() would fail on it).
  if (fd_activity_) syncWatch();
}

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::WtsComponent)
