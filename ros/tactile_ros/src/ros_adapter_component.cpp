// tactile_ros::RosAdapter: the project's ports as ROS 1 messages, in its own
// (non-real-time) thread. A thin component: it reads the deployment's ports
// (buffered connections: every sample), converts them with the plain
// functions of conversions.hpp, and
// writes them as ROS messages to output ports that a deployment streams to
// ROS topics with rtt_roscomm (deployments/ros_streams.ops; the typekits are
// the project's rtt_tactile_foreign_msgs and rtt_tactile_msgs, generated the
// rtt_roscomm way), and broadcasts TF with tf2_ros from this
// thread. The real-time components only gain one more lock-free connection
// per port; conversion here, serialisation and publishing in rtt_roscomm's
// publisher thread.
//
//   in   calibrated_frame (/tactile/TactileFrame)    -> port image_msg        sensor_msgs/Image 32FC1 (N)
//   in   features         (/tactile/ContactFeatures) -> port features_msg     tactile_msgs/ContactFeatures
//   in   flange_pose      (/tactile/Pose)            -> port flange_pose_msg  geometry_msgs/PoseStamped ({g})
//   in   pose_command     (/tactile/PoseCommand)     -> port pose_command_msg geometry_msgs/PoseStamped ({g})
//   in   estimated_wrench (/tactile/Wrench)          -> port wrench_msg       geometry_msgs/WrenchStamped ({e})
//   in   phase            (/tactile/PhaseState)      -> port phase_msg        tactile_msgs/Phase
//   in   robot_state      (/tactile/RobotState)      -> port joint_state_msg  sensor_msgs/JointState (A1..A7, rad)
//                                                     -> port robot_state_msg  tactile_msgs/RobotState (the KRC's state)
//        both decimated by the samples' time to joint_state_period (the arm's 1 kHz -> 100 Hz);
//        robot_state_msg also at once when the KRC's state changes
//   TF   {g} -> {e} (flange_pose), {e} -> {s} (sensor_mount) unless publish_flange_tf is false (then
//        robot_state_publisher draws the arm from joint_state_msg and the URDF), {s} -> {c} (features,
//        while in contact)
//   op   bool switchPhase(SwitchPhase::Request&, SwitchPhase::Response&)  for rtt_rosservice:
//        calls switchPhase(name) of the peer named by the property `servo`
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <rtt/Component.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/OperationCaller.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include <ros/ros.h>
#include <tactile_msgs/SwitchPhase.h>
#include <tf2_ros/transform_broadcaster.h>

#include "tactile_ros/conversions.hpp"
#include "tactile_types_rtt/component.hpp"

