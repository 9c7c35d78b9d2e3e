// Shared by the simulator's tests and benchmark: poses and objects the
// world-level scenes are built from.
#pragma once

#include "tactile_sim_lwr/world.hpp"

namespace tactile {
namespace sim {
namespace simtest {

/// Flange pointing down (x_e = -x_g, z_e = -z_g): x_s = -x_g, y_s = y_g, z_s = -z_g.
inline Pose downPose(double x, double y, double z) {
  Pose p;
  p.p = {x, y, z};
  p.q = {0.0, 1.0, 0.0, 0.0};  // RotY(pi)
  return p;
}

/// The plane z_g = 0 (a table under the whole pad).
inline ObjectParams tablePlane() {
  ObjectParams table;
  table.name = "table";
  table.type = ObjectType::Plane;
  table.point = {0, 0, 0};
  table.normal = {0, 0, 1};
  return table;
}

}  // namespace simtest
}  // namespace sim
}  // namespace tactile
