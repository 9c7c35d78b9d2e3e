#include "tactile_fri/wrench_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include <Eigen/Dense>

#include "tactile_config/cli_args.hpp"

namespace tactile {
namespace fri {

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

using config::fmt;  // printf into a std::string

std::string vec(const KDL::Vector& v, double scale = 1.0, const char* f = "%.2f") {
  std::string s = "[";
  for (int i = 0; i < 3; ++i) {
    std::string x = fmt(f, scale * v(i));
    if (x.find_first_not_of("-0.") == std::string::npos && x[0] == '-') x.erase(0, 1);  // no "-0.00"
    s += (i ? ", " : "") + x;
  }
  return s + "]";
}

double angleDeg(const KDL::Vector& a, const KDL::Vector& b) {
  const double n = a.Norm() * b.Norm();
  if (!(n > 0.0)) return 180.0;
  return std::acos(std::max(-1.0, std::min(1.0, KDL::dot(a, b) / n))) * kRadToDeg;
}

KDL::Vector force(const std::array<double, 6>& w) { return KDL::Vector(w[0], w[1], w[2]); }
KDL::Vector moment(const std::array<double, 6>& w) { return KDL::Vector(w[3], w[4], w[5]); }

}  // namespace

// ---- recordings ---------------------------------------------------------------

void writeRecordingHeader(FILE* f) {
  std::fprintf(f, "t_s,state,quality,r11,r12,r13,x,r21,r22,r23,y,r31,r32,r33,z,fx,fy,fz,tx,ty,tz\n");
}

void writeRecordingLine(FILE* f, double t_s, const MsrPacket& m) {
  std::fprintf(f, "%.4f,%u,%u", t_s, unsigned(m.intf.state), unsigned(m.intf.quality));
  for (float v : m.data.msr_cart_pos) std::fprintf(f, ",%.7g", double(v));
  for (double v : toWrench(m.data.est_ext_tcp_ft)) std::fprintf(f, ",%.7g", v);
  std::fprintf(f, "\n");
}

ConfigResult readRecording(const std::string& file, std::vector<WrenchSample>& out) {
  std::ifstream in(file);
  if (!in) return ConfigResult::failure(file + ": cannot read (a recording of fri_check --monitor --record)");
  out.clear();
  std::string line;
  for (int ln = 1; std::getline(in, line); ++ln) {
    if (line.empty() || line[0] == '#' || line.rfind("t_s,", 0) == 0) continue;
    double v[21];
    const char* p = line.c_str();
    int n = 0;
    for (; n < 21; ++n) {
      char* end = nullptr;
      v[n] = std::strtod(p, &end);
      if (end == p || !std::isfinite(v[n])) break;
      p = end;
      if (*p == ',') ++p;
    }
    if (n != 21 || *p != '\0')
      return ConfigResult::failure(file + ":" + std::to_string(ln) +
                                   ": expected 21 numbers (t_s, state, quality, msrCartPos 12, wrench 6)");
    float pose[kCartFrameDim];
    for (int i = 0; i < kCartFrameDim; ++i) pose[i] = static_cast<float>(v[3 + i]);
    if (!validFriPose(pose)) return ConfigResult::failure(file + ":" + std::to_string(ln) + ": msrCartPos is not a pose");
    WrenchSample s;
    toFrame(pose, s.pose);
    for (std::size_t i = 0; i < 6; ++i) s.w[i] = v[15 + i];
    out.push_back(s);
  }
  if (out.empty()) return ConfigResult::failure(file + ": no measurement (was the KRC sending?)");
  return ConfigResult::success();
}

ConfigResult restMean(const std::string& file, const std::vector<WrenchSample>& s, RestMean& out) {
  if (s.empty()) return ConfigResult::failure(file + ": no measurement");
  RestMean m;
  m.file = file;
  m.pose = s.front().pose;
  double dp = 0.0, dr = 0.0;  // the largest excursion from the first pose
  for (const WrenchSample& x : s) {
    KDL::Vector axis;
    dp = std::max(dp, (x.pose.p - m.pose.p).Norm());
    dr = std::max(dr, rotationAngle(m.pose.M.Inverse() * x.pose.M, axis));
    for (std::size_t i = 0; i < 6; ++i) m.w[i] += x.w[i];
  }
  if (dp > kStillM || dr > kStillRad)
    return ConfigResult::failure(fmt("%s: the arm moved %.1f mm / %.3f rad during the recording (at most %.0f mm / "
                                     "%.2f rad): record again with the arm still",
                                     file.c_str(), dp * 1e3, dr, kStillM * 1e3, kStillRad));
  m.samples = s.size();
  for (double& v : m.w) v /= double(s.size());
  double ss = 0.0;
  for (const WrenchSample& x : s) ss += (force(x.w) - force(m.w)).Norm() * (force(x.w) - force(m.w)).Norm();
  m.force_sd_n = std::sqrt(ss / double(s.size()));
  out = m;
  return ConfigResult::success();
}

// ---- the known weight ---------------------------------------------------------

const char* toString(WeightVerdict v) {
  switch (v) {
    case WeightVerdict::Correct: return "frame correct";
    case WeightVerdict::WrongFrame: return "wrong frame";
    case WeightVerdict::SignInverted: return "sign inverted";
    case WeightVerdict::WrongFrameAndSign: return "wrong frame and sign inverted";
    case WeightVerdict::MagnitudeOff: return "magnitude off";
    case WeightVerdict::Undetermined: return "undetermined";
  }
  return "?";
}

namespace {

/// The verdict's lines: what the best reading says and what to change.
void advise(WeightResult& r, WrenchFrame configured) {
  const char* got = toString(r.frame);
  const char* want = toString(configured);
  const char* krl = r.frame == WrenchFrame::Base ? "#TOOL" : "#BASE";
  const char* krl_got = r.frame == WrenchFrame::Base ? "#BASE" : "#TOOL";
  switch (r.verdict) {
    case WeightVerdict::Correct:
      r.lines.push_back(fmt("verdict: frame correct (the KRC sends estExtTcpFT in %s axes, as fri.wrench_frame: %s "
                            "says; sign right; magnitude %.1f %% of m g)", got, want, 100.0 * r.ratio));
      break;
    case WeightVerdict::WrongFrame:
      r.lines.push_back(fmt("verdict: frame is %s not %s (the KRC sends estExtTcpFT in %s axes, fri.wrench_frame says "
                            "%s)", got, want, got, want));
      r.lines.push_back(fmt("  change: $STIFFNESS.FRAMETYPE = %s in krc/TactileServo.src (it is %s on this KRC), or "
                            "fri.wrench_frame: %s in fri.yaml; then krc/check_krc_config.py must agree and this "
                            "check pass", krl, krl_got, got));
      break;
    case WeightVerdict::SignInverted:
    case WeightVerdict::WrongFrameAndSign:
      r.lines.push_back(fmt("verdict: sign inverted%s (the force reads against the weight's, in %s axes)",
                            r.verdict == WeightVerdict::WrongFrameAndSign ? " and frame is not the configured one" : "",
                            got));
      r.lines.push_back("  change: first --direction (a hanging weight pulls along gravity, base 0,0,-1); if it was "
                        "right, no fri.yaml or $STIFFNESS setting reverses estExtTcpFT: do not run the servo (its "
                        "force watchdog would read a press as a pull), report it with this output");
      if (r.verdict == WeightVerdict::WrongFrameAndSign)
        r.lines.push_back(fmt("  and the frame: $STIFFNESS.FRAMETYPE = %s or fri.wrench_frame: %s", krl, got));
      break;
    case WeightVerdict::MagnitudeOff:
      r.lines.push_back(fmt("verdict: magnitude off (frame %s and sign right, but |force| = %.2f N is %.1f %% of m g "
                            "= %.2f N, tolerance %.0f %%)", got, r.measured.Norm(), 100.0 * r.ratio,
                            r.expected_base.Norm(), 100.0 * kMagnitudeTol));
      r.lines.push_back("  change: check --mass (the weight with its hook), that it hangs free, and the load data "
                        "(fri_check --load-data, the next step); the tare removes a load error only in its own pose");
      break;
    case WeightVerdict::Undetermined: break;
  }
}

}  // namespace

WeightResult checkKnownWeight(const RestMean& tare, const RestMean& loaded, const KnownWeight& kw,
                              WrenchFrame configured) {
  WeightResult r;
  const KDL::Rotation& R = loaded.pose.M;
  const double mg = kw.mass_kg * kGravityMps2;
  const KDL::Vector d = kw.dir / kw.dir.Norm();
  r.expected_base = kw.dir_in_tool ? R * d * mg : d * mg;
  r.expected_tool = R.Inverse() * r.expected_base;
  r.measured = force(loaded.w) - force(tare.w);
  r.ratio = r.measured.Norm() / mg;
  r.lines.push_back(fmt("weight: %.3f kg, m g = %.2f N; expected force in base axes %s N, in tool axes %s N",
                        kw.mass_kg, mg, vec(r.expected_base).c_str(), vec(r.expected_tool).c_str()));
  r.lines.push_back(fmt("measured: tare %s N (%zu samples, sd %.2f N), loaded %s N (%zu samples, sd %.2f N): "
                        "change %s N, |change| %.2f N", vec(force(tare.w)).c_str(), tare.samples, tare.force_sd_n,
                        vec(force(loaded.w)).c_str(), loaded.samples, loaded.force_sd_n, vec(r.measured).c_str(),
                        r.measured.Norm()));
  KDL::Vector pred[2][2];
  int bf = 0, bs = 0;
  for (int f = 0; f < 2; ++f) {
    for (int s = 0; s < 2; ++s) {
      pred[f][s] = (f == 0 ? r.expected_base : r.expected_tool) * (s == 0 ? 1.0 : -1.0);
      r.angle_deg[f][s] = angleDeg(r.measured, pred[f][s]);
      if (r.angle_deg[f][s] < r.angle_deg[bf][bs]) bf = f, bs = s;
    }
  }
  r.separation_deg = 180.0;
  for (int f = 0; f < 2; ++f)
    for (int s = 0; s < 2; ++s)
      if (f != bf || s != bs) r.separation_deg = std::min(r.separation_deg, angleDeg(pred[bf][bs], pred[f][s]));
  r.lines.push_back(fmt("readings (angle to the change): base(+) %.1f deg, base(-) %.1f deg, tool(+) %.1f deg, "
                        "tool(-) %.1f deg; best %s(%s), %.1f deg from the nearest other reading",
                        r.angle_deg[0][0], r.angle_deg[0][1], r.angle_deg[1][0], r.angle_deg[1][1],
                        bf == 0 ? "base" : "tool", bs == 0 ? "+" : "-", r.separation_deg));
  r.frame = bf == 0 ? WrenchFrame::Base : WrenchFrame::Tool;
  r.sign = bs == 0 ? 1 : -1;
  KDL::Vector axis;
  const double moved_m = (loaded.pose.p - tare.pose.p).Norm();
  const double moved_rad = rotationAngle(tare.pose.M.Inverse() * loaded.pose.M, axis);
  if (moved_m > 0.02 || moved_rad > 0.1) {
    r.lines.push_back(fmt("verdict: undetermined (the arm moved %.1f mm / %.3f rad between the tare and the loaded "
                          "recording: record both in one pose)", moved_m * 1e3, moved_rad));
  } else if (r.ratio < kMinForceRatio) {
    r.lines.push_back(fmt("verdict: undetermined (the force changed by %.2f N, under %.0f %% of m g: the weight was not "
                          "on the pad during the loaded recording, or the KRC does not report estExtTcpFT)",
                          r.measured.Norm(), 100.0 * kMinForceRatio));
  } else if (r.separation_deg < kMinSeparationDeg) {
    r.lines.push_back(fmt("verdict: undetermined (in this pose two readings lie %.1f deg apart, under %.0f deg: "
                          "tilt the flange so that the pad faces sideways, e.g. A = 0, B = 90, C = 180 on the "
                          "pendant, and record the tare and the weight again)", r.separation_deg, kMinSeparationDeg));
  } else if (r.angle_deg[bf][bs] > kMaxAngleDeg) {
    r.lines.push_back(fmt("verdict: undetermined (no reading fits: the best is %.1f deg off, more than %.0f deg: "
                          "check --direction, that nothing but the weight touches the pad, and the tare)",
                          r.angle_deg[bf][bs], kMaxAngleDeg));
  } else {
    const bool frame_ok = r.frame == configured, sign_ok = r.sign > 0;
    r.verdict = frame_ok && sign_ok ? (std::fabs(r.ratio - 1.0) > kMagnitudeTol ? WeightVerdict::MagnitudeOff
                                                                                : WeightVerdict::Correct)
                : sign_ok ? WeightVerdict::WrongFrame
                : frame_ok ? WeightVerdict::SignInverted : WeightVerdict::WrongFrameAndSign;
    advise(r, configured);
  }
  return r;
}

// ---- the load data ------------------------------------------------------------

const char* toString(LoadVerdict v) {
  switch (v) {
    case LoadVerdict::Ok: return "load data OK";
    case LoadVerdict::MassOff: return "mass off";
    case LoadVerdict::ComOff: return "CoM off";
    case LoadVerdict::MassAndComOff: return "mass and CoM off";
    case LoadVerdict::Undetermined: return "undetermined";
  }
  return "?";
}

namespace {

constexpr int kUnknowns = 10;  // dm, s (3), b_f (3), b_t (3)
constexpr double kMinComMassKg = 0.05;  // below this fitted mass its centre is not placed

/// Rows 6i..6i+5 of the fit: f_e = dm g_e + b_f, t_e = s x g_e + b_t (flange axes).
void fillRows(const RestMean& m, WrenchFrame frame, int i, Eigen::MatrixXd& A, Eigen::VectorXd& b) {
  const KDL::Rotation Rt = m.pose.M.Inverse();
  const KDL::Vector g = Rt * KDL::Vector(0.0, 0.0, -kGravityMps2);
  const KDL::Vector f = frame == WrenchFrame::Tool ? force(m.w) : Rt * force(m.w);
  const KDL::Vector t = frame == WrenchFrame::Tool ? moment(m.w) : Rt * moment(m.w);
  const int r = 6 * i;
  for (int k = 0; k < 3; ++k) {
    A(r + k, 0) = g(k);
    A(r + k, 4 + k) = 1.0;
    A(r + 3 + k, 7 + k) = 1.0;
    b(r + k) = f(k);
    b(r + 3 + k) = t(k);
  }
  // s x g = -g x s: -[g]x
  A(r + 3, 2) = g.z(), A(r + 3, 3) = -g.y();
  A(r + 4, 1) = -g.z(), A(r + 4, 3) = g.x();
  A(r + 5, 1) = g.y(), A(r + 5, 2) = -g.x();
}

void adviseLoad(LoadResult& r, const LoadModel& model, double mass_tol, double com_tol) {
  const bool mass_off = std::fabs(r.dm_kg) > mass_tol;
  const bool com_off = r.com_known && (r.com_m - model.com_m).Norm() > com_tol;
  r.verdict = mass_off ? (com_off ? LoadVerdict::MassAndComOff : LoadVerdict::MassOff)
                       : (com_off ? LoadVerdict::ComOff : LoadVerdict::Ok);
  if (r.verdict == LoadVerdict::Ok) {
    r.lines.push_back(fmt("verdict: load data OK (mass within %.3f kg%s)", mass_tol,
                          r.com_known ? fmt(", centre of mass within %.0f mm", com_tol * 1e3).c_str() : ""));
    return;
  }
  r.lines.push_back(fmt("verdict: %s%s%s", mass_off ? fmt("mass off by %+.3f kg", r.dm_kg).c_str() : "",
                        mass_off && com_off ? ", " : "",
                        com_off ? fmt("CoM off by %.1f mm", (r.com_m - model.com_m).Norm() * 1e3).c_str() : ""));
  std::string change = "  change: in the sensor's parameter file pad: ";
  if (mass_off) change += fmt("pad_mass_kg: %.3f", r.mass_kg);
  if (com_off) change += fmt("%spad_com_m: [%.4f, %.4f, %.4f]", mass_off ? ", " : "", r.com_m.x(), r.com_m.y(), r.com_m.z());
  change += ", and the same in krc/TactileServo.dat TS_PAD_LOAD (";
  if (mass_off) change += fmt("M %.3f", r.mass_kg);
  if (com_off) change += fmt("%sCM {X %.1f, Y %.1f, Z %.1f} mm", mass_off ? ", " : "", 1e3 * r.com_m.x(),
                             1e3 * r.com_m.y(), 1e3 * r.com_m.z());
  r.lines.push_back(change + "); krc/check_krc_config.py compares the two; weigh the pad to confirm");
}

}  // namespace

LoadResult fitLoad(const std::vector<RestMean>& rests, WrenchFrame frame, const LoadModel& model, double mass_tol_kg,
                   double com_tol_m) {
  LoadResult r;
  const int n = static_cast<int>(rests.size());
  if (n < 3) {
    r.lines.push_back(fmt("verdict: undetermined (%d recording(s): at least 3 orientations at rest)", n));
    return r;
  }
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6 * n, kUnknowns);
  Eigen::VectorXd b(6 * n);
  for (int i = 0; i < n; ++i) fillRows(rests[static_cast<std::size_t>(i)], frame, i, A, b);
  // columns scaled to unit norm: the conditioning compares orientations, not units
  Eigen::VectorXd scale = A.colwise().norm().transpose();
  for (int j = 0; j < kUnknowns; ++j) scale(j) = scale(j) > 0.0 ? 1.0 / scale(j) : 1.0;
  const Eigen::MatrixXd As = A * scale.asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(As, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  r.conditioning = sv(sv.size() - 1) / sv(0);
  const Eigen::VectorXd x = scale.asDiagonal() * svd.solve(b);
  const Eigen::VectorXd res = A * x - b;
  double sf = 0.0, st = 0.0;
  for (int i = 0; i < n; ++i) sf += res.segment(6 * i, 3).squaredNorm(), st += res.segment(6 * i + 3, 3).squaredNorm();
  r.rms_force_n = std::sqrt(sf / n);
  r.rms_moment_nm = std::sqrt(st / n);
  r.dm_kg = x(0);
  r.s = KDL::Vector(x(1), x(2), x(3));
  r.bias_f = KDL::Vector(x(4), x(5), x(6));
  r.bias_t = KDL::Vector(x(7), x(8), x(9));
  r.mass_kg = model.mass_kg + r.dm_kg;
  r.com_known = r.mass_kg > kMinComMassKg;
  if (r.com_known) r.com_m = (model.com_m * model.mass_kg + r.s) / r.mass_kg;
  for (const RestMean& m : rests) {
    const KDL::Vector z = m.pose.M.UnitZ();
    r.lines.push_back(fmt("at rest: %s: %zu samples, flange z in base %s, force %s N, moment %s N m (as sent)",
                          m.file.c_str(), m.samples, vec(z).c_str(), vec(force(m.w)).c_str(),
                          vec(moment(m.w), 1.0, "%.3f").c_str()));
  }
  r.lines.push_back(fmt("fit over %d orientations (conditioning %.3f, at least %.2f): mass %.3f kg (modelled %.3f, "
                        "error %+.3f), centre of mass %s mm (modelled %s mm), offsets %s N, %s N m, residual rms "
                        "%.2f N, %.3f N m", n, r.conditioning, kMinConditioning, r.mass_kg, model.mass_kg, r.dm_kg,
                        r.com_known ? vec(r.com_m, 1e3, "%.1f").c_str() : "(mass too small to place)",
                        vec(model.com_m, 1e3, "%.1f").c_str(), vec(r.bias_f).c_str(),
                        vec(r.bias_t, 1.0, "%.3f").c_str(), r.rms_force_n, r.rms_moment_nm));
  if (r.conditioning < kMinConditioning) {
    r.lines.push_back("verdict: undetermined (the orientations are too alike: tilt the flange by 45 deg or more "
                      "between them, not only turn A6; docs/bringup.md)");
    return r;
  }
  adviseLoad(r, model, mass_tol_kg, com_tol_m);
  return r;
}

}  // namespace fri
}  // namespace tactile
