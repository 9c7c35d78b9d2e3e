// Rigid objects the tactile pad can touch, and their fast analytic evaluation
// in the sensor frame {s}.
//
// The pad model (pad_sensor.hpp) needs, for a column (x, y) of the sensing
// surface, the lowest point of the object along z_s: z_low(x, y) in {s}. The
// penetration into the elastic layer is then delta = -z_low (Winkler
// foundation, Eq. 2). Every object has an analytic z_low:
//   plane  : half-space (a table top), n . p <= n . p0, n the outward normal;
//   sphere : centre, radius;
//   bar    : a capsule (cylinder of radius r around a segment, rounded ends):
//            a straight bar whose top edge has the rounding radius r;
//   bent_bar: a polyline of such capsules (union), e.g. a centreline bent in
//            the xy and the xz planes (Sec. 5.2.1, Fig. 11);
//   tray   : a rigid plate on a pivot bearing with a copper bar (capsule)
//            glued underneath, the part the sensor holds (Sec. 5.3, Fig. 13);
//            its two small rotation angles about the bearing are world state.
// Object geometry is given in {g} (tray bar: in the tray frame, which is {g}
// translated to the bearing point and rotated by the tray angles).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "tactile_types/config_result.hpp"

namespace tactile {
namespace sim {

enum class ObjectType : uint8_t { Plane = 0, Sphere = 1, Bar = 2, BentBar = 3, Tray = 4 };
const char* toString(ObjectType t);
/// "plane" | "table" | "sphere" | "bar" | "bent_bar" | "tray" -> type; false if unknown.
bool parseObjectType(const std::string& s, ObjectType& out);

constexpr int kMaxObjects = 8;
constexpr int kMaxVertices = 65;   ///< per bar polyline (64 segments: a 6 cm ring within 0.07 mm)
constexpr int kMaxSegments = 128;  ///< over all objects

using Vec3 = std::array<double, 3>;

/// Tray of Sec. 5.3 (Fig. 13). The tray frame {t} is {g} translated to the
/// bearing point and rotated by Rx(roll_x) * Ry(roll_y) (small angles). The
/// bearing is modelled as a pivot that lets the tray pitch about x_g (this
/// sets the load on the sensor) and roll about y_g (the equilibrium axis,
/// from the bearing to the holding point, is along y_g at rest; the roll
/// makes the line load on the bar non-uniform), with optional torsional
/// springs/dampers. The tray plate itself is not a contact body; only the
/// bar glued underneath touches the pad. Both angles rest on stops at
/// +-0.6 rad (a tray that loses the sensor hangs there: watch tray_pitch).
struct TrayParams {
  Vec3 bearing{0.6, -0.4, 0.4};            ///< bearing point in {g} (m)
  Vec3 bar_from{-0.05, 0.4, -0.006};       ///< bar centreline start in {t} (m)
  Vec3 bar_to{0.05, 0.4, -0.006};          ///< bar centreline end in {t} (m)
  double bar_radius = 0.003;               ///< m (rounded copper bar)
  double tray_mass = 1.0;                  ///< kg (plate + bar)
  Vec3 tray_com{0.0, 0.2, 0.0};            ///< in {t} (m)
  double mass = 0.2;                       ///< the movable weight (kg), Sec. 5.3
  Vec3 mass_from{0.0, 0.2, 0.0};           ///< weight position before the move, {t} (m)
  Vec3 mass_to{0.06, 0.2, 0.0};            ///< after the move, {t} (m)
  double move_start_s = 5.0;               ///< scripted move: start time (s)
  double move_duration_s = 1.0;            ///< linear in time over this duration (s); 0 = jump
  double pitch_stiffness = 0.0;            ///< torsional spring about x_g at the bearing (N m/rad)
  double roll_stiffness = 0.0;             ///< about y_g (N m/rad)
  double bearing_damping = 0.5;            ///< N m s/rad, both axes (dynamics; bearing friction, lumped)
  double inertia_x = 0.0, inertia_y = 0.0; ///< about the bearing (kg m^2); 0 = from the masses
  double initial_pitch = 0.0, initial_roll = 0.0;  ///< rad
};

struct ObjectParams {
  std::string name;             ///< used in error messages
  ObjectType type = ObjectType::Plane;
  // plane
  Vec3 point{0.0, 0.0, 0.0};    ///< a point of the plane, {g}
  Vec3 normal{0.0, 0.0, 1.0};   ///< outward normal (out of the solid), {g}
  // sphere
  Vec3 center{0.0, 0.0, 0.0};
  double radius = 0.01;         ///< sphere radius or bar rounding radius (m)
  // bar / bent_bar: centreline vertices in {g} (2 for a bar, >= 2 for a bent bar)
  std::vector<Vec3> vertices;
  // tray
  TrayParams tray;
};

/// A point mass of the tray, for its gravity torque.
struct TrayPose {
  double pitch = 0.0;  ///< rotation about x_g at the bearing (rad)
  double roll = 0.0;   ///< rotation about y_g at the bearing (rad): the "tray angle"
};

/// The objects of a scene, evaluated in {s}. Fixed capacity, allocation-free
/// after configure().
class ObjectSet {
 public:
  ConfigResult configure(const std::vector<ObjectParams>& objects);
  int size() const { return n_objects_; }
  bool hasTray() const { return tray_index_ >= 0; }
  int trayIndex() const { return tray_index_; }
  const TrayParams& tray() const { return tray_; }
  const ObjectParams& params(int i) const { return params_[static_cast<std::size_t>(i)]; }