namespace tactile_ros {

class RosAdapter : public tactile::Component {
 public:
  explicit RosAdapter(const std::string& name)
      : tactile::Component(name, PreOperational),
        frame_in_("calibrated_frame"),
        features_in_("features"),
        flange_in_("flange_pose"),
        command_in_("pose_command"),
        wrench_in_("estimated_wrench"),
        phase_in_("phase"),
        robot_in_("robot_state"),
        image_out_("image_msg"),
        features_out_("features_msg"),
        flange_out_("flange_pose_msg"),
        command_out_("pose_command_msg"),
        wrench_out_("wrench_msg"),
        phase_out_("phase_msg"),
        joint_state_out_("joint_state_msg"),
        robot_state_out_("robot_state_msg"),
        servo_switch_("switchPhase") {
    addProperty("base_frame", base_frame_).doc("TF name of {g}, the robot base.");
    addProperty("flange_frame", flange_frame_).doc("TF name of {e}, the flange.");
    addProperty("sensor_frame", sensor_frame_).doc("TF name of {s}, the sensing surface (frame_id of image and features).");
    addProperty("contact_frame", contact_frame_).doc("TF name of {c}, the contact frame (published while in contact).");
    addProperty("sensor_mount", sensor_mount_)
        .doc("{e}T{s} as [x y z qx qy qz qw] (m, unit quaternion): the program's sensor_mount.");
    addProperty("stamp_offset", stamp_offset_)
        .doc("ROS stamp = sample time + stamp_offset (s). Ignored while auto_stamp_offset.");
    addProperty("auto_stamp_offset", auto_offset_)
        .doc("True: stamp_offset is set at the first sample to ROS time now - its time (simulated time -> ROS time).");
    addProperty("servo", servo_name_).doc("Peer whose switchPhase(string) the operation switchPhase calls.");
    addProperty("publish_tf", publish_tf_).doc("Broadcast {g}->{e}->{s}->{c} on /tf.");
    addProperty("publish_flange_tf", publish_flange_tf_)
        .doc("With publish_tf: broadcast {g}->{e}->{s} from flange_pose and sensor_mount. False where "
             "robot_state_publisher publishes the URDF's lwr_base ... lwr_flange -> wts0614 from joint_state_msg "
             "(two publishers of one frame would make TF jump); the contact frame {c} is broadcast either way.");
    addProperty("joint_names", joint_names_)
        .doc("The names of A1..A7 in joint_state_msg (7; default lwr_a1_joint..lwr_a7_joint, the URDF's).");
    addProperty("joint_state_period", joint_state_period_)
        .doc("Least time between two joint_state_msg / robot_state_msg samples, by the samples' own time (s; "
             "0.01: the arm's 1 kHz as 100 Hz; 0: every sample). A change of the KRC's state goes out at once.");

    addEventPort(frame_in_).doc("Calibrated frame (N per taxel, {s} layout) from the feature component.");
    addEventPort(features_in_).doc("Contact features in {s} from the feature component.");
    addPort(flange_in_).doc("Measured flange pose {g}T{e} (simulated arm or FRI bridge); buffered: published with the wrench written after it.");
    addEventPort(command_in_).doc("Commanded flange pose {g}T{e} from the servo.");
    addEventPort(wrench_in_).doc("The arm's estimated wrench [F T] ({g} axes, flange origin).");
    addEventPort(phase_in_).doc("Phase program state from the servo.");
    addEventPort(robot_in_).doc("The arm's state (the KRC's mode and quality, the measured joints) from the FRI "
                                "bridge or the simulated arm, every cycle.");
    addPort(image_out_).doc("The calibrated frame as sensor_msgs/Image (rows x cols, 32FC1, N, row-major; frame_id sensor_frame), to stream.");
    addPort(features_out_).doc("The features as tactile_msgs/ContactFeatures (frame_id sensor_frame), to stream.");
    addPort(flange_out_).doc("The measured flange pose as geometry_msgs/PoseStamped (frame_id base_frame), to stream.");
    addPort(command_out_).doc("The commanded flange pose as geometry_msgs/PoseStamped (frame_id base_frame), to stream.");
    addPort(wrench_out_).doc("The estimated wrench as geometry_msgs/WrenchStamped (in {e}: frame_id flange_frame), to stream.");
    addPort(phase_out_).doc("Phase as tactile_msgs/Phase, to stream.");
    addPort(joint_state_out_).doc("The measured joints as sensor_msgs/JointState (joint_names, rad; decimated to "
                                  "joint_state_period), to stream (robot_state_publisher's joint_states).");
    addPort(robot_state_out_).doc("The KRC's state as tactile_msgs/RobotState (mode, quality, commandable, ...; "
                                  "decimated, and at once on a change), to stream.");
    addOperation("switchPhase", &RosAdapter::switchPhase, this, RTT::ClientThread)
        .doc("ROS service body (tactile_msgs/SwitchPhase): the servo's switchPhase(request.phase).");
  }

  ~RosAdapter() override { haltActivity(); }  // its event ports outlive its thread (component.hpp)

