// The arm's estimated wrench the force estimate reads: the true wrench at the flange (fillEstimatedWrench)
// plus the scene's wrench-error model (EstimatedWrench: scale, bias, drift, seeded noise).
#include "tactile_sim/loop.hpp"

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

void EstimatedWrench::configure(const WrenchErrorParams& p, uint64_t seed) {
  p_ = p;
  seed_ = seed;
}

void EstimatedWrench::start(const SimState& initial) { p0_ = initial.T_ge.p; }

void EstimatedWrench::fill(const SimState& st, Wrench& out) const {
  fillEstimatedWrench(st, out);
  if (!p_.any()) return;
  const double dist = (st.T_ge.p - p0_).Norm();
  const uint64_t key = static_cast<uint64_t>(std::llround(st.time_s * 1e9));
  for (int i = 0; i < 3; ++i) {
    double e = p_.scale * out.w[i] + p_.bias_n[i] + p_.drift_n_per_m[i] * dist;
    if (p_.noise_n > 0.0) e += p_.noise_n * normalAt(seed_, key, static_cast<uint64_t>(i));
    out.w[i] += e;
  }
}

}  // namespace sim
}  // namespace tactile
