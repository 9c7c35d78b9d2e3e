// The loop's records: the ground truth of a cycle (fillTruth), a log row (makeRow) and the phase entries.
#include "tactile_sim_runner/loop.hpp"

#include <array>
#include <limits>

namespace tactile {
namespace sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::array<double, 3> rpyOf(const KDL::Rotation& R) {
  double r, p, y;
  R.GetRPY(r, p, y);
  return {r, p, y};
}

}  // namespace

void fillTruth(const SimState& st, const SensorTruth& acq, SimTruth& out) {
  out.time_s = st.time_s;
  out.wrench_s = st.wrench_s;
  out.layer_force = st.normal_force;
  out.housing_force = st.housing_force;
  out.tray_pitch = st.tray_pitch;
  out.tray_roll = st.tray_roll;
  out.contact_point_g = acq.contact_point_g;
  out.in_contact = acq.in_contact;
  out.sensor_pose = st.sensor_g;
  out.sim_status = static_cast<int>(st.status);
}

LogRow makeRow(const Scene& sc, double t, int phase, ServoStatus status, const ContactFeatures& f,
               const Pose& cmd, const SimTruth& truth, const Vec6& u_s, int beta) {
  LogRow row;
  const PhaseParams& pp = sc.servo.phases[static_cast<std::size_t>(phase)];
  row.t = t;
  row.phase = phase;
  row.servo = status;
  row.contact = f.contact;
  row.feature_status = f.status;
  const KDL::Frame T_cmd_s = toFrame(cmd) * sc.servo.sensor_mount;
  const KDL::Frame T_gs = toFrame(truth.sensor_pose);
  row.cmd = {T_cmd_s.p.x(), T_cmd_s.p.y(), T_cmd_s.p.z()};
  row.act = {T_gs.p.x(), T_gs.p.y(), T_gs.p.z()};
  row.cmd_rpy = rpyOf(T_cmd_s.M);
  row.act_rpy = rpyOf(T_gs.M);
  row.f = f;
  row.s_d = pp.s_d;
  row.sd_force = pp.s_d(kZ) / sc.servo.c_z;
  row.force_true = -truth.wrench_s[2];
  row.force_layer = truth.layer_force;
  row.housing_force = truth.housing_force;
  row.moment_x_true = truth.wrench_s[3];
  row.moment_y_true = truth.wrench_s[4];
  row.tray_angle_deg = truth.tray_roll * 180.0 / kPi;
  row.true_contact = truth.contact_point_g;
  row.true_in_contact = truth.in_contact;
  row.u_s = u_s;
  row.beta = beta;
  row.feature_age = f.status == FeatureStatus::NotConfigured ? kNaN : t - f.time_s;
  return row;
}

std::vector<PhaseEntry> phaseEntries(const Scene& sc, const std::vector<LogRow>& rows) {
  std::vector<PhaseEntry> out;
  int last = -1;
  for (const auto& r : rows)
    if (r.phase != last) {
      out.push_back({sc.servo.phases[static_cast<std::size_t>(r.phase)].name, r.t});
      last = r.phase;
    }
  return out;
}

}  // namespace sim
}  // namespace tactile
