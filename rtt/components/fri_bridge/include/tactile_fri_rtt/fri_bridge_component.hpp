// tactile::FriBridgeComponent: thin RTT wrapper around tactile::fri::FriBridge
// (the FRI protocol logic: sequence checks, MON echo, rate limiter, hold) and
// tactile::fri::UdpSocket (the UDP transport to the KUKA KRC).
//
// Same port names and types as tactile::LwrSimComponent, so a deployment
// swaps the simulator for the robot by changing one loadComponent line.
//
// Interface (documented with .doc() in the constructor):
//   property param_file (string)   YAML with a `fri:` map (params/sensors/fri.yaml)
//   property port (int)            UDP port override: -1 = the file's fri.udp.port, 0 = ephemeral
//   property receive_timeout (double)  s, (0, 1]: longest silence of the KRC before `krc_silent`
//                                  (FileDescriptorActivity timeout; the bounded wait otherwise)
//   in   pose_command (/tactile/PoseCommand)  desired {g}T{e} (from the servo)
//   out  flange_pose  (/tactile/Pose)         measured {g}T{e} (msrCartPos), per accepted packet
//   out  estimated_wrench (/tactile/Wrench)   estExtTcpFT as w = [Fx Fy Fz Tx Ty Tz] (N, N m), fixed size
//   out  robot_state (/tactile/RobotState)    per accepted packet, written before flange_pose: the KRC's
//                                             mode, quality, drives, strategy, the check against fri.yaml
//                                             (cycle, port, control mode), dry run, `commandable`, joints
//   attr dry_run (bool)         bring-up dry run: in CMD the bridge holds the pose where CMD was entered;
//                               the servo computes and records as if the arm followed (set it, or setDryRun)
//   op   setDryRun(bool)
//   attr local_port (int)       the bound UDP port (after configure)
//   attr bridge_status (int)    fri::BridgeStatus of the last packet (see bridge.hpp)
//   attr fri_state (int), fri_quality (int)  KRC interface state / quality of the last packet
//   attr krc_silent (bool)      no datagram for receive_timeout s (cleared by the next one)
//   attr fd_activity (bool)     the activity is a FileDescriptorActivity (set by configure/start)
//   attr received, replies, lost, timeouts, socket_errors (int)  counters since configure
//        (timeouts: receive_timeout periods without a datagram)
//   op   string lastError(), string statusName() ("krc_silent" while silent)
//   attr limits (int)           fri::limit:: bits that clipped the last packet's command (status limited)
//   attr limited_max_lin_speed, limited_max_rot_speed (int)  commands clipped by each limit since configure
//   op   string limitNames()    the fri.yaml keys of `limits` ("" when the last command was not clipped)
//   op   requestKrcStop()       asks the KRL program (krc/TactileServo.src) to end: every reply from the
//                               next packet on carries $FRI_FRM_INT[1] = 99 (latched until configure)
//                               (a servo watchdog status on pose_command does the same in the bridge
//                               core when fri.yaml's stop_krc_on_servo_fault is set)
//   attr krc_stop_requested (bool)  a stop was requested: requestKrcStop(), or a servo fault
//   attr krc_stop_cause (int)   the tactile::ServoStatus (a watchdog) that requested it; 0 (ok) for none
//                               or for requestKrcStop()
//   attr krc_program (int)      the KRL program's step ($FRI_TO_INT[1]: 10 waiting for quality,
//                               20 commanding, 25 stopping, 30 closed); op string krcProgramName()
//
// Execution, paced by the KRC (one measurement datagram per cycle, 1 kHz):
//  * RTT::extras::FileDescriptorActivity (the deployments): configure() sets
//    its timeout to receive_timeout, start() drops any backlog and watches the
//    UDP socket, stop() unwatches it (a Stopped component would otherwise spin
//    on a readable socket). updateHook runs when a datagram is readable and
//    reads exactly one without waiting (another queued one wakes it again at
//    once): step the bridge, reply, write the outputs. On the activity's
//    timeout it sets krc_silent and counts a timeout; it never blocks.
//  * A periodic activity, or a SlaveActivity (tests, simulation): each cycle
//    reads what is already queued without waiting (a SlaveActivity: one
//    datagram per update(), its master decides the cycles; a periodic
//    activity: up to 8, to keep up with the KRC); with none for receive_timeout s (RTT's TimeService) it sets
//    krc_silent and counts a timeout, once per receive_timeout.
//  A non-periodic activity of any other kind is refused by start() (the hook
//  never waits: it would spin or never read). Prefer the FileDescriptorActivity.
// Per cycle: no heap allocation, no exceptions, no logging, no waiting.
#pragma once

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include "tactile_types_rtt/component.hpp"
#include <rtt/extras/FileDescriptorActivityInterface.hpp>

