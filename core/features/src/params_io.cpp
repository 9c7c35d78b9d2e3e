#include "tactile_features/params_io.hpp"

#include "tactile_config/schema_yaml.hpp"
#include "tactile_features/features_schema.hpp"

namespace tactile {

using config::read;
using config::Where;

ConfigResult loadFeatureParams(const YAML::Node& node, const Where& where, FeatureParams& p) {
  if (!node) return ConfigResult::success();
  ConfigResult r = config::readBlock(node, where, featuresSchema(), p);
  if (!r) return r;
  if (const YAML::Node t = node["threshold"]) {
    if (t.IsScalar() && t.Scalar() == "otsu") {
      p.threshold_mode = ThresholdMode::Otsu;
    } else {
      p.threshold_mode = ThresholdMode::Fixed;
      if (!(r = read(node, "threshold", p.threshold, where))) return r;
    }
  }
  FeatureExtractor scratch;
  ConfigResult v = scratch.configure(p);
  if (!v) return ConfigResult::failure((where.file.empty() ? "" : where.file + ": ") + v.message());
  return v;
}

ConfigResult loadCalibrationParams(const YAML::Node& node, const Where& where, int rows, int cols,
                                   CalibrationParams& p) {
  p.rows = rows;
  p.cols = cols;
  if (node) {
    CalibrationFile f = CalibrationFile::of(p);
    ConfigResult r = config::readBlock(node, where, calibrationSchema(), f);  // the lists: below
    if (!r || !(r = schema::checkRanges(calibrationSchema(), f, where.str()))) return r;
    p.full_scale = static_cast<uint16_t>(f.full_scale);
    p.max_tare = static_cast<uint16_t>(f.max_tare);
    p.noise_counts = f.noise_counts;
    std::vector<double> v;
    if (node["coeffs"]) {
      if (!(r = read(node, "coeffs", v, where))) return r;
      if (v.empty() || v.size() > 4) return rangeError(where.child("coeffs").str() + " (length)", v.size(), "must have 1..4 entries");
      p.coeffs = {0, 0, 0, 0};
      for (std::size_t i = 0; i < v.size(); ++i) p.coeffs[i] = v[i];
    }
    if (node["border_coeffs"]) {
      if (!(r = read(node, "border_coeffs", v, where))) return r;
      if (v.empty() || v.size() > 4)
        return rangeError(where.child("border_coeffs").str() + " (length)", v.size(), "must have 1..4 entries");
      p.border_coeffs = {0, 0, 0, 0};
      for (std::size_t i = 0; i < v.size(); ++i) p.border_coeffs[i] = v[i];
      p.use_border = true;
    }
    if (node["taxels"]) {
      std::vector<std::vector<double>> t;
      if (!(r = read(node, "taxels", t, where))) return r;
      p.taxels.clear();
      for (std::size_t i = 0; i < t.size(); ++i) {
        if (t[i].empty() || t[i].size() > 4)
          return rangeError(where.child("taxels[" + std::to_string(i) + "]").str() + " (length)", t[i].size(),
                            "must have 1..4 entries");
        std::array<double, 4> c{0, 0, 0, 0};
        for (std::size_t k = 0; k < t[i].size(); ++k) c[k] = t[i][k];
        p.taxels.push_back(c);
      }
    }
  }
  Calibration scratch;
  ConfigResult v = scratch.configure(p);
  if (!v) return ConfigResult::failure((where.file.empty() ? "" : where.file + ": ") + v.message());
  return v;
}

ConfigResult loadSensorParamFile(const std::string& file, FeatureParams& fp, CalibrationParams& cp) {
  if (file.empty()) return ConfigResult::failure("param_file is empty: set it to a YAML file with `features:` and `calibration:` maps");
  YAML::Node root;
  ConfigResult r = config::loadFile(file, root);
  if (!r) return r;
  if (!root.IsMap() || (!root["features"] && !root["calibration"]))
    return ConfigResult::failure(file + ": expected a map with `features:` and/or `calibration:`");
  fp = FeatureParams();
  cp = CalibrationParams();
  r = loadFeatureParams(root["features"], config::Where{file, "features"}, fp);
  if (!r) return r;
  return loadCalibrationParams(root["calibration"], config::Where{file, "calibration"}, fp.rows, fp.cols, cp);
}

}  // namespace tactile
