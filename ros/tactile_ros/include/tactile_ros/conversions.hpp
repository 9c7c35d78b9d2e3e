// Conversions from the project's port types (core/types) to ROS 1
// messages: plain functions, no RTT, no ROS node, tested on their own
// (test/test_conversions.cpp). Units SI; frames {g} base, {e} flange,
// {s} sensor, {c} contact (tactile_types/conventions.hpp).
//
// The functions write into a message the caller owns; a caller that keeps its
// messages reuses their strings and vectors (no allocation once sized).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <ros/time.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/JointState.h>

#include <tactile_msgs/ContactFeatures.h>
#include <tactile_msgs/Phase.h>
#include <tactile_msgs/RobotState.h>
#include <tactile_types/types.hpp>

namespace tactile_ros {

/// The ROS stamp of a port sample: time_s + offset_s (s). A sum that is not
/// finite or below zero (no ROS time) gives ros::Time(0) and false.
bool toStamp(double time_s, double offset_s, ros::Time& stamp);

/// A calibrated frame as a 32FC1 image: height = rows (6), width = cols (14),
/// row-major as the frame (row 0 first, taxel (r, c) at data[4 (r cols + c)]),
/// newtons, little-endian floats. False (image emptied) for a size beyond
/// tactile::kMaxRows x kMaxCols or zero.
bool toImage(const tactile::TactileFrame& frame, const ros::Time& stamp, const std::string& sensor_frame,
             sensor_msgs::Image& out);

/// The features, field by field (frame_id = the sensor frame {s}).
void toFeatures(const tactile::ContactFeatures& f, const ros::Time& stamp, const std::string& sensor_frame,
                tactile_msgs::ContactFeatures& out);

/// A pose {parent}T{child} as PoseStamped (frame_id = parent).
void toPose(const tactile::Pose& pose, const ros::Time& stamp, const std::string& parent,
            geometry_msgs::PoseStamped& out);

/// A pose {parent}T{child} as a TF transform.
void toTransform(const tactile::Pose& pose, const ros::Time& stamp, const std::string& parent,
                 const std::string& child, geometry_msgs::TransformStamped& out);

/// The arm's wrench [Fx Fy Fz Tx Ty Tz] ({g} axes, flange origin) expressed in
/// the flange frame {e}: f_e = R^T f_g, t_e = R^T t_g with R the rotation of
/// {g}T{e} = flange_pose (normalised). frame_id = flange frame. False (and
/// the wrench in {g} axes unchanged, frame_id = base frame) when the pose is
/// not valid (tactile::validPose).
bool toWrench(const tactile::Wrench& w, const tactile::Pose& flange_pose, const ros::Time& stamp,
              const std::string& base_frame, const std::string& flange_frame, geometry_msgs::WrenchStamped& out);

/// The phase state (name up to its NUL, the servo status and its name).
void toPhase(const tactile::PhaseState& p, const ros::Time& stamp, tactile_msgs::Phase& out);

/// The joint names of the robot model (ros/tactile_ros/urdf/lwr4plus_wts.urdf),
/// A1..A7 in the order of tactile::RobotState::q.
extern const std::array<const char*, tactile::kArmJoints> kLwrJointNames;

/// Sizes a joint-state message for the arm once: name = names (kArmJoints of
/// them), position kArmJoints zeros, velocity and effort empty (not
/// measured on the port). False (message unchanged) for another count of names.
bool initJointState(const std::vector<std::string>& names, sensor_msgs::JointState& out);

/// The measured joints of a robot state (rad, A1..A7) into a message sized by
/// initJointState: writes the stamp and the positions only, never resizes (no
/// allocation). False (nothing written) when the message is not sized for the
/// arm or a joint is not finite.
bool toJointState(const tactile::RobotState& s, const ros::Time& stamp, sensor_msgs::JointState& out);

/// The KRC's state of a robot state, field by field (the joints left out).
void toRobotStateMsg(const tactile::RobotState& s, const ros::Time& stamp, tactile_msgs::RobotState& out);

/// True when the KRC's state (everything but the time and the joints) is the
/// same in both: a change is published at once, not at the next decimated sample.
bool sameKrcState(const tactile::RobotState& a, const tactile::RobotState& b);

/// Bounds the rate of a stream of samples by their own time (not a clock) to
/// one per period_s on average: a sample is due when it is the first, when it
/// is at or after the next slot (slots period_s apart from the first due
/// sample, within kTimeSlack_s, so that a 1 kHz stream decimated to 0.01 s
/// gives every tenth sample despite rounding), or when it is older than the
/// last due one (the time restarted). The slots keep their own schedule, so
/// jitter in the samples' times (the FRI bridge stamps a packet when it
/// arrives) does not lower the rate; a gap longer than a period re-anchors
/// them at the sample after it. period_s <= 0: every sample. No allocation.
class Decimator {
 public:
  static constexpr double kTimeSlack_s = 1e-6;
  explicit Decimator(double period_s = 0.0) : period_s_(period_s) {}
  void reset() { have_ = false; }
  bool due(double t_s) {
    const bool restart = !have_ || t_s < last_s_;
    if (!restart && t_s < next_s_ - kTimeSlack_s) return false;
    // The next slot: one period on, or from this sample after a restart or a gap.
    next_s_ = restart || t_s >= next_s_ + period_s_ ? t_s + period_s_ : next_s_ + period_s_;
    have_ = true;
    last_s_ = t_s;
    return true;
  }

 private:
  double period_s_;
  double last_s_ = 0.0;  ///< the last due sample's time
  double next_s_ = 0.0;  ///< the next slot
  bool have_ = false;
};

/// True when the features locate a contact frame: usable status and a
/// contact (point, edge or multiple).
bool inContact(const tactile::ContactFeatures& f);

/// {s}T{c}: origin at the centre of pressure (Eq. B.2/B.3) on the surface
/// (z = 0), rotated by alpha_z about z_s (Eq. B.5) when alpha_defined, else
/// aligned with {s}.
tactile::Pose contactPose(const tactile::ContactFeatures& f);

/// A pose from [x y z qx qy qz qw] (a property); false when not 7 values or
/// not a valid pose (tactile::validPose).
bool poseFromVector(const std::vector<double>& v, tactile::Pose& out);

}  // namespace tactile_ros
