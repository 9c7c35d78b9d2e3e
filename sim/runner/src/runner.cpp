#include "tactile_sim/runner.hpp"

#include <algorithm>
#include <chrono>

#include "tactile_features/edge_line.hpp"
#include "tactile_sim/loop.hpp"

#include "tactile_fri/params_io.hpp"
#include "tactile_fri/protocol.hpp"
#include <cmath>
#include <limits>

namespace tactile {
namespace sim {


ConfigResult Runner::configure(const Scene& scene) {
  ConfigResult r = validateScene(scene);
  if (!r) return r;
  scene_ = scene;
  if (!(r = world_.configure(worldParams(scene)))) return ConfigResult::failure(scene.file + ": " + r.message());
  // The sensor's electronics and its reader from the one calibration file.
  if (!(r = response_.configure(responseParams(scene)))) return ConfigResult::failure(scene.file + ": sensor: " + r.message());
  if (!(r = sensor_.configure(scene.features, scene.calibration))) return ConfigResult::failure(scene.file + ": " + r.message());
  ServoParams sp = scene.servo;
  sp.mode = scene.controller;
  if (!(r = servo_.configure(sp, 1.0 / scene.rates.servo))) return ConfigResult::failure(scene.program_file + ": " + r.message());
  if (!(r = schedule_.configure(scene.rates, scene.duration))) return ConfigResult::failure(scene.file + ": " + r.message());
  end_.configure(scene.rates);
  // The KRC's script; through FRI the default passes through monitor mode
  // for the first 5 ms (friOpen, then friStart before the servo's second cycle).
  const std::string krc = scene.krc.empty() && scene.through_fri ? "0:friOpen,0.005:friStart" : scene.krc;
  if (!(r = krc_script_.parse(krc, scene.file + ": krc"))) return r;
  if (scene.through_fri) {
    fri::BridgeParams bp;
    fri::UdpParams up;
    if (!scene.fri_file.empty() && !(r = fri::loadBridgeParamsFile(scene.fri_file, bp, up))) return r;
    bp.cycle_time_s = 1.0 / scene.rates.sim;
    if (!(r = bridge_.configure(bp))) return ConfigResult::failure(scene.file + ": fri: " + r.message());
    fri::KrcModelParams kp;
    kp.period_s = 1.0 / scene.rates.sim;
    if (!(r = krc_.configure(kp))) return ConfigResult::failure(scene.file + ": fri: " + r.message());
    krc_.reset(world_.state().T_ge);
  }
  return ConfigResult::success();
}

void Runner::run(RunResult& out, const std::function<void(double, double)>& progress) {
  const auto wall0 = std::chrono::steady_clock::now();
  const Scene& sc = scene_;
  out = RunResult{};
  for (int k = 0; k < servo_.servo().phaseCount(); ++k) out.phase_names.push_back(servo_.servo().phase(k).name);
  Schedule& sched = schedule_;
  sched.reset();
  end_.reset();
  sensor_.reset();
  servo_.reset();
  response_.reseed(sc.seed);  // noise, creep, hysteresis and transfer ring as after configure
  const double dt = sched.dt();
  out.rows.reserve(static_cast<std::size_t>(sc.duration * sc.rates.servo) + 16);
  out.contacts.reserve(out.rows.capacity());
  out.edge_points.reserve(out.rows.capacity() * static_cast<std::size_t>(sc.features.cols));
  const SensorGeometry geometry = sc.features.geometry();
  EdgeLineParams line_params;
  line_params.fire_n = sc.features.contact_threshold;  // the features' own firing threshold
  EdgeLinePoints line;

  // The signals between the stages (what the RTT ports carry).
  TactileFrame forces;     // arm -> sensor: true taxel forces
  SensorTruth acq;         // the last acquisition's ground truth
  SimTruth truth;          // arm -> logs: ground truth after the last step
  RawTactileFrame raw;     // sensor -> features
  bool new_raw = false;
  uint32_t raw_seq = 0;
  TactileFrame frame;      // calibrated (features' output, for snapshots)
  ContactFeatures feats;   // NotConfigured until the first extraction: the servo holds
  ServoOutput sout;
  ServoStatus st = ServoStatus::NotConfigured;
  SimState state = world_.state();
  SimStatus ss = state.status;
  EstimatedWrench est_wrench;  // the arm's estimated wrench with the scene's error
  est_wrench.configure(sc.wrench_error, sc.seed);
  est_wrench.start(state);
  Pose cmd = state.command_g;  // the initial command (dynamics may start at its equilibrium, off it)
  // The arm at start: its image for the first acquisition, its ground truth.
  if (sched.fires().wts) world_.acquireForces(forces, acq);
  fillTruth(state, acq, truth);

  int last_phase = -1;
  bool first_contact_snap = false;
  Snapshot worst{0.0, "largest |DZMP_y|", TactileFrame{}};
  double worst_dzmp = -1.0;
  EndReason end = EndReason::None;
  Summary& sum = out.summary;
  sum.scene = sc.name;
  sum.controller = toString(sc.controller);
  sum.seed = sc.seed;
  sum.fidelity = toString(sc.world.fidelity);
  const long progress_every = std::max(1L, sched.ticks() / 100);

  RobotState robot;  // the arm side's state (what the robot_state port carries)
  robot.commandable = true;
  while (!sched.finished()) {
    const double t = sched.time();
    const StageFires fi = sched.fires();
    // The KRC's script: through FRI the bridge reports the robot state from
    // the packets (friCycle); directly, the same rule from the script.
    const fri::KrcScript::At krc_now = krc_script_.at(t);
    if (!sc.through_fri) {
      fri::robotStateOf(krc_now, t, robot);
      robot.setpoint = state.command_g;  // the KRC's set point: the last command the arm took
    }
    // WTS acquisition (Table 2: 140 Hz): the sensor's electronics; the frame
    // reaches the reader at once or, with a transfer delay, when it has arrived.
    if ((fi.wts && response_.acquire(forces, t, raw)) || (response_.delayed() && response_.deliver(t, raw))) {
      raw.seq = raw_seq++;
      raw.device_time_ms = static_cast<uint32_t>(std::llround(raw.time_s * 1000.0));
      new_raw = true;
    }
    if (fi.features && new_raw) {  // calibration + features on the latest frame (200 Hz)
      bool frame_ok = false;
      sensor_.step(raw, frame, feats, frame_ok);
      new_raw = false;
    }
    if (fi.servo) {  // tactile servo (100 Hz)
      servo_.setMeasuredPose(state.flange_g);
      Wrench wrench;  // the arm's estimated wrench, as the RTT arm publishes it
      est_wrench.fill(state, wrench);
      servo_.setEstimatedWrench(wrench);
      for (int j = 0; j < kArmJoints; ++j) robot.q[static_cast<std::size_t>(j)] = state.q(j);
      servo_.setRobotState(robot);
      if (servo_.step(t, feats, sout, st)) cmd = sout.command.pose;

      const int ph = servo_.servo().phaseIndex();
      const PhaseParams& pp = servo_.servo().phase(ph);
      if (ph != last_phase) {
        out.snapshots.push_back({t, "enter " + pp.name, frame});
        last_phase = ph;
      }
      if (!first_contact_snap && feats.contact != ContactType::None) {
        out.snapshots.push_back({t, "first contact", frame});
        first_contact_snap = true;
      }
      out.rows.push_back(makeRow(sc, t, ph, st, feats, cmd, truth, sout.u_s, sout.beta));
      if (feats.contact == ContactType::Edge && std::fabs(feats.dzmp_y) > worst_dzmp) {
        worst_dzmp = std::fabs(feats.dzmp_y);
        worst.t = t;
        worst.frame = frame;
      }
      if ((pp.requires_contact || pp.terminal) && feats.contact != ContactType::None) {
        // The controller's own data: the measured flange pose, the sensor
        // mount and the CoP (the truth beside it, for evaluation only).
        const KDL::Frame T_gs = toFrame(state.flange_g) * sc.servo.sensor_mount;
        const KDL::Vector p = T_gs * KDL::Vector(feats.cop_x, feats.cop_y, 0.0);
        out.contacts.push_back({t, {p.x(), p.y(), p.z()}, acq.contact_point_g, feats.lambda1, ph});
        const int n = edgeLinePoints(frame, geometry, line_params, line);
        for (int i = 0; i < n && out.edge_points.size() < out.edge_points.capacity(); ++i) {
          const KDL::Vector q = T_gs * KDL::Vector(line[static_cast<std::size_t>(i)].x, line[static_cast<std::size_t>(i)].y, 0.0);
          out.edge_points.push_back({t, {q.x(), q.y(), q.z()}, ph});
        }
      }
      if ((end = end_.afterServo(st)) != EndReason::None) break;
    }
    // The arm: one physics step toward the latest command.
    // Not commandable: the KRC keeps the set point it has.
    Pose applied = robot.commandable ? cmd : state.command_g;
    if (sc.through_fri) {
      PoseCommand desired = sout.command;
      desired.pose = cmd;
      desired.time_s = t;
      KDL::Frame f;
      if (friCycle(state, krc_now, desired, t, f, robot, sum)) applied = toPose(f);
      else applied = state.command_g;  // no packet: the KRC keeps its last set point
    }
    ss = world_.step(applied, dt, state);
    if (ss == SimStatus::NotConverged)
      sum.sim_unconverged_max_residual = std::max(sum.sim_unconverged_max_residual, state.solver_residual);
    sched.advance();
    if (sched.fires().wts) world_.acquireForces(forces, acq);  // the image of the next acquisition
    fillTruth(state, acq, truth);
    if ((end = end_.afterPhysics(ss)) != EndReason::None) break;
    if (progress && sched.tick() % progress_every == 0) progress(t, sc.duration);
  }
  if (progress) progress(state.time_s, sc.duration);
  if (worst_dzmp >= 0.0) out.snapshots.push_back(worst);
  out.snapshots.push_back({state.time_s, "end", frame});
  applyEnd(end, ss, sum);
  sum.sim_unconverged_steps = end_.unconvergedSteps();
  sum.sim_time_s = state.time_s;
  sum.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  sum.real_time_factor = sum.wall_time_s > 0 ? sum.sim_time_s / sum.wall_time_s : 0.0;
  out.phases = phaseEntries(sc, out.rows);
  computeSummary(sc, out);
}

bool Runner::friCycle(const SimState& st, const fri::KrcScript::At& krc_now, const PoseCommand& desired, double t,
                      KDL::Frame& applied, RobotState& robot, Summary& sum) {
  using namespace fri;
  // The simulated KRC (tactile::fri::KrcModel, the UDP test peer's model)
  // following the scene's KRC script (by default MON for the first 5 ms,
  // then CMD at perfect quality under Cartesian impedance): the servo holds
  // at the measured pose while the bridge's robot state is not commandable,
  // so its command passes the bridge's start gate when it becomes so. The
  // world's measured state in the packet; a closed link sends nothing.
  if (!krc_now.open) return false;
  KrcModel& krc = krc_;
  krc.setState(krc_now.state, krc_now.quality, krc_now.power ? 0x7F : 0);
  krc.holdUnlessCommanding(st.T_ge);
  PlantState plant;
  for (int j = 0; j < kNumJoints; ++j) plant.q[static_cast<std::size_t>(j)] = st.q(j);
  plant.pose = st.T_ge;
  MsrPacket m;
  krc.buildMeasurement(plant, t, m);
  std::size_t n = 0;
  if (encodeMeasurement(m, wire_.data(), wire_.size(), n) != PacketStatus::Ok) return false;
  BridgeOutput out;
  bridge_.stepDatagram(wire_.data(), n, desired, t, out);
  if (out.status != BridgeStatus::Malformed) robot = out.robot;
  if (out.reply && encodeCommand(out.cmd, wire_.data(), wire_.size(), n) == PacketStatus::Ok)
    krc.handleReply(wire_.data(), n);
  const KrcModelStats& ks = krc.stats();
  sum.fri_replies = static_cast<long>(ks.replies);
  sum.fri_max_step_m = ks.max_cmd_step_m;
  sum.fri_max_step_rad = ks.max_cmd_step_rad;
  applied = krc.setPoint();  // the KRC's set point: the last applied command, the measured pose outside CMD
  return true;
}

}  // namespace sim
}  // namespace tactile