#include <array>
#include <atomic>
#include <string>
#include <vector>

#include "tactile_fri/bridge.hpp"
#include "tactile_fri/udp.hpp"
#include "tactile_types/types.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace tactile {

class FriBridgeComponent : public Component {
 public:
  explicit FriBridgeComponent(const std::string& name);
  ~FriBridgeComponent() override;

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void stopHook() override;
  void cleanupHook() override;

  std::string lastError() const { return last_error_; }
  void setDryRun(bool on) { record(dry_run_, on); }
  std::string statusName() const;
  std::string limitNames() const { return fri::limitNames(static_cast<uint8_t>(limits_.load())); }
  void requestKrcStop() { record(krc_stop_requested_, true); }
  std::string krcProgramName() const { return fri::krl::programStepName(krc_program_.load()); }

 private:
  /// The activity as a FileDescriptorActivity, or nullptr (any other activity).
  RTT::extras::FileDescriptorActivityInterface* fdActivity();
  /// One datagram through the bridge: step, reply, outputs, counters.
  void handleDatagram(fri::UdpStatus us, std::size_t n);
  void markSilent();
  /// Periodic / SlaveActivity cycle: queued datagrams without waiting, silence by time.
  void pollCycle();

  // properties / attributes
  std::string param_file_;
  int port_ = -1;
  double receive_timeout_ = 0.1;
  std::string last_error_;
  // The component's record, written by the activity and read by any thread
  // (attributes over atomics: tactile_types_rtt/atomic_attribute.hpp).
  std::atomic<int> local_port_{0};
  std::atomic<int> bridge_status_{static_cast<int>(fri::BridgeStatus::NotConfigured)};
  std::atomic<int> fri_state_{0}, fri_quality_{0};
  std::atomic<bool> krc_silent_{false};
  std::atomic<bool> dry_run_{false};
  std::atomic<bool> fd_activity_attr_{false};
  RTT::extras::FileDescriptorActivityInterface* fd_activity_ = nullptr;  // set by startHook while running
  int watched_fd_ = -1;
  double silence_since_s_ = 0.0;  // polled mode: last datagram or timeout (TimeService s)
  int max_per_cycle_ = 1;         // polled mode: datagrams per cycle (SlaveActivity 1, periodic 8)
  std::atomic<int> received_{0}, replies_{0}, lost_{0}, timeouts_{0}, socket_errors_{0};
  std::atomic<int> limits_{0}, limited_lin_{0}, limited_rot_{0};
  std::atomic<int> krc_program_{0};
  std::atomic<bool> krc_stop_requested_{false};
  std::atomic<int> krc_stop_cause_{0};

  // ports
  RTT::InputPort<PoseCommand> command_in_;
  RTT::OutputPort<Pose> pose_out_;
  RTT::OutputPort<Wrench> wrench_out_;
  RTT::OutputPort<RobotState> robot_out_;

  // cores and preallocated buffers
  fri::FriBridge bridge_;
  fri::UdpSocket socket_;
  fri::BridgeOutput out_;
  PoseCommand desired_;
  Pose measured_;
  Wrench wrench_;
  std::array<uint8_t, 2048> rx_{};
  std::array<uint8_t, fri::kCmdPacketSize> tx_{};
};

}  // namespace tactile
