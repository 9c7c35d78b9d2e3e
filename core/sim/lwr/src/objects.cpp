#include "tactile_sim_lwr/objects.hpp"

#include "tactile_sim_lwr/sim_schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace tactile {
namespace sim {

const char* toString(ObjectType t) {
  switch (t) {
    case ObjectType::Plane: return "plane";
    case ObjectType::Sphere: return "sphere";
    case ObjectType::Bar: return "bar";
    case ObjectType::BentBar: return "bent_bar";
    case ObjectType::Tray: return "tray";
  }
  return "unknown";
}

bool parseObjectType(const std::string& s, ObjectType& out) {
  if (s == "plane" || s == "table") out = ObjectType::Plane;
  else if (s == "sphere") out = ObjectType::Sphere;
  else if (s == "bar") out = ObjectType::Bar;
  else if (s == "bent_bar") out = ObjectType::BentBar;
  else if (s == "tray") out = ObjectType::Tray;
  else return false;
  return true;
}

namespace {
bool finite3(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
KDL::Vector V(const Vec3& v) { return KDL::Vector(v[0], v[1], v[2]); }
std::string where(const ObjectParams& o, std::size_t i) {
  return "objects[" + std::to_string(i) + "]" + (o.name.empty() ? std::string() : " (" + o.name + ")");
}
}  // namespace

ConfigResult ObjectSet::configure(const std::vector<ObjectParams>& objects) {
  n_objects_ = 0;
  tray_index_ = -1;
  if (objects.size() > static_cast<std::size_t>(kMaxObjects))
    return rangeError("objects (count)", objects.size(), "must be <= " + std::to_string(kMaxObjects));
  int segments = 0;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const ObjectParams& o = objects[i];
    const std::string w = where(o, i);
    // The declared ranges (objectSchema: finite positions, radii, the tray's
    // masses, springs and angles), then what a range cannot say.
    if (const ConfigResult r = schema::checkRanges(objectSchema(), o, w); !r) return r;
    switch (o.type) {
      case ObjectType::Plane: {
        const double n = V(o.normal).Norm();
        if (!(n > 1e-9)) return rangeError(w + ".normal (norm)", n, "must be > 0");
        break;
      }
      case ObjectType::Sphere: break;
      case ObjectType::Bar:
      case ObjectType::BentBar: {
        const std::size_t nmin = 2, nmax = o.type == ObjectType::Bar ? 2 : static_cast<std::size_t>(kMaxVertices);
        if (o.vertices.size() < nmin || o.vertices.size() > nmax)
          return rangeError(w + ".vertices (count)", o.vertices.size(),
                            "must be in [" + std::to_string(nmin) + ", " + std::to_string(nmax) + "]");
        for (std::size_t k = 0; k < o.vertices.size(); ++k) {
          if (!finite3(o.vertices[k]))
            return ConfigResult::failure(w + ".vertices[" + std::to_string(k) + "]: must be finite (m)");
          if (k > 0 && (V(o.vertices[k]) - V(o.vertices[k - 1])).Norm() < 1e-6)
            return ConfigResult::failure(w + ".vertices[" + std::to_string(k) + "]: coincides with the previous vertex");
        }
        segments += static_cast<int>(o.vertices.size()) - 1;
        break;
      }
      case ObjectType::Tray: {
        const TrayParams& t = o.tray;
        if (tray_index_ >= 0) return ConfigResult::failure(w + ".type = tray: only one tray per scene");
        if ((V(t.bar_to) - V(t.bar_from)).Norm() < 1e-6) return ConfigResult::failure(w + ".bar_to: equals bar_from");
        tray_index_ = static_cast<int>(i);
        tray_ = t;
        // Inertia about the bearing axes from point masses + a plate spread
        // over the bar's lever (|y| up to the bar): I = m r^2 (+ m L^2 / 3 for the plate).
        const double Ly = std::fabs(t.bar_from[1]) > std::fabs(t.bar_to[1]) ? std::fabs(t.bar_from[1]) : std::fabs(t.bar_to[1]);
        const double Lx = 0.5 * std::fabs(t.bar_to[0] - t.bar_from[0]);
        const double mx2 = t.mass * (t.mass_from[1] * t.mass_from[1] + t.mass_from[2] * t.mass_from[2]);
        const double my2 = t.mass * (t.mass_from[0] * t.mass_from[0] + t.mass_from[2] * t.mass_from[2]);
        tray_ix_ = t.inertia_x > 0.0 ? t.inertia_x : t.tray_mass * Ly * Ly / 3.0 + mx2;
        tray_iy_ = t.inertia_y > 0.0 ? t.inertia_y : t.tray_mass * (Lx * Lx / 3.0 + 1e-4) + my2 + 1e-5;
        segments += 1;
        break;
      }
      default:
        return rangeError(w + ".type", static_cast<int>(o.type), "unknown object type");
    }
  }
  if (segments > kMaxSegments)
    return rangeError("objects (bar segments in total)", segments, "must be <= " + std::to_string(kMaxSegments));
  params_ = objects;
  n_objects_ = static_cast<int>(objects.size());
  return ConfigResult::success();
}

namespace {
// Row kernels of lowestZRow(): candidate heights of one primitive over m
// columns (+inf where it misses), branch-free so that they vectorise. On
// x86-64 they are also compiled for AVX2 and picked at load time (ifunc);
// no FMA in either clone, so both round exactly like lowestZ(). Not under
// ThreadSanitizer: the ifunc resolver runs while the loader relocates, before
// the TSan runtime is up, and the instrumented resolver crashes there (every
// binary linking the simulator segfaulted before main; scripts/realtime/sanitize.sh).
#if defined(__SANITIZE_THREAD__)
#define TACTILE_NO_IFUNC 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define TACTILE_NO_IFUNC 1
#endif
#endif
#if defined(__x86_64__) && !defined(TACTILE_NO_IFUNC) && (defined(__clang__) ? __clang_major__ >= 14 : defined(__GNUC__))
#define TACTILE_ROW_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define TACTILE_ROW_KERNEL
#endif

TACTILE_ROW_KERNEL
void ballKernel(const double* xc, int m, double* cand, double cx, double cz, double r, double dy, double x0, double x1) {
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < m; ++i) {
    const double dx = xc[i] - cx;
    const double h2 = r * r - dx * dx - dy * dy;
    // A named clamp (GCC 12 if-converts it; inside sqrt() it does not) and
    // bitwise & (no short-circuit): no control flow.
    const double hc = h2 > 0.0 ? h2 : 0.0;
    const double zi = cz - std::sqrt(hc);
    const bool ok = !(xc[i] < x0) & !(xc[i] > x1) & (h2 > 0.0);
    cand[i] = ok ? zi : inf;
  }
}

TACTILE_ROW_KERNEL
void segmentKernel(const double* xc, int m, double* cand, double p0x, double ax, double ay, double az, double wy,
                   double wz, double r2, double len, double inv_a, double x0, double x1) {
  const double inf = std::numeric_limits<double>::infinity();
  const double A = 1.0 - az * az;
  for (int i = 0; i < m; ++i) {
    const double wx = xc[i] - p0x;
    const double wa = wx * ax + wy * ay + wz * az;
    const double px = wx - wa * ax, py = wy - wa * ay, pz = wz - wa * az;
    const double B = pz;
    const double C = px * px + py * py + pz * pz - r2;
    const double disc = B * B - A * C;
    const double dc = disc >= 0.0 ? disc : 0.0;
    const double zi = (-B - std::sqrt(dc)) * inv_a;
    const double t = wa + zi * az;
    const bool ok = !(xc[i] < x0) & !(xc[i] > x1) & !(disc < 0.0) & (t >= 0.0) & (t <= len);
    cand[i] = ok ? zi : inf;
  }
}

// Surface slopes dz/dx, dz/dy at the candidate heights (for the Newton
// tangent of PadSensor::evaluate): -n_x / n_z, -n_y / n_z with n the outward
// normal there (point minus its axis foot / the centre). Bounded to +-10:
// only the Newton tangent uses them; where the candidate is +inf the result
// is never read.
inline double boundSlope(double v) { return v > 10.0 ? 10.0 : (v < -10.0 ? -10.0 : v); }

void segmentSlopes(const double* xc, int m, const double* cand, double* sx, double* sy, double p0x, double ax,
                   double ay, double az, double wy, double wz) {
  for (int i = 0; i < m; ++i) {
    const double wx = xc[i] - p0x, wzi = wz + cand[i];
    const double t = wx * ax + wy * ay + wzi * az;
    const double nx = wx - t * ax, ny = wy - t * ay, nz = wzi - t * az;
    sx[i] = boundSlope(-nx / nz);
    sy[i] = boundSlope(-ny / nz);
  }
}

void ballSlopes(const double* xc, int m, const double* cand, double* sx, double* sy, double cx, double cz, double dy) {
  for (int i = 0; i < m; ++i) {
    const double nz = cand[i] - cz;
    sx[i] = boundSlope(-(xc[i] - cx) / nz);
    sy[i] = boundSlope(-dy / nz);
  }
}
// A chunk of lowestZRow() before its primitives: no surface (+inf, object
// -1) and, where asked for (sx, sy non-null), flat.
void clearChunk(int m, double* z, int* which, double* sx, double* sy) {
  for (int i = 0; i < m; ++i) {
    z[i] = std::numeric_limits<double>::infinity();
    which[i] = -1;
  }
  if (sx != nullptr && sy != nullptr)
    for (int i = 0; i < m; ++i) sx[i] = sy[i] = 0.0;
}
}  // namespace

