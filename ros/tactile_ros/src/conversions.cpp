#include "tactile_ros/conversions.hpp"

#include <cmath>
#include <cstring>

namespace tactile_ros {

bool toStamp(double time_s, double offset_s, ros::Time& stamp) {
  const double t = time_s + offset_s;
  if (!std::isfinite(t) || t < 0.0 || t > 4294967295.0) {
    stamp = ros::Time(0);
    return false;
  }
  stamp = ros::Time(t);
  return true;
}

bool toImage(const tactile::TactileFrame& frame, const ros::Time& stamp, const std::string& sensor_frame,
             sensor_msgs::Image& out) {
  out.header.stamp = stamp;
  out.header.seq = frame.seq;
  out.header.frame_id = sensor_frame;
  out.encoding = "32FC1";
  out.is_bigendian = 0;
  if (frame.rows == 0 || frame.cols == 0 || frame.rows > tactile::kMaxRows || frame.cols > tactile::kMaxCols) {
    out.height = out.width = out.step = 0;
    out.data.clear();
    return false;
  }
  out.height = frame.rows;
  out.width = frame.cols;
  out.step = static_cast<uint32_t>(frame.cols * sizeof(float));
  out.data.resize(static_cast<std::size_t>(out.step) * out.height);
  for (int i = 0; i < frame.size(); ++i) {
    const float v = static_cast<float>(frame.force[static_cast<std::size_t>(i)]);
    std::memcpy(&out.data[static_cast<std::size_t>(i) * sizeof(float)], &v, sizeof(float));  // x86: little-endian
  }
  return true;
}

void toFeatures(const tactile::ContactFeatures& f, const ros::Time& stamp, const std::string& sensor_frame,
                tactile_msgs::ContactFeatures& out) {
  out.header.stamp = stamp;
  out.header.seq = f.seq;
  out.header.frame_id = sensor_frame;
  out.seq = f.seq;
  out.cop_x = f.cop_x;
  out.cop_y = f.cop_y;
  out.coc_x = f.coc_x;
  out.coc_y = f.coc_y;
  out.dzmp_x = f.dzmp_x;
  out.dzmp_y = f.dzmp_y;
  out.alpha_z = f.alpha_z;
  out.alpha_defined = f.alpha_defined;
  out.force = f.force;
  out.d_z = f.d_z;
  out.lambda1 = f.lambda1;
  out.lambda2 = f.lambda2;
  out.curvature = f.curvature;
  out.max_taxel = f.max_taxel;
  out.area = f.area;
  out.contact = static_cast<uint8_t>(f.contact);
  out.status = static_cast<uint8_t>(f.status);
}

void toPose(const tactile::Pose& pose, const ros::Time& stamp, const std::string& parent,
            geometry_msgs::PoseStamped& out) {
  out.header.stamp = stamp;
  out.header.frame_id = parent;
  out.pose.position.x = pose.p[0];
  out.pose.position.y = pose.p[1];
  out.pose.position.z = pose.p[2];
  out.pose.orientation.x = pose.q[0];
  out.pose.orientation.y = pose.q[1];
  out.pose.orientation.z = pose.q[2];
  out.pose.orientation.w = pose.q[3];
}

void toTransform(const tactile::Pose& pose, const ros::Time& stamp, const std::string& parent,
                 const std::string& child, geometry_msgs::TransformStamped& out) {
  out.header.stamp = stamp;
  out.header.frame_id = parent;
  out.child_frame_id = child;
  out.transform.translation.x = pose.p[0];
  out.transform.translation.y = pose.p[1];
  out.transform.translation.z = pose.p[2];
  out.transform.rotation.x = pose.q[0];
  out.transform.rotation.y = pose.q[1];
  out.transform.rotation.z = pose.q[2];
  out.transform.rotation.w = pose.q[3];
}

namespace {
// v' = R(q)^T v for a unit quaternion q = (x, y, z, w).
void rotateInverse(const std::array<double, 4>& q, const double* v, double* out) {
  const double x = -q[0], y = -q[1], z = -q[2], w = q[3];  // conjugate
  // t = 2 (u x v), v' = v + w t + u x t
  const double tx = 2.0 * (y * v[2] - z * v[1]);
  const double ty = 2.0 * (z * v[0] - x * v[2]);
  const double tz = 2.0 * (x * v[1] - y * v[0]);
  out[0] = v[0] + w * tx + (y * tz - z * ty);
  out[1] = v[1] + w * ty + (z * tx - x * tz);
  out[2] = v[2] + w * tz + (x * ty - y * tx);
}
}  // namespace

bool toWrench(const tactile::Wrench& w, const tactile::Pose& flange_pose, const ros::Time& stamp,
              const std::string& base_frame, const std::string& flange_frame, geometry_msgs::WrenchStamped& out) {
  out.header.stamp = stamp;
  double f[3] = {w.w[0], w.w[1], w.w[2]};
  double t[3] = {w.w[3], w.w[4], w.w[5]};
  const bool valid = tactile::validPose(flange_pose);
  if (valid) {
    std::array<double, 4> q = flange_pose.q;
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& c : q) c /= n;
    double fe[3], te[3];
    rotateInverse(q, f, fe);
    rotateInverse(q, t, te);
    for (int i = 0; i < 3; ++i) {
      f[i] = fe[i];
      t[i] = te[i];
    }
  }
  out.header.frame_id = valid ? flange_frame : base_frame;
  out.wrench.force.x = f[0];
  out.wrench.force.y = f[1];
  out.wrench.force.z = f[2];
  out.wrench.torque.x = t[0];
  out.wrench.torque.y = t[1];
  out.wrench.torque.z = t[2];
  return valid;
}

