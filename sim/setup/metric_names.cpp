#include "sim/setup/metric_names.h"

#include <algorithm>
#include <cctype>

namespace lap::sim {

std::string snake_case(const std::string& name) {
  std::string out;
  bool gap = false;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 128 && std::isalnum(u) != 0) {
      if (gap && !out.empty()) out.push_back('_');
      gap = false;
      out.push_back(static_cast<char>(std::tolower(u)));
    } else {
      gap = true;
    }
  }
  return out;
}

const std::vector<std::string>& fixed_metric_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = {"completion_time_s",
                                  "session_time_s",
                                  "phase_catheter_grasped_s",
                                  "phase_tip_at_incision_s",
                                  "phase_tip_in_lumen_s",
                                  "phase_target_depth_reached_s",
                                  "phase_held_s"};
    for (const std::string side : {"left", "right"}) {
      for (const std::string& x :
           {"path_length_" + side + "_m", "movements_" + side, "economy_of_motion_" + side,
            "mean_jerk_" + side + "_m_per_s3", "idle_time_" + side + "_s", "grasp_attempts_" + side,
            "out_of_view_" + side + "_s"}) {
        n.push_back(x);
      }
    }
    for (const char* x :
         {"path_length_dominant_m", "path_length_non_dominant_m", "path_ratio_non_dominant",
          "time_over_threshold_s", "injury_events", "max_squeeze_duct_n", "catheter_drops",
          "grasp_attempts", "max_insertion_depth_m", "final_insertion_depth_m",
          "time_out_of_view_s"}) {
      n.emplace_back(x);
    }
    return n;
  }();
  return names;
}

std::vector<std::string> organ_metric_names(const std::string& organ) {
  return {"max_force_" + organ + "_n", "mean_force_" + organ + "_n", "contact_time_" + organ + "_s",
          "time_over_threshold_" + organ + "_s"};
}

bool is_metric_name(const std::string& name, const std::vector<std::string>& organ_names) {
  const std::vector<std::string>& fixed = fixed_metric_names();
  if (std::find(fixed.begin(), fixed.end(), name) != fixed.end()) return true;
  std::vector<std::string> organs = {"duct"};
  for (const std::string& o : organ_names) organs.push_back(snake_case(o));
  return std::any_of(organs.begin(), organs.end(), [&](const std::string& o) {
    const std::vector<std::string> names = organ_metric_names(o);
    return std::find(names.begin(), names.end(), name) != names.end();
  });
}

}  // namespace lap::sim
