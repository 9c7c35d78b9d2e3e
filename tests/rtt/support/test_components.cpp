// Components for the RTT tests and the deployer test scripts only (package
// "tactile_test", not installed):
//
//   tactile::SyntheticTouch  a stand-in sensor: an indenter pressed on the
//       elastic pad model (core/sim/contact), quantised to raw counts and written on
//       `raw_frame` (and the forces on `frame`) at every update(). Properties
//       place the contact: a disc (length = 0) or an edge of `length` at `angle`.
//       Frames are stamped with RTT's TimeService (seconds).
//   tactile::IdealRobot      a stand-in robot: `flange_pose` := the last
//       `pose_command` (perfect tracking), starting from the pose in its
//       properties x, y, z, qx, qy, qz, qw.
//   tactile::PhaseLog        records which phases a servo went through: input
//       `phase` (connect it with a buffer policy), operations visited(name),
//       waitFor(name, timeout_s) (polls, for scripts of running deployments),
//       and sleep(s).
//   tactile::OpsCheck        assertions for .ops scripts: expect(cond, what)
//       prints "[PASS] what" / "[FAIL] what"; finish() prints the summary (once)
//       and returns 1 (all passed, at least one check) or -1. The deployer only
//       fails on script *parse* errors, so a test script ends with the
//       checkpoint `var int all_checks_passed(Check.finish())`: RTT evaluates
//       the size hint while parsing, and -1 is a parse error, which makes the
//       deployer's runScript() fail. Run with `deployer --check -s x.ops`
//       (tests/rtt/run_deployer.cmake) the deployer then exits by its normal
//       shutdown (components stopped, cleaned up, unloaded): 0 or 255.
#include <rtt/Component.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/Logger.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/os/TimeService.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "raw_from_forces.hpp"
#include "tactile_config/yaml_params.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_sim_contact/elastic_pad.hpp"
#include "tactile_types/types.hpp"
#include "tactile_types_rtt/component.hpp"

namespace tactile {

class SyntheticTouch : public Component {
 public:
  explicit SyntheticTouch(const std::string& name)
      : Component(name, PreOperational), raw_out_("raw_frame"), frame_out_("frame") {
    addProperty("rows", rows_).doc("Taxel rows (6 for the WTS0614).");
    addProperty("cols", cols_).doc("Taxel columns (14 for the WTS0614).");
    addProperty("pitch", pitch_).doc("Taxel pitch (m).");
    addProperty("center_x", center_x_).doc("Contact centre x in {s} (m).");
    addProperty("center_y", center_y_).doc("Contact centre y in {s} (m).");
    addProperty("length", length_).doc("Edge length (m); 0 = disc contact.");
    addProperty("angle", angle_).doc("Edge direction from x_s (rad).");
    addProperty("radius", radius_).doc("Indenter radius (m): half width of the pressed band.");
    addProperty("depth", depth_).doc("Penetration at the centre line (m); 0 = no contact.");
    addProperty("modulus", modulus_).doc("Foundation modulus of the pad (Pa/m).");
    addProperty("counts_per_newton", counts_per_newton_)
        .doc("Raw counts per newton (inverse of a linear calibration gain); used when param_file is empty.");
    addProperty("param_file", param_file_)
        .doc("Sensor parameter file (`calibration:` map, e.g. params/sensors/wts0614.yaml): raw counts are "
             "the inverse of that calibration, so a FeatureComponent reading the same file recovers the forces.");
    addProperty("full_scale", full_scale_).doc("Raw value at which a taxel saturates.");
    addPort(raw_out_).doc("Raw frame (counts).");
    addPort(frame_out_).doc("The same contact as forces (N per taxel).");
  }

