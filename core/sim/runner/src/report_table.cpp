#include "tactile_sim_runner/report_table.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "tactile_sim_runner/loop.hpp"

namespace tactile {
namespace sim {

namespace {

template <typename E>
bool enumByName(const std::string& s, int last, E& out) {
  for (int v = 0; v <= last; ++v)
    if (s == toString(static_cast<E>(v))) {
      out = static_cast<E>(v);
      return true;
    }
  return false;
}

struct Columns {
  std::unordered_map<std::string, std::size_t> index;
  std::string missing;
  std::size_t operator()(const std::string& name) {
    const auto it = index.find(name);
    if (it == index.end()) {
      if (missing.empty()) missing = name;
      return 0;
    }
    return it->second;
  }
};

}  // namespace

ConfigResult readReportTable(const std::string& path, const Scene& scene, RunResult& out) {
  std::ifstream in(path);
  if (!in) return ConfigResult::failure(path + ": cannot open the reporter's table");
  std::string line;
  if (!std::getline(in, line)) return ConfigResult::failure(path + ": empty (no header line)");
  Columns col;
  {
    std::istringstream hs(line);
    std::string name;
    for (std::size_t i = 0; hs >> name; ++i) col.index.emplace(name, i);
  }
  const std::string F = "Features.features.", T = "Robot.truth.", C = "Servo.pose_command.pose.";
  const std::size_t c_t = col("Servo.phase.time_s"), c_phase = col("Servo.phase.index"), c_status = col("Servo.phase.status");
  const std::size_t c_ft = col(F + "time_s"), c_seq = col(F + "seq"), c_cop = col(F + "cop_x"), c_area = col(F + "area"),
                    c_contact = col(F + "contact"), c_fstatus = col(F + "status");
  const std::size_t c_cmd_p = col(C + "p.Element0"), c_cmd_q = col(C + "q.Element0");
  const std::size_t c_wrench = col(T + "wrench_s.Element0"), c_layer = col(T + "layer_force"),
                    c_housing = col(T + "housing_force"), c_pitch = col(T + "tray_pitch"), c_roll = col(T + "tray_roll"),
                    c_cp = col(T + "contact_point_g.Element0"), c_inc = col(T + "in_contact"),
                    c_sp = col(T + "sensor_pose.p.Element0"), c_sq = col(T + "sensor_pose.q.Element0"),
                    c_sim = col(T + "sim_status"), c_truth_t = col(T + "time_s");
  if (!col.missing.empty())
    return ConfigResult::failure(path + ": no column '" + col.missing +
                                 "' (report Servo.phase, Servo.pose_command, Features.features and Robot.truth with "
                                 "ComplexDecompose = true)");
  // The features' doubles in their declaration order (types.hpp): cop_x .. max_taxel.
  const char* kFeatureDoubles[] = {"cop_x", "cop_y", "coc_x", "coc_y", "dzmp_x", "dzmp_y", "alpha_z",
                                   "force", "d_z",   "lambda1", "lambda2", "max_taxel"};
  std::size_t c_fd[12];
  for (int k = 0; k < 12; ++k) c_fd[k] = col(F + kFeatureDoubles[k]);
  (void)c_cop;

  out.rows.clear();
  std::vector<std::string> v;
  int lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    v.clear();
    for (std::string tok; ls >> tok;) v.push_back(tok);
    if (v.empty()) continue;
    if (v.size() != col.index.size())
      return ConfigResult::failure(path + ":" + std::to_string(lineno) + ": " + std::to_string(v.size()) +
                                   " values for " + std::to_string(col.index.size()) + " columns");
    auto d = [&](std::size_t c) { return std::strtod(v[c].c_str(), nullptr); };
    ServoStatus st = ServoStatus::NotConfigured;
    if (!enumByName(v[c_status], static_cast<int>(kLastServoStatus), st))
      return ConfigResult::failure(path + ":" + std::to_string(lineno) + ": unknown servo status '" + v[c_status] + "'");
    ContactFeatures f;
    f.time_s = d(c_ft);
    f.seq = static_cast<uint32_t>(d(c_seq));
    double* fd[12] = {&f.cop_x, &f.cop_y, &f.coc_x, &f.coc_y, &f.dzmp_x, &f.dzmp_y, &f.alpha_z,
                      &f.force, &f.d_z,   &f.lambda1, &f.lambda2, &f.max_taxel};
    for (int k = 0; k < 12; ++k) *fd[k] = d(c_fd[k]);
    f.area = static_cast<uint16_t>(d(c_area));
    if (!enumByName(v[c_contact], static_cast<int>(kLastContactType), f.contact) ||
        !enumByName(v[c_fstatus], static_cast<int>(kLastFeatureStatus), f.status))
      return ConfigResult::failure(path + ":" + std::to_string(lineno) + ": unknown contact type or feature status");
    Pose cmd;
    for (std::size_t k = 0; k < 3; ++k) cmd.p[k] = d(c_cmd_p + k);
    for (std::size_t k = 0; k < 4; ++k) cmd.q[k] = d(c_cmd_q + k);
    SimTruth truth;
    truth.time_s = d(c_truth_t);
    for (std::size_t k = 0; k < 6; ++k) truth.wrench_s[k] = d(c_wrench + k);
    truth.layer_force = d(c_layer);
    truth.housing_force = d(c_housing);
    truth.tray_pitch = d(c_pitch);
    truth.tray_roll = d(c_roll);
    for (std::size_t k = 0; k < 3; ++k) truth.contact_point_g[k] = d(c_cp + k);
    truth.in_contact = v[c_inc] == "1" || v[c_inc] == "true";
    for (std::size_t k = 0; k < 3; ++k) truth.sensor_pose.p[k] = d(c_sp + k);
    for (std::size_t k = 0; k < 4; ++k) truth.sensor_pose.q[k] = d(c_sq + k);
    truth.sim_status = static_cast<int>(d(c_sim));
    // The servo's clock is the simulated time (tactile::SimClock): the row's t.
    out.rows.push_back(makeRow(scene, d(c_t), static_cast<int>(d(c_phase)), st, f, cmd, truth));
  }
  if (out.rows.empty()) return ConfigResult::failure(path + ": no samples after the header");
  out.phases = phaseEntries(scene, out.rows);
  return ConfigResult::success();
}

}  // namespace sim
}  // namespace tactile
