#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "tactile_sim_runner/runner.hpp"

namespace tactile {
namespace sim {

namespace {

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

// Appends ",<v>" formatted exactly as printf("%.9g") (std::to_chars with a
// precision is specified as printf's conversion) but several times faster:
// the timeseries is ~50 columns per servo cycle.
void appendG9(std::string& line, double v) {
  char b[40];
  b[0] = ',';
  const auto res = std::to_chars(b + 1, b + sizeof b, v, std::chars_format::general, 9);
  line.append(b, static_cast<std::size_t>(res.ptr - b));
}

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o;
}

}  // namespace

std::string summaryJson(const Scene& sc, const RunResult& r) {
  const Summary& s = r.summary;
  std::ostringstream o;
  o << "{\n";
  o << "  \"scene\": \"" << esc(s.scene) << "\",\n";
  o << "  \"scene_file\": \"" << esc(sc.file) << "\",\n";
  o << "  \"figure\": \"" << esc(sc.figure) << "\",\n";
  o << "  \"controller\": \"" << s.controller << "\",\n";
  o << "  \"fidelity\": \"" << s.fidelity << "\",\n";
  o << "  \"seed\": " << s.seed << ",\n";
  o << "  \"status\": \"" << s.status << "\",\n";
  o << "  \"exit_code\": " << s.exit_code << ",\n";
  o << "  \"fault_time_s\": " << num(s.fault_time_s) << ",\n";
  o << "  \"rates_hz\": {\"sim\": " << num(sc.rates.sim) << ", \"servo\": " << num(sc.rates.servo)
    << ", \"wts\": " << num(sc.rates.wts) << ", \"features\": " << num(sc.rates.features) << "},\n";
  o << "  \"subsamples\": " << sc.world.pad.subsamples << ",\n";
  o << "  \"sim_time_s\": " << num(s.sim_time_s) << ",\n";
  o << "  \"wall_time_s\": " << num(s.wall_time_s) << ",\n";
  o << "  \"real_time_factor\": " << num(s.real_time_factor) << ",\n";
  o << "  \"phases\": [";
  for (std::size_t i = 0; i < r.phases.size(); ++i)
    o << (i ? ", " : "") << "{\"name\": \"" << esc(r.phases[i].name) << "\", \"t_enter\": " << num(r.phases[i].t_enter)
      << "}";
  o << "],\n";
  o << "  \"contact_lost_count\": " << s.contact_lost_count << ",\n";
  o << "  \"force_true_mean_n\": " << num(s.force_true_mean_n) << ",\n";
  o << "  \"force_true_max_n\": " << num(s.force_true_max_n) << ",\n";
  o << "  \"force_true_rms_error_n\": " << num(s.force_true_rms_error_n) << ",\n";
  o << "  \"force_true_in_band_fraction\": " << num(s.force_true_in_band_fraction) << ",\n";
  o << "  \"force_scored_s\": " << num(s.force_scored_s) << ",\n";
  o << "  \"force_true_in_band_s\": " << num(s.force_true_in_band_s) << ",\n";
  o << "  \"alignment_time_s\": " << num(s.alignment_time_s) << ",\n";
  // The scored window's path and speed under their own names, and under the
  // names the sweeps read (path_length_m, slide_speed_mps: the same values).
  o << "  \"scored_path_m\": " << num(s.path_length_m) << ",\n";
  o << "  \"scored_duration_s\": " << num(s.scored_duration_s) << ",\n";
  o << "  \"scored_mean_speed_mps\": " << num(s.slide_speed_mps) << ",\n";
  o << "  \"path_length_m\": " << num(s.path_length_m) << ",\n";
  o << "  \"slide_speed_mps\": " << num(s.slide_speed_mps) << ",\n";
  // The whole slide, transients included.
  o << "  \"slide_path_m\": " << num(s.slide_path_m) << ",\n";
  o << "  \"slide_duration_s\": " << num(s.slide_duration_s) << ",\n";
  o << "  \"slide_mean_speed_mps\": " << num(s.slide_mean_speed_mps) << ",\n";
  o << "  \"slide_force_true_mean_n\": " << num(s.slide_force_true_mean_n) << ",\n";
  o << "  \"slide_force_true_max_n\": " << num(s.slide_force_true_max_n) << ",\n";
  o << "  \"slide_force_true_rms_error_n\": " << num(s.slide_force_true_rms_error_n) << ",\n";
  o << "  \"slide_force_true_in_band_fraction\": " << num(s.slide_force_true_in_band_fraction) << ",\n";
  o << "  \"dzmp_final_m\": " << num(s.dzmp_final_m) << ",\n";
  o << "  \"dzmp_recovery_time_s\": " << num(s.dzmp_recovery_time_s) << ",\n";
  o << "  \"translation_x_m\": " << num(s.translation_x_m) << ",\n";
  o << "  \"tray_angle_max_deg\": " << num(s.tray_angle_max_deg) << ",\n";
  o << "  \"through_fri\": " << (sc.through_fri ? "true" : "false") << ",\n";
  o << "  \"fri_replies\": " << s.fri_replies << ",\n";
  o << "  \"fri_max_step_m\": " << num(s.fri_max_step_m) << ",\n";
  o << "  \"fri_max_step_rad\": " << num(s.fri_max_step_rad) << ",\n";
  o << "  \"sim_unconverged_steps\": " << s.sim_unconverged_steps << ",\n";
  o << "  \"sim_unconverged_max_residual\": " << num(s.sim_unconverged_max_residual) << ",\n";
  o << "  \"criteria_passed\": " << (s.criteria_failed.empty() ? "true" : "false") << ",\n";
  o << "  \"criteria_failed\": [";
  for (std::size_t i = 0; i < s.criteria_failed.size(); ++i) o << (i ? ", " : "") << "\"" << esc(s.criteria_failed[i]) << "\"";
  o << "]\n";
  o << "}\n";
  return o.str();
}

bool writeRun(const std::string& dir, const Scene& sc, const RunResult& r, std::string& error) {
  auto open = [&](const char* name) -> FILE* {
    FILE* f = std::fopen((dir + "/" + name).c_str(), "w");
    if (!f) error = "cannot write " + dir + "/" + name;
    return f;
  };
  FILE* f = open("timeseries.csv");
  if (!f) return false;
  std::fprintf(f,
               "time,phase,phase_name,servo_status,contact,feature_status,cmd_x,cmd_y,cmd_z,cmd_roll,cmd_pitch,cmd_yaw,"
               "act_x,act_y,act_z,act_roll,act_pitch,act_yaw,cop_x,cop_y,coc_x,coc_y,dzmp_x,dzmp_y,alpha_z,force,d_z,"
               "lambda1,lambda2,area,sd_cop_x,sd_cop_y,sd_d_z,sd_dzmp_x,sd_dzmp_y,sd_alpha_z,sd_force,force_true,"
               "force_layer,housing_force,moment_x_true,moment_y_true,tray_angle_deg,true_cx,true_cy,true_cz,u_x,u_y,"
               "u_z,u_wx,u_wy,u_wz,beta,feature_age,curvature,slide_speed,speed_limiter,law_force_error,law_force_rate,"
               "law_angle_rate,law_curvature,law_extent,law_excess,joint_margin,force_wrench,"
               "force_correction,force_demand\n");
  std::string line;
  for (const auto& w : r.rows) {
    const auto& ft = w.f;
    const std::string& pname =
        w.phase >= 0 && w.phase < static_cast<int>(r.phase_names.size()) ? r.phase_names[static_cast<std::size_t>(w.phase)] : "";
    std::fprintf(f, "%.4f,%d,%s,%s,%d,%s", w.t, w.phase, pname.c_str(), toString(w.servo), static_cast<int>(w.contact),
                 toString(w.feature_status));
    const double v[] = {w.cmd[0], w.cmd[1], w.cmd[2], w.cmd_rpy[0], w.cmd_rpy[1], w.cmd_rpy[2], w.act[0], w.act[1],
                        w.act[2], w.act_rpy[0], w.act_rpy[1], w.act_rpy[2], ft.cop_x, ft.cop_y, ft.coc_x, ft.coc_y,
                        ft.dzmp_x, ft.dzmp_y, ft.alpha_z, ft.force, ft.d_z, ft.lambda1, ft.lambda2,
                        static_cast<double>(ft.area), w.s_d(0), w.s_d(1), w.s_d(2), w.s_d(3), w.s_d(4), w.s_d(5),
                        w.sd_force, w.force_true, w.force_layer, w.housing_force, w.moment_x_true, w.moment_y_true,
                        w.tray_angle_deg, w.true_contact[0], w.true_contact[1], w.true_contact[2], w.u_s(0), w.u_s(1),
                        w.u_s(2), w.u_s(3), w.u_s(4), w.u_s(5), static_cast<double>(w.beta), w.feature_age,
                        ft.curvature, w.slide_speed, static_cast<double>(w.speed_limiter),
                        w.speed_inputs.force_error_n, w.speed_inputs.force_error_rate, w.speed_inputs.angle_rate,
                        w.speed_inputs.curvature, w.speed_inputs.extent_m, w.speed_inputs.wrench_excess_n,
                        w.joint_margin, w.force_wrench, w.force_correction, w.force_demand};
    line.clear();
    for (double x : v) appendG9(line, x);
    line += '\n';
    std::fwrite(line.data(), 1, line.size(), f);
  }
  std::fclose(f);

  if (!(f = open("snapshots.csv"))) return false;
  std::fprintf(f, "time,label");
  for (int i = 0; i < sc.features.rows * sc.features.cols; ++i) std::fprintf(f, ",t%d", i);
  std::fprintf(f, "\n");
  for (const auto& s : r.snapshots) {
    std::fprintf(f, "%.4f,%s", s.t, s.label.c_str());
    for (int i = 0; i < s.frame.size(); ++i) std::fprintf(f, ",%.4f", s.frame.force[static_cast<std::size_t>(i)]);
    std::fprintf(f, "\n");
  }
  std::fclose(f);

  if (!(f = open("contacts.csv"))) return false;
  std::fprintf(f, "time,x,y,z,true_x,true_y,true_z,lambda1,phase\n");
  for (const auto& c : r.contacts)
    std::fprintf(f, "%.4f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.4g,%d\n", c.t, c.p[0], c.p[1], c.p[2], c.truth[0], c.truth[1],
                 c.truth[2], c.lambda1, c.phase);
  std::fclose(f);

  if (!(f = open("edge_points.csv"))) return false;
  std::fprintf(f, "time,x,y,z,phase\n");
  for (const auto& e : r.edge_points) std::fprintf(f, "%.4f,%.6f,%.6f,%.6f,%d\n", e.t, e.p[0], e.p[1], e.p[2], e.phase);
  std::fclose(f);

  if (!(f = open("summary.json"))) return false;
  const std::string js = summaryJson(sc, r);
  std::fputs(js.c_str(), f);
  std::fclose(f);
  return true;
}

}  // namespace sim
}  // namespace tactile