  bool configureHook() override {
    if (!poseFromVector(sensor_mount_, mount_)) {
      RTT::log(RTT::Error) << getName() << ": property sensor_mount must be [x y z qx qy qz qw] with a unit quaternion"
                           << RTT::endlog();
      return false;
    }
    servo_switch_ = RTT::OperationCaller<bool(const std::string&)>();
    if (!servo_name_.empty()) {
      RTT::TaskContext* servo = getPeer(servo_name_);
      if (!servo || !servo->provides()->hasOperation("switchPhase")) {
        RTT::log(RTT::Error) << getName() << ": property servo = '" << servo_name_
                             << "' is not a peer with an operation switchPhase (addPeer first)" << RTT::endlog();
        return false;
      }
      servo_switch_ = servo->getOperation("switchPhase");
    }
    if (!ros::isStarted()) {
      RTT::log(RTT::Error) << getName() << ": no ROS node (ros.import(\"rtt_rosnode\") with a roscore running)"
                           << RTT::endlog();
      return false;
    }
    if (!initJointState(joint_names_, joint_state_)) {
      RTT::log(RTT::Error) << getName() << ": property joint_names must hold " << tactile::kArmJoints
                           << " names (A1..A7), has " << joint_names_.size() << RTT::endlog();
      return false;
    }
    if (!std::isfinite(joint_state_period_) || joint_state_period_ < 0.0 || joint_state_period_ > 1.0) {
      RTT::log(RTT::Error) << getName() << ": property joint_state_period = " << joint_state_period_
                           << " must be in [0, 1] s" << RTT::endlog();
      return false;
    }
    // The samples' sizes for the streams' buffers (the largest frame; the
    // joint state with its names and positions): a write copies into them.
    sensor_msgs::Image sample;
    sample.data.resize(static_cast<std::size_t>(tactile::kMaxRows) * tactile::kMaxCols * sizeof(float));
    image_out_.setDataSample(sample);
    joint_state_out_.setDataSample(joint_state_);
    toRobotStateMsg(tactile::RobotState{}, ros::Time(0), robot_state_msg_);
    robot_state_out_.setDataSample(robot_state_msg_);
    if (publish_tf_) tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();
    return true;
  }

  bool startHook() override {
    offset_set_ = !auto_offset_;
    joint_decimator_ = Decimator(joint_state_period_);
    krc_published_ = false;
    return true;
  }

  void updateHook() override {
    const HookScope hook(*this);  // tactile_types_rtt/component.hpp
    while (frame_in_.read(frame_, false) == RTT::NewData) {
      if (!stamp(frame_.time_s)) continue;
      if (toImage(frame_, stamp_, sensor_frame_, image_)) image_out_.write(image_);
    }
    while (features_in_.read(features_, false) == RTT::NewData) {
      if (!stamp(features_.time_s)) continue;
      toFeatures(features_, stamp_, sensor_frame_, features_msg_);
      features_out_.write(features_msg_);
      if (tf_ && inContact(features_)) {
        toTransform(contactPose(features_), stamp_, sensor_frame_, contact_frame_, tf_sc_);
        tf_->sendTransform(tf_sc_);
      }
    }
    while (command_in_.read(command_, false) == RTT::NewData) {
      if (!stamp(command_.time_s)) continue;
      toPose(command_.pose, stamp_, base_frame_, command_msg_);
      command_out_.write(command_msg_);
    }
    // A pose carries no time: the arm writes flange_pose, then estimated_wrench,
    // every step, so the pose that precedes a wrench in its (FIFO) buffer is
    // published with the wrench's stamp.
    while (wrench_in_.read(wrench_, false) == RTT::NewData) {
      if (!stamp(wrench_.time_s)) continue;
      if (flange_in_.read(flange_, false) == RTT::NewData) {
        toPose(flange_, stamp_, base_frame_, flange_msg_);
        flange_out_.write(flange_msg_);
        if (tf_ && publish_flange_tf_ && tactile::validPose(flange_)) {
          toTransform(flange_, stamp_, base_frame_, flange_frame_, tf_ge_);
          toTransform(mount_, stamp_, flange_frame_, sensor_frame_, tf_es_);
          tf_pair_[0] = tf_ge_;
          tf_pair_[1] = tf_es_;
          tf_->sendTransform(tf_pair_);
        }
      }
      toWrench(wrench_, flange_, stamp_, base_frame_, flange_frame_, wrench_msg_);
      wrench_out_.write(wrench_msg_);
    }
    while (phase_in_.read(phase_, false) == RTT::NewData) {
      if (!stamp(phase_.time_s)) continue;
      toPhase(phase_, stamp_, phase_msg_);
      phase_out_.write(phase_msg_);
    }
    // The arm's state at its rate (1 kHz): every sample read, a bounded rate
    // published; the messages were sized in configureHook (no allocation).
    while (robot_in_.read(robot_, false) == RTT::NewData) {
      if (!stamp(robot_.time_s)) continue;
      const bool due = joint_decimator_.due(robot_.time_s);
      if (due && toJointState(robot_, stamp_, joint_state_)) joint_state_out_.write(joint_state_);
      if (due || !krc_published_ || !sameKrcState(robot_, krc_last_)) {
        toRobotStateMsg(robot_, stamp_, robot_state_msg_);
        robot_state_out_.write(robot_state_msg_);
        krc_last_ = robot_;
        krc_published_ = true;
      }
    }
  }

