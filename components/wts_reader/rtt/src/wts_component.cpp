#include "tactile_wts_rtt/wts_component.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/os/TimeService.hpp>

#include <algorithm>
#include <chrono>
#include <thread>

#include "tactile_config/yaml_params.hpp"
#include "tactile_wts/params_io.hpp"

namespace tactile {

WtsComponent::WtsComponent(const std::string& name) : RTT::TaskContext(name, PreOperational), raw_out_("raw_frame") {
  addProperty("param_file", param_file_)
      .doc("Optional YAML file with a `wts:` map (device, rows, cols, transpose, periodic_ms, ...); empty = defaults.");
  addProperty("device", device_).doc("Serial device path; overrides the file's wts.device when not empty.");
  addProperty("poll_timeout", poll_timeout_).doc("Longest wait for bytes per updateHook (s), (0, 1].");
  addAttribute("read_status", read_status_);
  addAttribute("frames", frames_);
  addPort(raw_out_).doc("Raw WTS frame (12-bit counts, {s} layout), stamped with RTT's TimeService (s).");
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
  if (r) r = driver_.configure(p);
  if (!r) {
    last_error_ = r.message();
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    return false;
  }
  last_error_.clear();
  raw_ = RawTactileFrame();
  raw_.rows = static_cast<uint16_t>(p.cells.rows);
  raw_.cols = static_cast<uint16_t>(p.cells.cols);
  raw_out_.setDataSample(raw_);
  return true;
}

bool WtsComponent::startHook() {
  std::string why;
  const wts::CmdStatus st = driver_.open(&why);
  if (st != wts::CmdStatus::Ok) {
    last_error_ = driver_.params().device + ": " + wts::toString(st) + (why.empty() ? "" : ": " + why);
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    driver_.close();
    return false;
  }
  frames_ = 0;
  return true;
}

void WtsComponent::stopHook() {
  driver_.stopPeriodic();  // bounded by command_timeout_ms; ignored when unplugged
  driver_.close();
}

std::string WtsComponent::statusName() const {
  return wts::toString(static_cast<wts::ReadStatus>(status_shadow_.load()));
}

void WtsComponent::updateHook() {
  const double now = RTT::os::TimeService::Instance()->secondsSince(0);  // the servo's clock
  // periodic: never wait longer than a period; clamped to [0, 1] s (NaN -> 0)
  const double wait_s = std::min(getPeriod() > 0.0 ? 0.0 : 1.0, std::max(0.0, poll_timeout_));
  const int timeout_ms = static_cast<int>(1000.0 * wait_s);
  const wts::ReadStatus st = driver_.poll(now, timeout_ms, raw_);
  read_status_ = static_cast<int>(st);
  status_shadow_.store(read_status_);
  if (st == wts::ReadStatus::NewFrame) {
    raw_.time_s = now;
    raw_out_.write(raw_);
    ++frames_;
  }
  if (getPeriod() > 0.0) return;  // periodic activity: the period paces the polls
  // Non-periodic: paced by the device (poll waits for bytes), loop. Unplugged,
  // poll() returns at once: wait poll_timeout (bounded) so the loop does not spin
  // while the driver retries every reconnect_period_s.
  if (st == wts::ReadStatus::Disconnected || st == wts::ReadStatus::NotConfigured)
    std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
  this->trigger();  // a no-op under a SlaveActivity
}

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::WtsComponent)
