#include "tactile_fri_rtt/fri_bridge_component.hpp"

#include "tactile_types_rtt/atomic_attribute.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>

#include <arpa/inet.h>

#include <algorithm>
#include <cmath>

#include "tactile_fri/params_io.hpp"
#include "tactile_fri/protocol.hpp"

namespace tactile {

FriBridgeComponent::FriBridgeComponent(const std::string& name)
    : Component(name, PreOperational),
      command_in_("pose_command"),
      pose_out_("flange_pose"),
      wrench_out_("estimated_wrench"),
      robot_out_("robot_state") {
  addProperty("param_file", param_file_)
      .doc("YAML file with a `fri:` map (BridgeParams, and `udp:` bind_address/port); read by configure().");
  addProperty("port", port_).doc("UDP port to bind: -1 = fri.udp.port of param_file, 0 = ephemeral (tests), else [1, 65535].");
  addProperty("receive_timeout", receive_timeout_)
      .doc("Longest KRC silence (s), (0, 1], before krc_silent: the FileDescriptorActivity's timeout "
           "(set by configure()/start()); on a periodic or slave activity, measured with RTT's TimeService.");
  addAtomicAttribute(*provides(), "local_port", local_port_);
  addAtomicAttribute(*provides(), "bridge_status", bridge_status_);
  addAtomicAttribute(*provides(), "fri_state", fri_state_);
  addAtomicAttribute(*provides(), "fri_quality", fri_quality_);
  addAtomicAttribute(*provides(), "krc_silent", krc_silent_);
  addAtomicAttribute(*provides(), "dry_run", dry_run_);
  addAtomicAttribute(*provides(), "fd_activity", fd_activity_attr_);
  addAtomicAttribute(*provides(), "received", received_);
  addAtomicAttribute(*provides(), "replies", replies_);
  addAtomicAttribute(*provides(), "lost", lost_);
  addAtomicAttribute(*provides(), "timeouts", timeouts_);
  addAtomicAttribute(*provides(), "socket_errors", socket_errors_);
  addAtomicAttribute(*provides(), "limits", limits_);
  addAtomicAttribute(*provides(), "krc_program", krc_program_);
  addAtomicAttribute(*provides(), "krc_stop_requested", krc_stop_requested_);
  addAtomicAttribute(*provides(), "krc_stop_cause", krc_stop_cause_);
  addAtomicAttribute(*provides(), "limited_max_lin_speed", limited_lin_);
  addAtomicAttribute(*provides(), "limited_max_rot_speed", limited_rot_);
  addPort(command_in_).doc("Desired flange pose {g}T{e} (from the servo); rate-limited by the bridge.");
  addPort(pose_out_).doc("Measured flange pose {g}T{e} (msrCartPos of the KRC), per accepted packet.");
  addPort(wrench_out_).doc("Estimated external TCP wrench w = [Fx Fy Fz Tx Ty Tz] (N, N m) from estExtTcpFT, "
                           "time_s = the TimeService at reception.");
  addPort(robot_out_).doc("The KRC's state per accepted packet (written before flange_pose): mode, quality, drives, "
                          "control strategy, config_ok (cycle time, port and control mode agree with fri.yaml), "
                          "dry_run, commandable (the arm follows pose commands now) and the measured joints.");
  addOperation("setDryRun", &FriBridgeComponent::setDryRun, this, RTT::ClientThread)
      .doc("Bring-up dry run on/off (also the attribute dry_run): in CMD the bridge holds the pose where CMD was "
           "entered whatever the servo asks; robot_state says dry_run, so the servo computes as if the arm followed.")
      .arg("on", "true: dry run");
  addOperation("lastError", &FriBridgeComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
  addOperation("statusName", &FriBridgeComponent::statusName, this, RTT::ClientThread)
      .doc("BridgeStatus of the last packet as text, or krc_silent after receive_timeout s without one.");
  addOperation("requestKrcStop", &FriBridgeComponent::requestKrcStop, this, RTT::ClientThread)
      .doc("Asks the KRL program (krc/TactileServo.src) to end: from the next packet on every reply carries "
           "$FRI_FRM_INT[1] = 99 (TS_REQ_STOP), latched until configure(). For a latched servo fault or the "
           "experiment's end.");
  addOperation("krcProgramName", &FriBridgeComponent::krcProgramName, this, RTT::ClientThread)
      .doc("The KRL program's step ($FRI_TO_INT[1]) of the last packet: waiting_for_quality, halted_before_start, "
           "commanding, stopping, closed, init or unknown.");
  addOperation("limitNames", &FriBridgeComponent::limitNames, this, RTT::ClientThread)
      .doc("The limits (fri.yaml keys: max_lin_speed, max_rot_speed) that clipped the last command; \"\" if none.");
}

FriBridgeComponent::~FriBridgeComponent() {
  stop();  // unwatches the socket before its member closes it (no-op when not running)
  haltActivity();  // its thread, while the ports exist (component.hpp)
}

namespace {
// receive_timeout in us, clamped to [0, 1] s (the property may change after
// configure; NaN -> 0).
int64_t timeoutUs(double s) { return static_cast<int64_t>(std::min(1.0, std::max(0.0, s)) * 1e6); }
// The FileDescriptorActivity's timeout: 0 would mean none, so at least 1 ms.
int fdTimeoutUs(double s) { return static_cast<int>(std::max<int64_t>(1000, timeoutUs(s))); }
// Polled mode: datagrams handled per cycle at most (a backlog is worked off
// over a few cycles, each bounded).
constexpr int kMaxPerCycle = 8;
double nowS() { return RTT::os::TimeService::Instance()->secondsSince(0); }  // the servo's clock
}  // namespace

RTT::extras::FileDescriptorActivityInterface* FriBridgeComponent::fdActivity() {
  return dynamic_cast<RTT::extras::FileDescriptorActivityInterface*>(getActivity());
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
  record(krc_stop_requested_, false);  // a new session: no stop request
  record(krc_stop_cause_, 0);
  if (r) {
    if (port_ >= 0) up.port = static_cast<uint16_t>(port_);
    socket_.close();  // never watched here: start() watches it, stop() unwatches it
    r = socket_.open(up);
  }
  if (!verdict(r, last_error_)) return false;
  record(local_port_, static_cast<int>(socket_.localPort()));
  measured_ = Pose();
  pose_out_.setDataSample(measured_);
  wrench_ = Wrench();
  wrench_out_.setDataSample(wrench_);
  robot_out_.setDataSample(RobotState());
  for (std::atomic<int>* c : {&received_, &replies_, &lost_, &timeouts_, &socket_errors_}) record(*c, 0);
  // Paced by the socket: the KRC's silence is the FileDescriptorActivity's timeout.
  auto* fda = fdActivity();
  record(fd_activity_attr_, fda != nullptr);
  if (fda) fda->setTimeout_us(fdTimeoutUs(receive_timeout_));
  return true;
}

bool FriBridgeComponent::startHook() {
  if (!socket_.isOpen()) return false;
  if (!fdActivity() && getActivity() && !getActivity()->isPeriodic() &&
      dynamic_cast<RTT::extras::SlaveActivity*>(getActivity()) == nullptr) {
    last_error_ = "a non-periodic activity that is not a FileDescriptorActivity would spin or never read: "
                  "use a FileDescriptorActivity (paced by the KRC), a periodic activity or a SlaveActivity";
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    return false;
  }
  silence_since_s_ = nowS();
  // A SlaveActivity's master decides the cycles: one datagram per update(); a
  // periodic activity works off a backlog (bounded per cycle) to keep up with the KRC.
  max_per_cycle_ = dynamic_cast<RTT::extras::SlaveActivity*>(getActivity()) != nullptr ? 1 : kMaxPerCycle;
  bridge_.reset();
  desired_ = PoseCommand();  // never set: the bridge holds (DesiredInvalid) until the servo writes one
  record(krc_silent_, false);
  // Measurements queued while stopped are stale: the first reply answers a current one.
  socket_.discardPending();
  fd_activity_ = fdActivity();  // the activity cannot change while running
  record(fd_activity_attr_, fd_activity_ != nullptr);
  if (fd_activity_) {
    fd_activity_->setTimeout_us(fdTimeoutUs(receive_timeout_));
    // Watched only while running: select() is level-triggered and a Stopped
    // component does not read, so a watched socket with a KRC sending would spin.
    watched_fd_ = socket_.fd();
    fd_activity_->watch(watched_fd_);
  }
  return true;
}

void FriBridgeComponent::stopHook() {
  if (fd_activity_ && watched_fd_ >= 0) fd_activity_->unwatch(watched_fd_);
  watched_fd_ = -1;
  fd_activity_ = nullptr;
}

void FriBridgeComponent::cleanupHook() { socket_.close(); }

std::string FriBridgeComponent::statusName() const {
  if (krc_silent_.load(std::memory_order_relaxed)) return "krc_silent";
  return fri::toString(static_cast<fri::BridgeStatus>(bridge_status_.load(std::memory_order_relaxed)));
}

void FriBridgeComponent::markSilent() {
  bump(timeouts_);
  record(krc_silent_, true);
}

void FriBridgeComponent::updateHook() {
  const HookScope hook(*this);  // the other hooks' writes before this update (component.hpp)
  std::size_t n = 0;
  if (fd_activity_) {
    // FileDescriptorActivity: woken by a readable socket, by its timeout (no
    // datagram for receive_timeout s), or by a trigger()/start(). Never waits.
    if (fd_activity_->hasTimeout()) {
      markSilent();
      return;
    }
    if (fd_activity_->hasError()) {
      bump(socket_errors_);  // select() failed (the activity logs it)
      return;
    }
    // One datagram per cycle; another one queued wakes the activity again at once.
    const fri::UdpStatus us = socket_.receive(rx_.data(), rx_.size(), n, 0);
    if (us == fri::UdpStatus::Ok || us == fri::UdpStatus::Truncated)
      handleDatagram(us, n);
    else if (us != fri::UdpStatus::Timeout)  // Timeout: woken without a datagram (trigger)
      bump(socket_errors_);
    return;
  }
  pollCycle();
}

void FriBridgeComponent::pollCycle() {
  // Periodic activity or SlaveActivity: what is queued, never waiting.
  for (int k = 0; k < max_per_cycle_; ++k) {
    std::size_t n = 0;
    const fri::UdpStatus us = socket_.receive(rx_.data(), rx_.size(), n, 0);
    if (us == fri::UdpStatus::Timeout) break;  // nothing (more) queued
    if (us != fri::UdpStatus::Ok && us != fri::UdpStatus::Truncated) {
      bump(socket_errors_);  // Error / NotOpen: stop() + start() retries
      return;
    }
    handleDatagram(us, n);
    silence_since_s_ = nowS();
  }
  // No datagram for receive_timeout s: silent, counted once per receive_timeout.
  const double now = nowS();
  if (now - silence_since_s_ >= receive_timeout_) {
    markSilent();
    silence_since_s_ = now;
  }
}

void FriBridgeComponent::handleDatagram(fri::UdpStatus us, std::size_t n) {
  record(krc_silent_, false);
  command_in_.read(desired_, false);  // keeps the last sample when nothing new
  const double now = nowS();
  // A truncated datagram is passed as longer than the buffer: the decoder rejects it (TooLong).
  const std::size_t size = us == fri::UdpStatus::Truncated ? rx_.size() + 1 : n;
  bridge_.setDryRun(dry_run_.load(std::memory_order_acquire));
  if (krc_stop_requested_.load(std::memory_order_acquire) && !bridge_.stopRequested()) bridge_.requestStop();
  bridge_.notePeerPort(socket_.hasPeer() ? ntohs(socket_.lastPeer().sin_port) : 0);
  const fri::BridgeStatus st = bridge_.stepDatagram(rx_.data(), size, desired_, now, out_);
  if (out_.reply) {
    std::size_t w = 0;
    if (fri::encodeCommand(out_.cmd, tx_.data(), tx_.size(), w) == fri::PacketStatus::Ok &&
        socket_.reply(tx_.data(), w) == fri::UdpStatus::Ok)
      bump(replies_);
  }
  record(bridge_status_, static_cast<int>(st));
  if (bridge_.stopRequested() && !krc_stop_requested_.load(std::memory_order_relaxed)) {
    record(krc_stop_requested_, true);  // the core asked on a servo fault (stop_krc_on_servo_fault)
    record(krc_stop_cause_, static_cast<int>(bridge_.stopCause()));
  }
  bump(received_);
  record(lost_, static_cast<int>(bridge_.stats().lost));
  record(limits_, static_cast<int>(out_.limits));
  record(krc_program_, static_cast<int>(out_.krl_program));
  record(limited_lin_, static_cast<int>(bridge_.stats().limited_lin_speed));
  record(limited_rot_, static_cast<int>(bridge_.stats().limited_rot_speed));
  if (st == fri::BridgeStatus::Malformed || st == fri::BridgeStatus::DroppedDuplicate ||
      st == fri::BridgeStatus::DroppedOutOfOrder || st == fri::BridgeStatus::NotConfigured)
    return;
  const fri::MsrPacket& msr = bridge_.lastMeasurement();
  record(fri_state_, static_cast<int>(out_.state));
  record(fri_quality_, static_cast<int>(out_.quality));
  robot_out_.write(out_.robot);  // before the pose: a servo that sees the pose sees the state too
  const bool pose_ok = fri::validFriPose(msr.data.msr_cart_pos);
  KDL::Frame f = KDL::Frame::Identity();
  if (pose_ok) {
    fri::toFrame(msr.data.msr_cart_pos, f);
    toPose(f, measured_);
    pose_out_.write(measured_);
  }
  // the wrench in {g}: in the KRC's tool axes it needs the measured pose
  const fri::WrenchFrame axes = bridge_.params().wrench_frame;
  if (axes == fri::WrenchFrame::Tool && !pose_ok) return;
  const std::array<double, 6> w = fri::wrenchInBase(msr.data.est_ext_tcp_ft, axes, f.M);
  bool finite = true;
  for (double v : w) finite = finite && std::isfinite(v);
  if (finite) {
    wrench_.time_s = now;
    wrench_.w = w;
    wrench_out_.write(wrench_);
  }
}

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::FriBridgeComponent)