void ObjectSet::lowestZRow(double y, const double* x, int n, double* z, int* which, double* sx, double* sy) const {
  // Per primitive, candidate heights from the kernels above over the columns
  // of its footprint box only (x ascending: a binary search; outside the box
  // the kernels would return +inf); the first primitive that crosses a chunk
  // writes them directly, the others merge keeping the first strict minimum.
  // The primitives are visited in lowestZ()'s order with its operations: the
  // result is bit-identical. With sx/sy, the winner's surface slopes follow.
  constexpr int kChunk = 64;
  const double inf = std::numeric_limits<double>::infinity();
  const bool slopes = sx != nullptr && sy != nullptr;
  double buf[kChunk], bsx[kChunk], bsy[kChunk];
  for (int i0 = 0; i0 < n; i0 += kChunk) {
    const int m = n - i0 < kChunk ? n - i0 : kChunk;
    const double* xc = x + i0;
    double* zc = z + i0;
    int* wc = which + i0;
    double* sxc = slopes ? sx + i0 : nullptr;
    double* syc = slopes ? sy + i0 : nullptr;
    clearChunk(m, zc, wc, sxc, syc);
    bool first = true;
    int a = 0, b = m;
    // Columns [a, b) of the chunk with x0 <= x <= x1; false if none.
    auto range = [&](double x0, double x1) {
      a = static_cast<int>(std::lower_bound(xc, xc + m, x0) - xc);
      b = static_cast<int>(std::upper_bound(xc + a, xc + m, x1) - xc);
      return b > a;
    };
    // Where the candidates of the current primitive go: straight into z (and
    // the slopes) for the first one, else into the buffers.
    auto target = [&]() { return first ? zc + a : buf; };
    auto slopeTarget = [&](double*& tx, double*& ty) {
      tx = first ? sxc + a : bsx;
      ty = first ? syc + a : bsy;
    };
    auto take = [&](int object) {
      if (first) {
        for (int i = a; i < b; ++i) wc[i] = zc[i] < inf ? object : -1;
        first = false;
        return;
      }
      for (int i = a; i < b; ++i)
        if (buf[i - a] < zc[i]) {
          zc[i] = buf[i - a];
          wc[i] = object;
          if (slopes) {
            sxc[i] = bsx[i - a];
            syc[i] = bsy[i - a];
          }
        }
    };
    for (int k = 0; k < n_plane_; ++k) {
      const PlaneS& p = plane_[static_cast<std::size_t>(k)];
      if (!(p.n.z() < -1e-6)) continue;
      const double nx = p.n.x(), ny = p.n.y(), nz = p.n.z(), d = p.d;
      a = 0;
      b = m;
      double* c = target();
      for (int i = 0; i < m; ++i) c[i] = (d - nx * xc[i] - ny * y) / nz;
      if (slopes) {
        double *tx, *ty;
        slopeTarget(tx, ty);
        const double px = boundSlope(-nx / nz), py = boundSlope(-ny / nz);  // a plane's slopes are constant
        for (int i = 0; i < m; ++i) {
          tx[i] = px;
          ty[i] = py;
        }
      }
      take(p.object);
    }
    for (int k = 0; k < n_ball_; ++k) {
      const Ball& bl = ball_[static_cast<std::size_t>(k)];
      if (y < bl.ymin || y > bl.ymax || !range(bl.xmin, bl.xmax)) continue;
      double* c = target();
      ballKernel(xc + a, b - a, c, bl.c.x(), bl.c.z(), bl.r, y - bl.c.y(), bl.xmin, bl.xmax);
      if (slopes) {
        double *tx, *ty;
        slopeTarget(tx, ty);
        ballSlopes(xc + a, b - a, c, tx, ty, bl.c.x(), bl.c.z(), y - bl.c.y());
      }
      take(bl.object);
    }
    for (int k = 0; k < n_seg_; ++k) {
      const Segment& sg = seg_[static_cast<std::size_t>(k)];
      if (y < sg.ymin || y > sg.ymax || sg.inv_a == 0.0 || !range(sg.xmin, sg.xmax)) continue;
      double* c = target();
      segmentKernel(xc + a, b - a, c, sg.p0.x(), sg.a.x(), sg.a.y(), sg.a.z(), y - sg.p0.y(), -sg.p0.z(), sg.r2,
                    sg.len, sg.inv_a, sg.xmin, sg.xmax);
      if (slopes) {
        double *tx, *ty;
        slopeTarget(tx, ty);
        segmentSlopes(xc + a, b - a, c, tx, ty, sg.p0.x(), sg.a.x(), sg.a.y(), sg.a.z(), y - sg.p0.y(), -sg.p0.z());
      }
      take(sg.object);
    }
  }
}