  /// Only the region (x, y in {s}) where lowestZ() will be asked matters
  /// (the sensor outline): primitives outside it are dropped in pose().
  /// Default: everywhere.
  void setRegion(double xmin, double xmax, double ymin, double ymax) { region_ = {xmin, xmax, ymin, ymax}; }

  /// Place all objects in {s}: T_gs = {g}T{s}; tray pose for the tray bar.
  void pose(const KDL::Frame& T_gs, const TrayPose& tray);

  /// Lowest object surface point along z_s over the column (x, y) in {s}
  /// (+inf if no object crosses the column). `which` = object index.
  /// Exact wherever the result is below the sensing surface (z < 0) inside
  /// the region; columns where every object stays above z = 0 may report
  /// +inf instead of the (positive) height (footprint culling).
  double lowestZ(double x, double y, int& which) const;

  /// lowestZ() at the n points (x[i], y), bit-identical to n calls (same
  /// operations in the same order), branch-free per point: the rows of the
  /// pad sampling (PadSensor). +inf / -1 where nothing is below.
  /// With sx and sy (n values each): the surface slopes dz/dx, dz/dy of the
  /// lowest surface at each point (bounded to +-10; 0 where nothing is below),
  /// for the Newton tangent of PadSensor::evaluate().
  void lowestZRow(double y, const double* x, int n, double* z, int* which, double* sx = nullptr,
                  double* sy = nullptr) const;

  /// Range of x (in {s}) over which the line y = const can have lowestZ < 0
  /// (union of the primitives' footprints crossing that line); false if none.
  /// Conservative, like footprint().
  bool rowSpan(double y, double& xmin, double& xmax) const;

  /// Bounding box in {s} (x, y) of every object part that reaches below the
  /// sensing surface (z < 0) after pose(); false if nothing does (no contact
  /// possible anywhere: layer and housing are both at z <= 0). Conservative:
  /// lowestZ(x, y) >= 0 outside it.
  bool footprint(double& xmin, double& xmax, double& ymin, double& ymax) const {
    xmin = fp_[0]; xmax = fp_[1]; ymin = fp_[2]; ymax = fp_[3];
    return fp_any_;
  }

  /// Lower bound of lowestZ() over the region after pose() (+inf if nothing
  /// reaches below z = 0, -inf with a facing plane): no column can have
  /// lowestZ < lowestPoint(). Lets the pad skip its housing ring (top face
  /// at -recess) whenever lowestPoint() >= -recess.
  double lowestPoint() const { return z_low_; }

  /// Tray bar endpoints in {g} at a tray pose.
  void trayBar(const TrayPose& tp, KDL::Vector& a, KDL::Vector& b) const;
  /// Moving weight position in {t} at time t (scripted move).
  KDL::Vector trayMassPosition(double t) const;
  /// Gravity torque about the bearing (x_g, y_g components) at pose tp, time t.
  void trayGravityTorque(const TrayPose& tp, double t, const KDL::Vector& g, double& tx, double& ty) const;
  KDL::Vector bearing() const { return KDL::Vector(tray_.bearing[0], tray_.bearing[1], tray_.bearing[2]); }
  double trayInertiaX() const { return tray_ix_; }
  double trayInertiaY() const { return tray_iy_; }

 private:
  struct Segment {  // capsule cylinder part, in {s}
    KDL::Vector p0, a;
    double len = 0.0, r = 0.0, r2 = 0.0, inv_a = 0.0;  // inv_a = 1 / (1 - a_z^2)
    double xmin = 0, xmax = 0, ymin = 0, ymax = 0;  // where it can reach below z = 0 (see addCapsuleS)
    int object = 0;
  };
  struct Ball {  // sphere / capsule end cap, in {s}
    KDL::Vector c;
    double r = 0.0;
    int object = 0;
    double xmin = 0, xmax = 0, ymin = 0, ymax = 0;  // where it can reach below z = 0
  };
  struct PlaneS {
    KDL::Vector n;
    double d = 0.0;
    int object = 0;
  };
  void addCapsuleS(const KDL::Vector& a, const KDL::Vector& b, double r, int object, bool cap_a, bool cap_b);
  void addBall(const KDL::Vector& c, double r, int object);

