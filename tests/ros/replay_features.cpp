// replay_features: the project's feature code (tactile::SensorStage, the
// extractor of the deployment's FeatureComponent, configured from the same
// sensor file) run offline on calibrated frames, e.g. the /tactile/image
// messages of a recorded bag (tests/ros/check_bag.py writes them).
//
//   replay_features SENSOR_YAML FRAMES
//
// FRAMES: one frame per line, `seq time_s rows cols f_0 ... f_{rows*cols-1}`
// (N per taxel, row-major in the {s} layout, as the image). The extractor
// keeps history (firing rates over frame time, alpha branch, contact-type
// hysteresis, App. B), so frames must come in order, every one, from a state
// the deployment's extractor shares (reset = no taxel fired yet).
// Output: one line per frame,
//   seq status contact alpha_defined area force cop_x cop_y coc_x coc_y
//   dzmp_x dzmp_y alpha_z d_z lambda1 lambda2 max_taxel
// (status and contact as the numbers of tactile_msgs/ContactFeatures,
// reals as %.17g). Exit 0; 1 on a malformed line; 2 on a configuration error.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <yaml-cpp/yaml.h>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_features/sensor_stage.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: replay_features SENSOR_YAML FRAMES\n";
    return 2;
  }
  const std::string sensor_file = argv[1];
  YAML::Node root;
  tactile::FeatureParams fp;
  tactile::CalibrationParams cp;
  tactile::ConfigResult r = tactile::config::loadFile(sensor_file, root);
  if (r) r = tactile::loadFeatureParams(root["features"], tactile::config::Where{sensor_file, "features"}, fp);
  if (r) r = tactile::loadCalibrationParams(root["calibration"], tactile::config::Where{sensor_file, "calibration"},
                                            fp.rows, fp.cols, cp);
  tactile::SensorStage stage;
  if (r) r = stage.configure(fp, cp);  // sets the extractor's taxel_noise from the calibration, as the component
  if (!r) {
    std::cerr << "replay_features: " << r.message() << "\n";
    return 2;
  }
  std::ifstream in(argv[2]);
  if (!in) {
    std::cerr << "replay_features: cannot open " << argv[2] << "\n";
    return 2;
  }
  stage.reset();  // FeatureComponent::startHook
  std::string line;
  long lineno = 0;
  tactile::TactileFrame frame;
  tactile::ContactFeatures f;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty()) continue;
    std::istringstream ls(line);
    unsigned long seq = 0;
    int rows = 0, cols = 0;
    ls >> seq >> frame.time_s >> rows >> cols;
    if (!ls || rows < 1 || cols < 1 || rows > tactile::kMaxRows || cols > tactile::kMaxCols) {
      std::cerr << "replay_features: " << argv[2] << ":" << lineno << ": bad header (seq time_s rows cols)\n";
      return 1;
    }
    frame.seq = static_cast<uint32_t>(seq);
    frame.rows = static_cast<uint16_t>(rows);
    frame.cols = static_cast<uint16_t>(cols);
    frame.saturated_count = 0;  // not in the image (32FC1 forces only)
    frame.force.fill(0.0);
    for (int i = 0; i < rows * cols; ++i) ls >> frame.force[static_cast<std::size_t>(i)];
    if (!ls) {
      std::cerr << "replay_features: " << argv[2] << ":" << lineno << ": expected " << rows * cols << " taxel values\n";
      return 1;
    }
    stage.stepCalibrated(frame, f);
    std::printf("%u %d %d %d %u %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", f.seq,
                static_cast<int>(f.status), static_cast<int>(f.contact), f.alpha_defined ? 1 : 0,
                static_cast<unsigned>(f.area), f.force, f.cop_x, f.cop_y, f.coc_x, f.coc_y, f.dzmp_x, f.dzmp_y,
                f.alpha_z, f.d_z, f.lambda1, f.lambda2, f.max_taxel);
  }
  return 0;
}