  bool configureHook() override {
    if (rows_ < 1 || rows_ > kMaxRows || cols_ < 1 || cols_ > kMaxCols || !(pitch_ > 0) || !(radius_ > 0)) return false;
    use_calibration_ = !param_file_.empty();
    if (use_calibration_) {
      YAML::Node root;
      CalibrationParams cp;
      ConfigResult r = config::loadFile(param_file_, root);
      if (r) r = loadCalibrationParams(root["calibration"], config::Where{param_file_, "calibration"}, rows_, cols_, cp);
      if (r) r = calibration_.configure(cp);
      if (!r) {
        RTT::log(RTT::Error) << getName() << ": " << r.message() << RTT::endlog();
        return false;
      }
    }
    raw_ = RawTactileFrame();
    raw_.rows = static_cast<uint16_t>(rows_);
    raw_.cols = static_cast<uint16_t>(cols_);
    frame_ = TactileFrame();
    raw_out_.setDataSample(raw_);
    frame_out_.setDataSample(frame_);
    return true;
  }

  void updateHook() override {
    const HookScope hook(*this);  // component.hpp
    sim::PadGeometry g;
    g.rows = rows_;
    g.cols = cols_;
    g.pitch = pitch_;
    g.modulus = modulus_;
    const double ux = std::cos(angle_), uy = std::sin(angle_), half = 0.5 * length_;
    auto penetration = [&](double x, double y) {
      const double dx = x - center_x_, dy = y - center_y_;
      const double t = std::max(-half, std::min(half, dx * ux + dy * uy));  // closest point on the segment
      const double ex = dx - t * ux, ey = dy - t * uy;
      const double d2 = (ex * ex + ey * ey) / (radius_ * radius_);
      return depth_ * (1.0 - d2);  // paraboloid / cylinder indenter; <= 0 outside
    };
    sim::integratePad(g, penetration, frame_);
    if (use_calibration_) {
      test::rawFromForces(calibration_, frame_, raw_);
    } else {
      const int n = rows_ * cols_;
      for (int i = 0; i < n; ++i) {
        const double c = std::round(frame_.force[static_cast<std::size_t>(i)] * counts_per_newton_);
        raw_.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>(std::min<double>(c, full_scale_));
      }
    }
    // Stamped with RTT's TimeService, the clock of the servo component.
    raw_.time_s = frame_.time_s = RTT::os::TimeService::Instance()->secondsSince(0);
    raw_.seq = frame_.seq = seq_++;
    raw_out_.write(raw_);
    frame_out_.write(frame_);
  }

 private:
  int rows_ = kDefaultRows, cols_ = kDefaultCols;
  double pitch_ = kDefaultPitch;
  double center_x_ = 0.0, center_y_ = 0.0, length_ = 0.0, angle_ = 0.0;
  double radius_ = 0.003, depth_ = 0.002, modulus_ = 2.0e7;
  double counts_per_newton_ = 500.0;
  int full_scale_ = 4095;
  std::string param_file_;
  bool use_calibration_ = false;
  Calibration calibration_;
  uint32_t seq_ = 0;
  RTT::OutputPort<RawTactileFrame> raw_out_;
  RTT::OutputPort<TactileFrame> frame_out_;
  RawTactileFrame raw_;
  TactileFrame frame_;
};

class IdealRobot : public Component {
 public:
  explicit IdealRobot(const std::string& name)
      : Component(name, PreOperational), command_in_("pose_command"), pose_out_("flange_pose") {
    const char* names[7] = {"x", "y", "z", "qx", "qy", "qz", "qw"};
    for (int i = 0; i < 7; ++i)
      addProperty(names[i], start_[static_cast<std::size_t>(i)]).doc("Initial flange pose {g}T{e} (m, unit quaternion).");
    addPort(command_in_).doc("Desired flange pose.");
    addPort(pose_out_).doc("Measured flange pose (= the last command).");
  }
  bool configureHook() override {
    pose_.p = {start_[0], start_[1], start_[2]};
    pose_.q = {start_[3], start_[4], start_[5], start_[6]};
    pose_out_.setDataSample(pose_);
    return true;
  }
  void updateHook() override {
    const HookScope hook(*this);  // component.hpp
    if (command_in_.read(cmd_, false) == RTT::NewData) pose_ = cmd_.pose;
    pose_out_.write(pose_);
  }