void ObjectSet::trayBar(const TrayPose& tp, KDL::Vector& a, KDL::Vector& b) const {
  const KDL::Rotation R = KDL::Rotation::RotX(tp.pitch) * KDL::Rotation::RotY(tp.roll);
  a = bearing() + R * V(tray_.bar_from);
  b = bearing() + R * V(tray_.bar_to);
}

KDL::Vector ObjectSet::trayMassPosition(double t) const {
  double s;
  if (t <= tray_.move_start_s) s = 0.0;
  else if (tray_.move_duration_s <= 0.0 || t >= tray_.move_start_s + tray_.move_duration_s) s = 1.0;
  else s = (t - tray_.move_start_s) / tray_.move_duration_s;
  return V(tray_.mass_from) + s * (V(tray_.mass_to) - V(tray_.mass_from));
}

void ObjectSet::trayGravityTorque(const TrayPose& tp, double t, const KDL::Vector& g, double& tx, double& ty) const {
  const KDL::Rotation R = KDL::Rotation::RotX(tp.pitch) * KDL::Rotation::RotY(tp.roll);
  const KDL::Vector tau = (R * V(tray_.tray_com)) * (tray_.tray_mass * g) + (R * trayMassPosition(t)) * (tray_.mass * g);
  tx = tau.x();
  ty = tau.y();
}

