// The arm's estimated wrench the force estimate reads: the true wrench at the flange (fillEstimatedWrench)
// plus the scene's wrench-error model (EstimatedWrench: scale, bias, drift, seeded noise) and its wrench faults.
#include "tactile_sim_runner/loop.hpp"

#include <cmath>
#include <cstdint>

namespace tactile {
namespace sim {

void fillEstimatedWrench(const SimState& st, Wrench& out) {
  const KDL::Wrench w_s(KDL::Vector(st.wrench_s[0], st.wrench_s[1], st.wrench_s[2]),
                        KDL::Vector(st.wrench_s[3], st.wrench_s[4], st.wrench_s[5]));
  const KDL::Wrench w_g = st.T_gs.M * w_s;                  // {g} axes, about the sensor origin
  const KDL::Wrench w_e = w_g.RefPoint(st.T_ge.p - st.T_gs.p);  // about the flange origin
  out.time_s = st.time_s;
  out.w = {w_e.force.x(), w_e.force.y(), w_e.force.z(), w_e.torque.x(), w_e.torque.y(), w_e.torque.z()};
}

namespace {
// SplitMix64 (a counter-based generator): a standard normal from (seed, key, axis).
uint64_t splitmix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}
double normalAt(uint64_t seed, uint64_t key, uint64_t axis) {
  const uint64_t a = splitmix(seed ^ splitmix(key * 4 + axis));
  const uint64_t b = splitmix(a);
  const double u1 = (static_cast<double>(a >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
  const double u2 = static_cast<double>(b >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);  // Box-Muller
}
}  // namespace

ConfigResult EstimatedWrench::configure(const WrenchErrorParams& p, uint64_t seed, const std::vector<FaultSpec>& faults) {
  p_ = p;
  seed_ = seed;
  std::vector<FaultSpec> wrench;
  for (const FaultSpec& f : faults)
    if (wrenchFault(f.kind)) wrench.push_back(f);
  return faults_.configure(wrench);
}

void EstimatedWrench::start(const SimState& initial) { p0_ = initial.T_ge.p; }

void EstimatedWrench::fill(const SimState& st, Wrench& out) const {
  fillEstimatedWrench(st, out);
  if (p_.any()) {
    const double dist = (st.T_ge.p - p0_).Norm();
    const uint64_t key = static_cast<uint64_t>(std::llround(st.time_s * 1e9));
    for (int i = 0; i < 3; ++i) {
      double e = p_.scale * out.w[i] + p_.bias_n[i] + p_.drift_n_per_m[i] * dist;
      if (p_.noise_n > 0.0) e += p_.noise_n * normalAt(seed_, key, static_cast<uint64_t>(i));
      out.w[i] += e;
    }
  }
  if (faults_.wrench()) applyFaults(st, out);
}

void EstimatedWrench::applyFaults(const SimState& st, Wrench& out) const {
  WrenchFaultTerms ft;
  faults_.wrenchAt(st.time_s, ft);
  if (!ft.any) return;
  KDL::Vector f(out.w[0] + ft.offset_n[0], out.w[1] + ft.offset_n[1], out.w[2] + ft.offset_n[2]);
  KDL::Vector m(out.w[3], out.w[4], out.w[5]);
  if (ft.mass_kg != 0.0) {
    // The load model's missing mass: its gravity, fixed in {g}, at the pad's
    // centre of mass (half-way from the flange to the sensing surface).
    const KDL::Vector g(0.0, 0.0, -ft.mass_kg * kGravity);
    f += g;
    m += (0.5 * (st.T_gs.p - st.T_ge.p)) * g;
  }
  if (ft.axes != WrenchAxes::Base) {  // the other axes' components, reported as {g}'s
    const KDL::Rotation& R = ft.axes == WrenchAxes::Flange ? st.T_ge.M : st.T_gs.M;
    f = R.Inverse(f);
    m = R.Inverse(m);
  }
  const double sign = ft.negate ? -1.0 : 1.0;
  out.w = {sign * f.x(), sign * f.y(), sign * f.z(), sign * m.x(), sign * m.y(), sign * m.z()};
}

}  // namespace sim
}  // namespace tactile