  bool switchPhase(tactile_msgs::SwitchPhase::Request& req, tactile_msgs::SwitchPhase::Response& res) {
    if (!servo_switch_.ready()) {
      res.ok = false;
      res.message = "no servo peer (property servo)";
      return true;
    }
    res.ok = servo_switch_(req.phase);
    res.message = res.ok ? "switching to '" + req.phase + "' at the next servo cycle"
                         : "no phase '" + req.phase + "' in the servo's program";
    return true;
  }

 private:
  // The ROS stamp of a sample; the first sample sets the offset when automatic.
  bool stamp(double time_s) {
    if (!offset_set_) {
      stamp_offset_ = ros::Time::now().toSec() - time_s;
      offset_set_ = true;
    }
    return toStamp(time_s, stamp_offset_, stamp_);
  }

  RTT::InputPort<tactile::TactileFrame> frame_in_;
  RTT::InputPort<tactile::ContactFeatures> features_in_;
  RTT::InputPort<tactile::Pose> flange_in_;
  RTT::InputPort<tactile::PoseCommand> command_in_;
  RTT::InputPort<tactile::Wrench> wrench_in_;
  RTT::InputPort<tactile::PhaseState> phase_in_;
  RTT::InputPort<tactile::RobotState> robot_in_;
  RTT::OutputPort<sensor_msgs::Image> image_out_;
  RTT::OutputPort<tactile_msgs::ContactFeatures> features_out_;
  RTT::OutputPort<geometry_msgs::PoseStamped> flange_out_;
  RTT::OutputPort<geometry_msgs::PoseStamped> command_out_;
  RTT::OutputPort<geometry_msgs::WrenchStamped> wrench_out_;
  RTT::OutputPort<tactile_msgs::Phase> phase_out_;
  RTT::OutputPort<sensor_msgs::JointState> joint_state_out_;
  RTT::OutputPort<tactile_msgs::RobotState> robot_state_out_;
  RTT::OperationCaller<bool(const std::string&)> servo_switch_;

  std::string base_frame_ = "lwr_base";
  std::string flange_frame_ = "lwr_flange";
  std::string sensor_frame_ = "wts0614";
  std::string contact_frame_ = "contact";
  std::vector<double> sensor_mount_{0.0, 0.0, 0.03, 0.0, 0.0, 0.0, 1.0};
  double stamp_offset_ = 0.0;
  bool auto_offset_ = true;
  bool offset_set_ = false;
  std::string servo_name_;
  bool publish_tf_ = true;
  bool publish_flange_tf_ = true;
  std::vector<std::string> joint_names_{kLwrJointNames.begin(), kLwrJointNames.end()};
  double joint_state_period_ = 0.01;

  tactile::Pose mount_;
  tactile::TactileFrame frame_;
  tactile::ContactFeatures features_;
  tactile::Pose flange_ = tactile::kNoPose;
  tactile::PoseCommand command_;
  tactile::Wrench wrench_;
  tactile::PhaseState phase_;
  tactile::RobotState robot_, krc_last_;
  Decimator joint_decimator_;
  bool krc_published_ = false;
  ros::Time stamp_;
  sensor_msgs::Image image_;
  tactile_msgs::ContactFeatures features_msg_;
  geometry_msgs::PoseStamped flange_msg_, command_msg_;
  geometry_msgs::WrenchStamped wrench_msg_;
  tactile_msgs::Phase phase_msg_;
  sensor_msgs::JointState joint_state_;
  tactile_msgs::RobotState robot_state_msg_;
  geometry_msgs::TransformStamped tf_ge_, tf_es_, tf_sc_;
  std::vector<geometry_msgs::TransformStamped> tf_pair_{2};
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_;
};

}  // namespace tactile_ros

ORO_CREATE_COMPONENT(tactile_ros::RosAdapter)