void ObjectSet::grow(double xmin, double xmax, double ymin, double ymax) {
  if (!fp_any_) {
    fp_ = {xmin, xmax, ymin, ymax};
    fp_any_ = true;
    return;
  }
  fp_[0] = std::min(fp_[0], xmin);
  fp_[1] = std::max(fp_[1], xmax);
  fp_[2] = std::min(fp_[2], ymin);
  fp_[3] = std::max(fp_[3], ymax);
}

void ObjectSet::addCapsuleS(const KDL::Vector& a, const KDL::Vector& b, double r, int object, bool cap_a, bool cap_b) {
  // Footprint culling. Only the part of the centreline that can carry a
  // surface point below z = 0 over the region matters: a point p of the
  // cylinder part with p.z < 0 has its axis foot c at |p - c| = r, so c.z < r
  // and c's projection lies within r of p's (inside the region). Clip the
  // segment a + t (b - a), t in [0, 1], to z <= r and to the region grown by r.
  const KDL::Vector d = b - a;
  double t0 = 0.0, t1 = 1.0;
  auto clip = [&t0, &t1](double v0, double dv, double lo, double hi) {
    if (std::fabs(dv) < 1e-15) {
      if (v0 < lo || v0 > hi) t1 = -1.0;
      return;
    }
    double ta = (lo - v0) / dv, tb = (hi - v0) / dv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  };
  clip(a.z(), d.z(), -std::numeric_limits<double>::infinity(), r);
  clip(a.x(), d.x(), region_[0] - r, region_[1] + r);
  clip(a.y(), d.y(), region_[2] - r, region_[3] + r);
  if (t1 >= t0 && n_seg_ < kMaxSegments) {
    const KDL::Vector c0 = a + t0 * d, c1 = a + t1 * d;
    // Horizontal reach: |p - c|^2 = r^2 = horiz^2 + (c.z - p.z)^2 with
    // p.z < 0 <= c.z gives horiz^2 < r^2 - c.z^2, largest at the lowest c.
    const double zlow = std::min(c0.z(), c1.z());
    const double rho = zlow > 0.0 ? std::sqrt(std::max(r * r - zlow * zlow, 0.0)) : r;
    Segment& s = seg_[static_cast<std::size_t>(n_seg_++)];
    s.p0 = a;
    s.len = d.Norm();
    s.a = d / s.len;
    s.r = r;
    s.r2 = r * r;
    const double A = 1.0 - s.a.z() * s.a.z();
    s.inv_a = A < 1e-12 ? 0.0 : 1.0 / A;  // 0: axis along z_s, the caps handle it
    s.object = object;
    s.xmin = std::min(c0.x(), c1.x()) - rho;
    s.xmax = std::max(c0.x(), c1.x()) + rho;
    s.ymin = std::min(c0.y(), c1.y()) - rho;
    s.ymax = std::max(c0.y(), c1.y()) + rho;
    grow(s.xmin, s.xmax, s.ymin, s.ymax);
    z_low_ = std::min(z_low_, zlow - r);
  }
  if (cap_a) addBall(a, r, object);
  if (cap_b) addBall(b, r, object);
}

