// Uses every exported core of an installed tactile_servo, and its shipped
// parameter files, from outside the source tree. Prints one line per check;
// exit code 0 only if all passed.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include <yaml-cpp/yaml.h>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_fri/params_io.hpp"
#include "tactile_servo/program_io.hpp"
#include "tactile_servo/servo.hpp"
#include "tactile_sim_lwr/pad_sensor.hpp"
#include "tactile_types/sensor_geometry.hpp"
#include "tactile_types/types.hpp"
#include "tactile_wts/protocol.hpp"

namespace {

int g_failed = 0;

void check(bool ok, const std::string& what) {
  std::printf("%s %s\n", ok ? "[ok]  " : "[FAIL]", what.c_str());
  if (!ok) ++g_failed;
}

void checkConfig(const tactile::ConfigResult& r, const std::string& what) {
  check(r.ok(), what + (r.ok() ? "" : ": " + r.message()));
}

}  // namespace

int main() {
  using namespace tactile;
  const std::string data = TACTILE_DATA_DIR;

  // Features: the shipped sensor file, then one synthetic frame with two equal
  // taxels at (row 2, col 6) and (row 2, col 7): the centre of pressure lies
  // half-way between their centres, x = 0, y = (2 - 2.5) pitch ({s}).
  YAML::Node root;
  FeatureParams fp;
  const std::string sensor_file = data + "/params/wts0614.yaml";
  ConfigResult r = config::loadFile(sensor_file, root);
  if (r.ok()) r = loadFeatureParams(root["features"], config::Where{sensor_file, "features"}, fp);
  checkConfig(r, "features parameters from " + sensor_file);
  FeatureExtractor ex;
  checkConfig(ex.configure(fp), "FeatureExtractor configures");
  TactileFrame frame;
  frame.rows = static_cast<uint16_t>(fp.rows);
  frame.cols = static_cast<uint16_t>(fp.cols);
  frame.at(2, 6) = 1.5;
  frame.at(2, 7) = 1.5;
  ContactFeatures f;
  const FeatureStatus st = ex.step(frame, f);
  check(st == FeatureStatus::Ok, "feature status Ok");
  check(std::fabs(f.force - 3.0) < 1e-12, "total force 3 N (got " + std::to_string(f.force) + ")");
  check(std::fabs(f.cop_x) < 1e-12, "CoP x = 0 (got " + std::to_string(f.cop_x) + ")");
  check(std::fabs(f.cop_y + 0.5 * fp.pitch) < 1e-12, "CoP y = -pitch/2 (got " + std::to_string(f.cop_y) + ")");
  check(f.contact == ContactType::Point, "two taxels are a point contact");
  const SensorGeometry g = fp.geometry();
  check(std::fabs(f.cop_x - 0.5 * (g.x(6) + g.x(7))) < 1e-12 && std::fabs(f.cop_y - g.y(2)) < 1e-12,
        "CoP between the SensorGeometry centres of the two taxels");

  // Servo: a shipped phase program configures the servo.
  ServoParams sp;
  const std::string program = data + "/programs/edge_exploration.yaml";
  checkConfig(loadServoProgram(program, sp), "servo program " + program);
  TactileServo servo;
  checkConfig(servo.configure(sp), "TactileServo configures");

  // WTS protocol: the CRC of "read single frame" (AA AA AA 20 01 00 00 -> 8F 83).
  uint8_t buf[16];
  const std::size_t n = wts::encodeReadSingleFrame(false, buf, sizeof(buf));
  check(n == 9 && buf[7] == 0x8F && buf[8] == 0x83, "WTS read-single-frame packet and CRC");

  // FRI: the shipped bridge parameters.
  fri::BridgeParams bp;
  fri::UdpParams up;
  checkConfig(fri::loadBridgeParamsFile(data + "/params/fri.yaml", bp, up), "FRI bridge parameters");

  // Simulator: the pad model configures with its defaults.
  sim::PadSensor pad;
  checkConfig(pad.configure(sim::PadParams{}), "sim::PadSensor configures");

  std::printf("consumer checks: %d failed\n", g_failed);
  return g_failed == 0 ? 0 : 1;
}