void toPhase(const tactile::PhaseState& p, const ros::Time& stamp, tactile_msgs::Phase& out) {
  out.header.stamp = stamp;
  out.index = p.index;
  out.name.assign(p.name.data(), strnlen(p.name.data(), p.name.size()));
  out.t_enter = p.t_enter_s;
  out.status = static_cast<uint8_t>(p.status);
  out.status_name = tactile::toString(p.status);
}

const std::array<const char*, tactile::kArmJoints> kLwrJointNames{
    {"lwr_a1_joint", "lwr_a2_joint", "lwr_a3_joint", "lwr_a4_joint", "lwr_a5_joint", "lwr_a6_joint", "lwr_a7_joint"}};

bool initJointState(const std::vector<std::string>& names, sensor_msgs::JointState& out) {
  if (names.size() != static_cast<std::size_t>(tactile::kArmJoints)) return false;
  out.name = names;
  out.position.assign(names.size(), 0.0);
  out.velocity.clear();
  out.effort.clear();
  return true;
}

bool toJointState(const tactile::RobotState& s, const ros::Time& stamp, sensor_msgs::JointState& out) {
  if (out.position.size() != s.q.size() || out.name.size() != s.q.size()) return false;
  for (const double q : s.q)
    if (!std::isfinite(q)) return false;
  out.header.stamp = stamp;
  for (std::size_t i = 0; i < s.q.size(); ++i) out.position[i] = s.q[i];
  return true;
}

void toRobotStateMsg(const tactile::RobotState& s, const ros::Time& stamp, tactile_msgs::RobotState& out) {
  out.header.stamp = stamp;
  out.mode = static_cast<uint8_t>(s.mode);
  out.mode_name = tactile::toString(s.mode);
  out.quality = s.quality;
  out.power_on = s.power_on;
  out.cartesian_impedance = s.cartesian_impedance;
  out.config_ok = s.config_ok;
  out.dry_run = s.dry_run;
  out.commandable = s.commandable;
  out.link_status = s.link_status;
}

bool sameKrcState(const tactile::RobotState& a, const tactile::RobotState& b) {
  return a.mode == b.mode && a.quality == b.quality && a.power_on == b.power_on &&
         a.cartesian_impedance == b.cartesian_impedance && a.config_ok == b.config_ok && a.dry_run == b.dry_run &&
         a.commandable == b.commandable && a.link_status == b.link_status;
}

bool inContact(const tactile::ContactFeatures& f) {
  return tactile::usable(f.status) && f.contact != tactile::ContactType::None;
}

tactile::Pose contactPose(const tactile::ContactFeatures& f) {
  tactile::Pose c;
  c.p = {f.cop_x, f.cop_y, 0.0};
  const double a = f.alpha_defined && std::isfinite(f.alpha_z) ? f.alpha_z : 0.0;
  c.q = {0.0, 0.0, std::sin(0.5 * a), std::cos(0.5 * a)};
  return c;
}

bool poseFromVector(const std::vector<double>& v, tactile::Pose& out) {
  if (v.size() != 7) return false;
  tactile::Pose p;
  for (int i = 0; i < 3; ++i) p.p[static_cast<std::size_t>(i)] = v[static_cast<std::size_t>(i)];
  for (int i = 0; i < 4; ++i) p.q[static_cast<std::size_t>(i)] = v[static_cast<std::size_t>(3 + i)];
  if (!tactile::validPose(p)) return false;
  out = p;
  return true;
}

}  // namespace tactile_ros