 private:
  std::array<double, 7> start_{{0.5, 0.0, 0.4, 1.0, 0.0, 0.0, 0.0}};
  RTT::InputPort<PoseCommand> command_in_;
  RTT::OutputPort<Pose> pose_out_;
  PoseCommand cmd_;
  Pose pose_;
};

class PhaseLog : public Component {
 public:
  explicit PhaseLog(const std::string& name) : Component(name), phase_in_("phase") {
    addEventPort(phase_in_).doc("Phase state of a ServoComponent (use a buffered connection).");
    addOperation("visited", &PhaseLog::visited, this, RTT::ClientThread)
        .doc("True once a PhaseState with this name was received.")
        .arg("name", "Phase name.");
    addOperation("waitFor", &PhaseLog::waitFor, this, RTT::ClientThread)
        .doc("Wait (polling every 5 ms) until the phase was visited or timeout_s passed (wall clock).")
        .arg("name", "Phase name.")
        .arg("timeout_s", "Longest wait (s).");
    addOperation("sleep", &PhaseLog::sleep, this, RTT::ClientThread).doc("Sleep (wall clock).").arg("s", "Seconds.");
    addAttribute("samples", samples_);
  }
  void updateHook() override {
    const HookScope hook(*this);  // component.hpp
    while (phase_in_.read(ps_, false) == RTT::NewData) {
      ++samples_;
      const std::size_t i = ps_.index;
      if (i < kSlots && !seen_[i].load(std::memory_order_acquire)) {
        std::memcpy(names_[i].data(), ps_.name.data(), names_[i].size());
        names_[i].back() = '\0';
        seen_[i].store(true, std::memory_order_release);
      }
    }
  }
  bool visited(const std::string& name) const {
    for (std::size_t i = 0; i < kSlots; ++i)
      if (seen_[i].load(std::memory_order_acquire) && name == names_[i].data()) return true;
    return false;
  }
  bool waitFor(const std::string& name, double timeout_s) const {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (!visited(name)) {
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
  }
  void sleep(double s) const { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

 private:
  static constexpr std::size_t kSlots = 32;
  RTT::InputPort<PhaseState> phase_in_;
  PhaseState ps_;
  int samples_ = 0;
  std::array<std::atomic<bool>, kSlots> seen_{};
  std::array<std::array<char, kPhaseNameLen>, kSlots> names_{};
};

class OpsCheck : public RTT::TaskContext {
 public:
  explicit OpsCheck(const std::string& name) : RTT::TaskContext(name) {
    addOperation("expect", &OpsCheck::expect, this, RTT::ClientThread)
        .doc("Record a check: prints [PASS]/[FAIL] what; returns cond.")
        .arg("cond", "The checked condition.")
        .arg("what", "What was checked.");
    addOperation("failures", &OpsCheck::failures, this, RTT::ClientThread).doc("Number of failed checks so far.");
    addOperation("sleep", &OpsCheck::sleep, this, RTT::ClientThread).doc("Sleep (wall clock).").arg("s", "Seconds.");
    addOperation("finish", &OpsCheck::finish, this, RTT::ClientThread)
        .doc("Print the summary (first call only) and return 1 if every check passed (and there was one), else -1: "
             "the size hint of `var int all_checks_passed(Check.finish())`, a parse error (deployer exit 255) on -1.");
  }

  bool expect(bool cond, const std::string& what) {
    ++checks_;
    if (!cond) ++failures_;
    std::printf("[%s] %s\n", cond ? "PASS" : "FAIL", what.c_str());
    std::fflush(stdout);
    return cond;
  }
  int failures() const { return failures_; }
  void sleep(double s) const { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }
  int finish() {
    // RTT evaluates a size hint more than once while parsing: report once.
    if (!finished_) {
      finished_ = true;
      std::printf("ops checks: %d run, %d failed\n", checks_, failures_);
      std::fflush(stdout);
    }
    return failures_ == 0 && checks_ > 0 ? 1 : -1;
  }

 private:
  int checks_ = 0, failures_ = 0;
  bool finished_ = false;
};

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::SyntheticTouch)
ORO_LIST_COMPONENT_TYPE(tactile::IdealRobot)
ORO_LIST_COMPONENT_TYPE(tactile::OpsCheck)
ORO_LIST_COMPONENT_TYPE(tactile::PhaseLog)
