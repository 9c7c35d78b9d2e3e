// tactile::Pose <-> KDL::Frame, the one conversion every layer uses (servo,
// simulator, FRI bridge, runner). Header-only; include it where KDL is linked.
// Pose = position (m) + unit quaternion (x, y, z, w), see conventions.hpp.
#pragma once

#include <cmath>
#include <kdl/frames.hpp>

#include "tactile_types/types.hpp"

namespace tactile {

/// Strict conversion for inputs from outside (ports, packets, commands):
/// returns false and leaves `f` untouched unless validPose(p) (types.hpp: the
/// one pose-validity rule, finite and a unit quaternion). The quaternion is
/// normalised first: KDL builds the matrix from the quaternion as given, and a
/// norm of 1 + e would scale it by ~1 + 2e.
inline bool toFrame(const Pose& p, KDL::Frame& f) noexcept {
  if (!validPose(p)) return false;
  const double n = std::sqrt(p.q[0] * p.q[0] + p.q[1] * p.q[1] + p.q[2] * p.q[2] + p.q[3] * p.q[3]);
  f = KDL::Frame(KDL::Rotation::Quaternion(p.q[0] / n, p.q[1] / n, p.q[2] / n, p.q[3] / n),
                 KDL::Vector(p.p[0], p.p[1], p.p[2]));
  return true;
}

/// Lenient conversion for poses the code made itself: normalised quaternion;
/// identity rotation if the quaternion cannot be normalised.
inline KDL::Frame toFrame(const Pose& p) noexcept {
  const double n = std::sqrt(p.q[0] * p.q[0] + p.q[1] * p.q[1] + p.q[2] * p.q[2] + p.q[3] * p.q[3]);
  const KDL::Rotation R = (n > 0.0 && std::isfinite(n))
                              ? KDL::Rotation::Quaternion(p.q[0] / n, p.q[1] / n, p.q[2] / n, p.q[3] / n)
                              : KDL::Rotation::Identity();
  return KDL::Frame(R, KDL::Vector(p.p[0], p.p[1], p.p[2]));
}

/// Every entry of the frame (position, rotation matrix) is finite.
inline bool frameFinite(const KDL::Frame& f) noexcept {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(f.p(i))) return false;
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(f.M(i, j))) return false;
  }
  return true;
}

inline void toPose(const KDL::Frame& f, Pose& p) noexcept {
  p.p = {f.p.x(), f.p.y(), f.p.z()};
  f.M.GetQuaternion(p.q[0], p.q[1], p.q[2], p.q[3]);
}

inline Pose toPose(const KDL::Frame& f) noexcept {
  Pose p;
  toPose(f, p);
  return p;
}

}  // namespace tactile
