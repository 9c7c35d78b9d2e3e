#include "tactile_sim_runner/runner.hpp"

#include <algorithm>
#include <chrono>

#include "tactile_features/edge_line.hpp"
#include "tactile_sim_runner/loop.hpp"

#include "tactile_fri/params_io.hpp"
#include "tactile_fri/protocol.hpp"
#include <cmath>
#include <limits>

namespace tactile {
namespace sim {


ConfigResult Runner::configure(const Scene& scene) {
  if (scene.program_file.empty())
    return ConfigResult::failure(scene.file + ": no phase program: a run is a scene with its program (loadRun)");
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

// The signals between the stages in one run (what the RTT ports carry) and
// the run's bookkeeping.
struct Runner::RunState {
  SensorGeometry geometry;
  EdgeLineParams line_params;
  EdgeLinePoints line;
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
  SimState state;
  SimStatus ss = SimStatus::Ok;
  EstimatedWrench est_wrench;  // the arm's estimated wrench with the scene's error
  Pose cmd;
  int last_phase = -1;
  bool first_contact_snap = false;
  Snapshot worst{0.0, "largest |DZMP_y|", TactileFrame{}};
  double worst_dzmp = -1.0;
  RobotState robot;  // the arm side's state (what the robot_state port carries)
};

void Runner::run(RunResult& out, const std::function<void(double, double)>& progress) {
  const auto wall0 = std::chrono::steady_clock::now();
  const Scene& sc = scene_;
  RunState rs;
  startRun(out, rs);
  Schedule& sched = schedule_;
  EndReason end = EndReason::None;
  const long progress_every = std::max(1L, sched.ticks() / 100);
  while (!sched.finished()) {
    const double t = sched.time();
    const StageFires fi = sched.fires();
    // The KRC's script: through FRI the bridge reports the robot state from
    // the packets (friCycle); directly, the same rule from the script.
    const fri::KrcScript::At krc_now = krc_script_.at(t);
    if (!sc.through_fri) {
      fri::robotStateOf(krc_now, t, rs.robot);
      rs.robot.setpoint = rs.state.command_g;  // the KRC's set point: the last command the arm took
    }
    sensorCycle(t, fi, rs);
    if (fi.servo && (end = servoCycle(t, rs, out)) != EndReason::None) break;
    physicsCycle(t, krc_now, rs, out.summary);
    if ((end = end_.afterPhysics(rs.ss)) != EndReason::None) break;
    if (progress && sched.tick() % progress_every == 0) progress(t, sc.duration);
  }
  if (progress) progress(rs.state.time_s, sc.duration);
  finishRun(end, rs, out);
  Summary& sum = out.summary;
  sum.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  sum.real_time_factor = sum.wall_time_s > 0 ? sum.sim_time_s / sum.wall_time_s : 0.0;
  out.phases = phaseEntries(sc, out.rows);
  computeSummary(sc, out);
}

void Runner::startRun(RunResult& out, RunState& rs) {
  const Scene& sc = scene_;
  out = RunResult{};
  for (int k = 0; k < servo_.servo().phaseCount(); ++k) out.phase_names.push_back(servo_.servo().phase(k).name);
  schedule_.reset();
  end_.reset();
  sensor_.reset();
  servo_.reset();
  response_.reseed(sc.seed);  // noise, creep, hysteresis and transfer ring as after configure
  out.rows.reserve(static_cast<std::size_t>(sc.duration * sc.rates.servo) + 16);
  out.contacts.reserve(out.rows.capacity());
  out.edge_points.reserve(out.rows.capacity() * static_cast<std::size_t>(sc.features.cols));
  rs.geometry = sc.features.geometry();
  rs.line_params.fire_n = sc.features.contact_threshold;  // the features' own firing threshold
  rs.state = world_.state();
  rs.ss = rs.state.status;
  rs.est_wrench.configure(sc.wrench_error, sc.seed, sc.faults);  // validated by loadScene
  rs.est_wrench.start(rs.state);
  rs.cmd = rs.state.command_g;  // the initial command (dynamics may start at its equilibrium, off it)
  // The arm at start: its image for the first acquisition, its ground truth.
  if (schedule_.fires().wts) world_.acquireForces(rs.forces, rs.acq);
  fillTruth(rs.state, rs.acq, rs.truth);
  Summary& sum = out.summary;
  sum.scene = sc.name;
  sum.controller = toString(sc.controller);
  sum.seed = sc.seed;
  sum.fidelity = toString(sc.world.fidelity);
  rs.robot.commandable = true;
}

void Runner::sensorCycle(double t, const StageFires& fi, RunState& rs) {
  // WTS acquisition (Table 2: 140 Hz): the sensor's electronics; the frame
  // reaches the reader at once or, with a transfer delay, when it has arrived.
  if ((fi.wts && response_.acquire(rs.forces, t, rs.raw)) || (response_.delayed() && response_.deliver(t, rs.raw))) {
    rs.raw.seq = rs.raw_seq++;
    rs.raw.device_time_ms = static_cast<uint32_t>(std::llround(rs.raw.time_s * 1000.0));
    rs.new_raw = true;
  }
  if (fi.features && rs.new_raw) {  // calibration + features on the latest frame (200 Hz)
    bool frame_ok = false;
    sensor_.step(rs.raw, rs.frame, rs.feats, frame_ok);
    rs.new_raw = false;
  }
}

EndReason Runner::servoCycle(double t, RunState& rs, RunResult& out) {
  // Tactile servo (100 Hz).
  servo_.setMeasuredPose(rs.state.flange_g);
  Wrench wrench;  // the arm's estimated wrench, as the RTT arm publishes it
  rs.est_wrench.fill(rs.state, wrench);
  servo_.setEstimatedWrench(wrench);
  for (int j = 0; j < kArmJoints; ++j) rs.robot.q[static_cast<std::size_t>(j)] = rs.state.q(j);
  servo_.setRobotState(rs.robot);
  if (servo_.step(t, rs.feats, rs.sout, rs.st)) rs.cmd = rs.sout.command.pose;
  logServoCycle(t, rs, out);
  return end_.afterServo(rs.st);
}

void Runner::logServoCycle(double t, RunState& rs, RunResult& out) const {
  const Scene& sc = scene_;
  const ContactFeatures& feats = rs.feats;
  const int ph = servo_.servo().phaseIndex();
  const PhaseParams& pp = servo_.servo().phase(ph);
  if (ph != rs.last_phase) {
    out.snapshots.push_back({t, "enter " + pp.name, rs.frame});
    rs.last_phase = ph;
  }
  if (!rs.first_contact_snap && feats.contact != ContactType::None) {
    out.snapshots.push_back({t, "first contact", rs.frame});
    rs.first_contact_snap = true;
  }
  out.rows.push_back(makeRow(sc, t, ph, rs.st, feats, rs.cmd, rs.truth, rs.sout.u_s, rs.sout.beta));
  out.rows.back().slide_speed = rs.sout.slide_speed;
  out.rows.back().speed_limiter = static_cast<int>(rs.sout.speed_limiter);
  out.rows.back().speed_inputs = rs.sout.speed_inputs;
  out.rows.back().joint_margin = servo_.servo().program().signals().joint_margin;
  out.rows.back().force_wrench = rs.sout.force_wrench;
  out.rows.back().force_correction = rs.sout.force_correction;
  out.rows.back().force_demand = rs.sout.force_demand;
  if (feats.contact == ContactType::Edge && std::fabs(feats.dzmp_y) > rs.worst_dzmp) {
    rs.worst_dzmp = std::fabs(feats.dzmp_y);
    rs.worst.t = t;
    rs.worst.frame = rs.frame;
  }
  if ((pp.requires_contact || pp.terminal) && feats.contact != ContactType::None) {
    // The controller's own data: the measured flange pose, the sensor
    // mount and the CoP (the truth beside it, for evaluation only).
    const KDL::Frame T_gs = toFrame(rs.state.flange_g) * sc.servo.sensor_mount;
    const KDL::Vector p = T_gs * KDL::Vector(feats.cop_x, feats.cop_y, 0.0);
    out.contacts.push_back({t, {p.x(), p.y(), p.z()}, rs.acq.contact_point_g, feats.lambda1, ph});
    const int n = edgeLinePoints(rs.frame, rs.geometry, rs.line_params, rs.line);
    for (int i = 0; i < n && out.edge_points.size() < out.edge_points.capacity(); ++i) {
      const KDL::Vector q =
          T_gs * KDL::Vector(rs.line[static_cast<std::size_t>(i)].x, rs.line[static_cast<std::size_t>(i)].y, 0.0);
      out.edge_points.push_back({t, {q.x(), q.y(), q.z()}, ph});
    }
  }
}

void Runner::physicsCycle(double t, const fri::KrcScript::At& krc_now, RunState& rs, Summary& sum) {
  // The arm: one physics step toward the latest command.
  // Not commandable: the KRC keeps the set point it has.
  Pose applied = rs.robot.commandable ? rs.cmd : rs.state.command_g;
  if (scene_.through_fri) {
    PoseCommand desired = rs.sout.command;
    desired.pose = rs.cmd;
    desired.time_s = t;
    KDL::Frame f;
    if (friCycle(rs.state, krc_now, desired, t, f, rs.robot, sum)) applied = toPose(f);
    else applied = rs.state.command_g;  // no packet: the KRC keeps its last set point
  }
  rs.ss = world_.step(applied, schedule_.dt(), rs.state);
  if (rs.ss == SimStatus::NotConverged)
    sum.sim_unconverged_max_residual = std::max(sum.sim_unconverged_max_residual, rs.state.solver_residual);
  schedule_.advance();
  if (schedule_.fires().wts) world_.acquireForces(rs.forces, rs.acq);  // the image of the next acquisition
  fillTruth(rs.state, rs.acq, rs.truth);
}

void Runner::finishRun(EndReason end, const RunState& rs, RunResult& out) {
  Summary& sum = out.summary;
  if (rs.worst_dzmp >= 0.0) out.snapshots.push_back(rs.worst);
  out.snapshots.push_back({rs.state.time_s, "end", rs.frame});
  applyEnd(end, rs.ss, sum);
  sum.sim_unconverged_steps = end_.unconvergedSteps();
  sum.sim_time_s = rs.state.time_s;
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