  std::vector<ObjectParams> params_;  // configure-time copy (names for messages)
  int n_objects_ = 0;
  int tray_index_ = -1;
  TrayParams tray_;
  double tray_ix_ = 0.0, tray_iy_ = 0.0;
  // Posed geometry in {s}, rebuilt by pose().
  std::array<Segment, kMaxSegments> seg_{};
  std::array<Ball, kMaxSegments + kMaxObjects> ball_{};
  std::array<PlaneS, kMaxObjects> plane_{};
  int n_seg_ = 0, n_ball_ = 0, n_plane_ = 0;
  std::array<double, 4> fp_{};  // union footprint xmin, xmax, ymin, ymax
  std::array<double, 4> region_{-1e9, 1e9, -1e9, 1e9};
  bool inRegion(double xmin, double xmax, double ymin, double ymax) const {
    return xmax >= region_[0] && xmin <= region_[1] && ymax >= region_[2] && ymin <= region_[3];
  }
  bool fp_any_ = false;
  double z_low_ = std::numeric_limits<double>::infinity();
  void grow(double xmin, double xmax, double ymin, double ymax);
};

// Hot path (called per sample): defined inline.
inline double ObjectSet::lowestZ(double x, double y, int& which) const {
  double zmin = std::numeric_limits<double>::infinity();
  which = -1;
  for (int i = 0; i < n_plane_; ++i) {
    const PlaneS& p = plane_[static_cast<std::size_t>(i)];
    if (p.n.z() < -1e-6) {  // the solid faces the sensing surface
      const double z = (p.d - p.n.x() * x - p.n.y() * y) / p.n.z();
      if (z < zmin) { zmin = z; which = p.object; }
    }
  }
  for (int i = 0; i < n_ball_; ++i) {
    const Ball& b = ball_[static_cast<std::size_t>(i)];
    if (x < b.xmin || x > b.xmax || y < b.ymin || y > b.ymax) continue;
    const double dx = x - b.c.x(), dy = y - b.c.y();
    const double h2 = b.r * b.r - dx * dx - dy * dy;
    if (h2 > 0.0) {
      const double z = b.c.z() - std::sqrt(h2);
      if (z < zmin) { zmin = z; which = b.object; }
    }
  }
  for (int i = 0; i < n_seg_; ++i) {
    const Segment& s = seg_[static_cast<std::size_t>(i)];
    if (x < s.xmin || x > s.xmax || y < s.ymin || y > s.ymax) continue;
    // Vertical line P(z) = (x, y, z) against the infinite cylinder around the
    // axis p0 + t a: |w_perp + z e_perp|^2 = r^2, lower root, then 0 <= t <= len.
    const double wx = x - s.p0.x(), wy = y - s.p0.y(), wz = -s.p0.z();
    const double wa = wx * s.a.x() + wy * s.a.y() + wz * s.a.z();
    const double px = wx - wa * s.a.x(), py = wy - wa * s.a.y(), pz = wz - wa * s.a.z();
    const double az = s.a.z();
    if (s.inv_a == 0.0) continue;  // axis along z_s: the caps handle it
    const double A = 1.0 - az * az;
    const double B = pz;  // w_perp . e_perp = w_perp . e_z (w_perp is orthogonal to a)
    const double C = px * px + py * py + pz * pz - s.r2;
    const double disc = B * B - A * C;
    if (disc < 0.0) continue;
    const double z = (-B - std::sqrt(disc)) * s.inv_a;
    const double t = wa + z * az;
    if (t >= 0.0 && t <= s.len && z < zmin) {
      zmin = z;
      which = s.object;
    }
  }
  return zmin;
}

inline bool ObjectSet::rowSpan(double y, double& xmin, double& xmax) const {
  if (n_plane_ > 0) {  // a facing plane may reach anywhere
    xmin = -std::numeric_limits<double>::infinity();
    xmax = std::numeric_limits<double>::infinity();
    return true;
  }
  bool any = false;
  xmin = std::numeric_limits<double>::infinity();
  xmax = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < n_ball_; ++i) {
    const Ball& b = ball_[static_cast<std::size_t>(i)];
    if (y < b.ymin || y > b.ymax) continue;
    any = true;
    if (b.xmin < xmin) xmin = b.xmin;
    if (b.xmax > xmax) xmax = b.xmax;
  }
  for (int i = 0; i < n_seg_; ++i) {
    const Segment& s = seg_[static_cast<std::size_t>(i)];
    if (y < s.ymin || y > s.ymax) continue;
    any = true;
    if (s.xmin < xmin) xmin = s.xmin;
    if (s.xmax > xmax) xmax = s.xmax;
  }
  return any;
}

}  // namespace sim
}  // namespace tactile
