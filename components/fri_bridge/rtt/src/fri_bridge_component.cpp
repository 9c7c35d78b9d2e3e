#include "tactile_fri_rtt/fri_bridge_component.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/os/TimeService.hpp>

#include <algorithm>
#include <cmath>

#include "tactile_fri/params_io.hpp"
#include "tactile_fri/protocol.hpp"

namespace tactile {

FriBridgeComponent::FriBridgeComponent(const std::string& name)
    : RTT::TaskContext(name, PreOperational),
      command_in_("pose_command"),
      pose_out_("flange_pose"),
      wrench_out_("estimated_wrench"),
      wrench_(6, 0.0) {
  addProperty("param_file", param_file_)
      .doc("YAML file with a `fri:` map (BridgeParams, and `udp:` bind_address/port); read by configure().");
  addProperty("port", port_).doc("UDP port to bind: -1 = fri.udp.port of param_file, 0 = ephemeral (tests), else [1, 65535].");
  addProperty("receive_timeout", receive_timeout_)
      .doc("Longest wait for one KRC packet per updateHook (s), (0, 1]; bounds how long stop() takes.");
  addAttribute("local_port", local_port_);
  addAttribute("bridge_status", bridge_status_);
  addAttribute("fri_state", fri_state_);
  addAttribute("fri_quality", fri_quality_);
  addAttribute("received", received_);
  addAttribute("replies", replies_);
  addAttribute("lost", lost_);
  addAttribute("timeouts", timeouts_);
  addAttribute("socket_errors", socket_errors_);
  addPort(command_in_).doc("Desired flange pose {g}T{e} (from the servo); rate-limited by the bridge.");
  addPort(pose_out_).doc("Measured flange pose {g}T{e} (msrCartPos of the KRC), per accepted packet.");
  addPort(wrench_out_).doc("Estimated external TCP wrench [Fx Fy Fz Tx Ty Tz] (N, N m) from estExtTcpFT.");
  addOperation("lastError", &FriBridgeComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
  addOperation("statusName", &FriBridgeComponent::statusName, this, RTT::ClientThread)
      .doc("BridgeStatus of the last packet as text.");
}

bool FriBridgeComponent::configureHook() {
  fri::BridgeParams bp;
  fri::UdpParams up;
  ConfigResult r = param_file_.empty()
                       ? ConfigResult::failure("param_file is empty: set it to a YAML file with a `fri:` map")
                       : fri::loadBridgeParamsFile(param_file_, bp, up);
  if (r && (port_ < -1 || port_ > 65535)) r = rangeError("port", port_, "-1 (from param_file), 0 (ephemeral) or [1, 65535]");
  if (r && !(receive_timeout_ > 0.0 && receive_timeout_ <= 1.0))
    r = rangeError("receive_timeout", receive_timeout_, "(0, 1] s");
  if (r) r = bridge_.configure(bp);
  if (r) {
    if (port_ >= 0) up.port = static_cast<uint16_t>(port_);
    socket_.close();
    r = socket_.open(up);
  }
  if (!r) {
    last_error_ = r.message();
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    return false;
  }
  last_error_.clear();
  local_port_ = socket_.localPort();
  measured_ = Pose();
  pose_out_.setDataSample(measured_);
  wrench_out_.setDataSample(wrench_);
  received_ = replies_ = lost_ = timeouts_ = socket_errors_ = 0;
  return true;
}

bool FriBridgeComponent::startHook() {
  bridge_.reset();
  desired_ = PoseCommand();  // never set: the bridge holds (DesiredInvalid) until the servo writes one
  return socket_.isOpen();
}

void FriBridgeComponent::cleanupHook() { socket_.close(); }

std::string FriBridgeComponent::statusName() const {
  return fri::toString(static_cast<fri::BridgeStatus>(status_shadow_.load()));
}

void FriBridgeComponent::updateHook() {
  std::size_t n = 0;
  // Clamped to [0, 1] s (the property may be changed while running; NaN -> 0).
  const double timeout_s = std::min(1.0, std::max(0.0, receive_timeout_));
  const auto timeout_us = static_cast<int64_t>(timeout_s * 1e6);
  const fri::UdpStatus us = socket_.receive(rx_.data(), rx_.size(), n, timeout_us);
  if (us == fri::UdpStatus::Ok || us == fri::UdpStatus::Truncated) {
    command_in_.read(desired_, false);  // keeps the last sample when nothing new
    const double now = RTT::os::TimeService::Instance()->secondsSince(0);  // the servo's clock
    // A truncated datagram is passed as longer than the buffer: the decoder rejects it (TooLong).
    const std::size_t size = us == fri::UdpStatus::Truncated ? rx_.size() + 1 : n;
    const fri::BridgeStatus st = bridge_.stepDatagram(rx_.data(), size, desired_, now, out_);
    if (out_.reply) {
      std::size_t w = 0;
      if (fri::encodeCommand(out_.cmd, tx_.data(), tx_.size(), w) == fri::PacketStatus::Ok &&
          socket_.reply(tx_.data(), w) == fri::UdpStatus::Ok)
        ++replies_;
    }
    bridge_status_ = static_cast<int>(st);
    status_shadow_.store(bridge_status_);
    ++received_;
    lost_ = static_cast<int>(bridge_.stats().lost);
    if (st != fri::BridgeStatus::Malformed && st != fri::BridgeStatus::DroppedDuplicate &&
        st != fri::BridgeStatus::DroppedOutOfOrder && st != fri::BridgeStatus::NotConfigured) {
      const fri::MsrPacket& msr = bridge_.lastMeasurement();
      fri_state_ = static_cast<int>(out_.state);
      fri_quality_ = static_cast<int>(out_.quality);
      if (fri::validFriPose(msr.data.msr_cart_pos)) {
        KDL::Frame f;
        fri::toFrame(msr.data.msr_cart_pos, f);
        toPose(f, measured_);
        pose_out_.write(measured_);
      }
      const std::array<double, 6> w = fri::toWrench(msr.data.est_ext_tcp_ft);
      bool finite = true;
      for (double v : w) finite = finite && std::isfinite(v);
      if (finite) {
        for (std::size_t i = 0; i < 6; ++i) wrench_[i] = w[i];
        wrench_out_.write(wrench_);
      }
    }
  } else if (us == fri::UdpStatus::Timeout) {
    ++timeouts_;
  } else {
    ++socket_errors_;  // Error / NotOpen: no busy loop on a broken socket; stop() + start() retries
    return;
  }
  // Paced by the KRC: wait for the next packet (a no-op under a SlaveActivity).
  this->trigger();
}

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::FriBridgeComponent)
