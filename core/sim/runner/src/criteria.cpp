// A scene's pass criteria against a run's summary (summaryMetric, checkCriteria).
#include "tactile_sim_runner/loop.hpp"

#include <cstdio>
#include <limits>
#include <string>

namespace tactile {
namespace sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

bool summaryMetric(const Summary& s, const std::string& name, double& v) {
  struct Entry {
    const char* name;
    double value;
  };
  const Entry table[] = {{"contact_lost_count", static_cast<double>(s.contact_lost_count)},
                         {"force_true_mean_n", s.force_true_mean_n},
                         {"force_true_max_n", s.force_true_max_n},
                         {"force_true_rms_error_n", s.force_true_rms_error_n},
                         {"force_true_in_band_fraction", s.force_true_in_band_fraction},
                         {"force_scored_s", s.force_scored_s},
                         {"force_true_in_band_s", s.force_true_in_band_s},
                         {"alignment_time_s", s.alignment_time_s},
                         {"scored_path_m", s.path_length_m},
                         {"scored_duration_s", s.scored_duration_s},
                         {"scored_mean_speed_mps", s.slide_speed_mps},
                         {"path_length_m", s.path_length_m},
                         {"slide_speed_mps", s.slide_speed_mps},
                         {"slide_path_m", s.slide_path_m},
                         {"slide_duration_s", s.slide_duration_s},
                         {"slide_mean_speed_mps", s.slide_mean_speed_mps},
                         {"slide_force_true_mean_n", s.slide_force_true_mean_n},
                         {"slide_force_true_max_n", s.slide_force_true_max_n},
                         {"slide_force_true_rms_error_n", s.slide_force_true_rms_error_n},
                         {"slide_force_true_in_band_fraction", s.slide_force_true_in_band_fraction},
                         {"dzmp_final_m", s.dzmp_final_m},
                         {"dzmp_recovery_time_s", s.dzmp_recovery_time_s},
                         {"translation_x_m", s.translation_x_m},
                         {"tray_angle_max_deg", s.tray_angle_max_deg},
                         {"sim_time_s", s.sim_time_s},
                         {"exit_code", static_cast<double>(s.exit_code)}};
  for (const Entry& e : table)
    if (name == e.name) {
      v = e.value;
      return true;
    }
  return false;
}

void checkCriteria(const Scene& sc, Summary& s) {
  s.criteria_failed.clear();
  for (const Criterion& c : sc.metrics.criteria) {
    double v = kNaN;
    char buf[160];
    if (!summaryMetric(s, c.metric, v)) {
      std::snprintf(buf, sizeof buf, "%s: not a summary metric", c.metric.c_str());
    } else if (!(v >= c.min)) {  // NaN fails too
      std::snprintf(buf, sizeof buf, "%s = %.6g < %.6g", c.metric.c_str(), v, c.min);
    } else if (!(v <= c.max)) {
      std::snprintf(buf, sizeof buf, "%s = %.6g > %.6g", c.metric.c_str(), v, c.max);
    } else {
      continue;
    }
    s.criteria_failed.emplace_back(buf);
  }
}

}  // namespace sim
}  // namespace tactile
