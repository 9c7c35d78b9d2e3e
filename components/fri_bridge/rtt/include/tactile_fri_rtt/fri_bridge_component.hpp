// tactile::FriBridgeComponent: thin RTT wrapper around tactile::fri::FriBridge
// (the FRI protocol logic: sequence checks, MON echo, rate limiter, hold) and
// tactile::fri::UdpSocket (the UDP transport to the KUKA KRC).
//
// Same port names and types as tactile::LwrSimComponent, so a deployment
// swaps the simulator for the robot by changing one loadComponent line.
//
// Interface (documented with .doc() in the constructor):
//   property param_file (string)   YAML with a `fri:` map (components/fri_bridge/params/fri.yaml)
//   property port (int)            UDP port override: -1 = the file's fri.udp.port, 0 = ephemeral
//   property receive_timeout (double)  s, (0, 1]: longest wait for one packet in updateHook
//   in   pose_command (/tactile/PoseCommand)  desired {g}T{e} (from the servo)
//   out  flange_pose  (/tactile/Pose)         measured {g}T{e} (msrCartPos), per accepted packet
//   out  estimated_wrench (array, 6)          estExtTcpFT as [Fx Fy Fz Tx Ty Tz] (N, N m)
//   attr local_port (int)       the bound UDP port (after configure)
//   attr bridge_status (int)    fri::BridgeStatus of the last packet (see bridge.hpp)
//   attr fri_state (int), fri_quality (int)  KRC interface state / quality of the last packet
//   attr received, replies, lost, timeouts, socket_errors (int)  counters since configure
//        (a socket error ends the trigger loop: stop() + start() to retry)
//   op   string lastError(), string statusName()
//
// Execution: run it with a NON-periodic activity. The component is paced by
// the KRC: each updateHook waits (bounded by receive_timeout) for one
// measurement datagram, steps the bridge, sends the reply, writes the outputs,
// and trigger()s itself for the next packet. stop() returns within
// receive_timeout. With a SlaveActivity (tests) each update() handles at most
// one packet. Per cycle: no heap allocation, no exceptions, no logging.
#pragma once

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include <array>
#include <atomic>
#include <string>
#include <vector>

#include "tactile_fri/bridge.hpp"
#include "tactile_fri/udp.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class FriBridgeComponent : public RTT::TaskContext {
 public:
  explicit FriBridgeComponent(const std::string& name);

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

  std::string lastError() const { return last_error_; }
  std::string statusName() const;

 private:
  // properties / attributes
  std::string param_file_;
  int port_ = -1;
  double receive_timeout_ = 0.1;
  std::string last_error_;
  int local_port_ = 0;
  int bridge_status_ = static_cast<int>(fri::BridgeStatus::NotConfigured);
  std::atomic<int> status_shadow_{static_cast<int>(fri::BridgeStatus::NotConfigured)};
  int fri_state_ = 0, fri_quality_ = 0;
  int received_ = 0, replies_ = 0, lost_ = 0, timeouts_ = 0, socket_errors_ = 0;

  // ports
  RTT::InputPort<PoseCommand> command_in_;
  RTT::OutputPort<Pose> pose_out_;
  RTT::OutputPort<std::vector<double>> wrench_out_;

  // cores and preallocated buffers
  fri::FriBridge bridge_;
  fri::UdpSocket socket_;
  fri::BridgeOutput out_;
  PoseCommand desired_;
  Pose measured_;
  std::vector<double> wrench_;  // size 6, sized at configure
  std::array<uint8_t, 2048> rx_{};
  std::array<uint8_t, fri::kCmdPacketSize> tx_{};
};

}  // namespace tactile