void ObjectSet::addBall(const KDL::Vector& c, double r, int object) {
  // Below z = 0 only within rho = sqrt(r^2 - c.z^2) of the centre (c.z > 0).
  if (!(c.z() < r) || n_ball_ >= static_cast<int>(ball_.size())) return;
  const double rho = c.z() > 0.0 ? std::sqrt(std::max(r * r - c.z() * c.z(), 0.0)) : r;
  if (!inRegion(c.x() - rho, c.x() + rho, c.y() - rho, c.y() + rho)) return;
  Ball& b = ball_[static_cast<std::size_t>(n_ball_++)];
  b.c = c;
  b.r = r;
  b.object = object;
  b.xmin = c.x() - rho;
  b.xmax = c.x() + rho;
  b.ymin = c.y() - rho;
  b.ymax = c.y() + rho;
  grow(b.xmin, b.xmax, b.ymin, b.ymax);
  z_low_ = std::min(z_low_, c.z() - r);
}

void ObjectSet::pose(const KDL::Frame& T_gs, const TrayPose& tp) {
  const KDL::Frame T_sg = T_gs.Inverse();
  n_seg_ = n_ball_ = n_plane_ = 0;
  fp_any_ = false;
  z_low_ = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n_objects_; ++i) {
    const ObjectParams& o = params_[static_cast<std::size_t>(i)];
    switch (o.type) {
      case ObjectType::Plane: {
        KDL::Vector n = V(o.normal);
        n.Normalize();
        const KDL::Vector ns = T_sg.M * n;
        const KDL::Vector ps = T_sg * V(o.point);
        if (ns.z() < -1e-6) {  // faces the sensing surface: may reach anywhere
          plane_[static_cast<std::size_t>(n_plane_++)] = PlaneS{ns, KDL::dot(ns, ps), i};
          grow(-1e9, 1e9, -1e9, 1e9);
          z_low_ = -std::numeric_limits<double>::infinity();
        }
        break;
      }
      case ObjectType::Sphere:
        addBall(T_sg * V(o.center), o.radius, i);
        break;
      case ObjectType::Bar:
      case ObjectType::BentBar: {
        const std::size_t nv = o.vertices.size();
        for (std::size_t k = 0; k + 1 < nv; ++k)
          addCapsuleS(T_sg * V(o.vertices[k]), T_sg * V(o.vertices[k + 1]), o.radius, i, k == 0, true);
        break;
      }
      case ObjectType::Tray: {
        KDL::Vector a, b;
        trayBar(tp, a, b);
        addCapsuleS(T_sg * a, T_sg * b, tray_.bar_radius, i, true, true);
        break;
      }
    }
  }
}

}  // namespace sim
}  // namespace tactile
