// Conversions from the project's port types (typekits/tactile_types) to ROS 1
// messages: plain functions, no RTT, no ROS node, tested on their own
// (test/test_conversions.cpp). Units SI; frames {g} base, {e} flange,
// {s} sensor, {c} contact (tactile_types/conventions.hpp).
//
// The functions write into a message the caller owns; a caller that keeps its
// messages reuses their strings and vectors (no allocation once sized).
#pragma once

#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <ros/time.h>
#include <sensor_msgs/Image.h>

#include <tactile_msgs/ContactFeatures.h>
#include <tactile_msgs/Phase.h>
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
