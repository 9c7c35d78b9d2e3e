// lwr_fk_table: the simulator's kinematics of the LWR 4+ (tactile::sim::LwrArm
// with its default ArmParams, as the simulated arm configures it) for the
// URDF check (tests/ros/check_urdf.py, ctest urdf_fk).
//
// First, one line per link of the simulator's chain (k = 1..7):
//   link k mass cx cy cz ixx iyy izz
// (ArmParams::links: kg, COM in the segment's tip frame in m, principal
// moments about the COM in kg m^2), then
//   tool mass cx cy cz
// (ArmParams::tool_mass, tool_com in {e}). Then, for every line of seven joint
// angles (rad) on standard input, one output line of 8 x 12 numbers: the tip
// frames of segments 1..7 from KDL::ChainFkSolverPos_recursive on
// LwrArm::chain(), then LwrArm::forward()'s flange pose {g}T{e}, each as
// px py pz r00 r01 r02 r10 r11 r12 r20 r21 r22 (m; rotation row-major).
// Exit 1 when a line is not seven finite numbers or the arm does not configure.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

#include <kdl/chainfksolverpos_recursive.hpp>

#include "tactile_sim_lwr/lwr_arm.hpp"

namespace {

void printFrame(const KDL::Frame& f) {
  std::printf(" %.17g %.17g %.17g", f.p.x(), f.p.y(), f.p.z());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) std::printf(" %.17g", f.M(r, c));
}

}  // namespace

int main() {
  using tactile::sim::kLwrJoints;
  tactile::sim::LwrArm arm;
  const tactile::sim::ArmParams params;
  const tactile::ConfigResult cfg = arm.configure(params);
  if (!cfg) {
    std::fprintf(stderr, "lwr_fk_table: the arm does not configure: %s\n", cfg.message().c_str());
    return 1;
  }
  for (int k = 0; k < kLwrJoints; ++k) {
    const auto& L = params.links[static_cast<std::size_t>(k)];
    std::printf("link %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", k + 1, L.mass, L.com[0], L.com[1], L.com[2],
                L.inertia[0], L.inertia[1], L.inertia[2]);
  }
  std::printf("tool %.17g %.17g %.17g %.17g\n", params.tool_mass, params.tool_com[0], params.tool_com[1],
              params.tool_com[2]);
  KDL::ChainFkSolverPos_recursive fk(arm.chain());
  std::string line;
  while (std::getline(std::cin, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream in(line);
    tactile::sim::JointVec q;
    KDL::JntArray kq(kLwrJoints);
    for (int i = 0; i < kLwrJoints; ++i) {
      if (!(in >> q[i]) || !std::isfinite(q[i])) {
        std::fprintf(stderr, "lwr_fk_table: need seven finite joint angles (rad) per line, got '%s'\n", line.c_str());
        return 1;
      }
      kq(static_cast<unsigned int>(i)) = q[i];
    }
    for (int k = 1; k <= kLwrJoints; ++k) {
      KDL::Frame tip;
      if (fk.JntToCart(kq, tip, k) < 0) {
        std::fprintf(stderr, "lwr_fk_table: KDL forward kinematics failed at segment %d\n", k);
        return 1;
      }
      printFrame(tip);
    }
    KDL::Frame T_ge;
    arm.forward(q, T_ge);
    printFrame(T_ge);
    std::printf("\n");
  }
  return 0;
}
