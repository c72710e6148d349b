#include "sim/report/touch_departure.h"

#include <algorithm>
#include <cstdio>

namespace lap::sim {

namespace {

std::string organ_name(size_t organ, const std::vector<std::string>& names) {
  return organ < names.size() && !names[organ].empty() ? names[organ]
                                                       : "organ " + std::to_string(organ);
}

std::string newtons(float f) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g N", static_cast<double>(f));
  return text;
}

}  // namespace

std::string describe_touch(const ToolTouch& touch, const std::vector<std::string>& organ_names) {
  std::vector<std::string> parts;
  if (touch.catheter_held) parts.emplace_back("held the catheter");
  if (touch.duct_held) parts.emplace_back("held the duct");
  std::string touched;
  for (size_t k = 0; k < touch.listed(); ++k) {
    const uint16_t n = touch.organ_contacts[k];
    touched += (k == 0 ? "" : ", ") + organ_name(touch.organ[k], organ_names) + " (" +
               std::to_string(n) + (n == 1 ? " contact, " : " contacts, ") +
               newtons(touch.force_n[k]) + ")";
  }
  const size_t more = touch.organs - touch.listed();
  if (more > 0) {
    touched += ", " + std::to_string(more) + (more == 1 ? " more organ" : " more organs");
  }
  parts.push_back(touched.empty() ? "touched nothing" : "touched " + touched);
  std::string text;
  for (size_t i = 0; i < parts.size(); ++i) text += (i == 0 ? "" : ", ") + parts[i];
  return text;
}

std::optional<std::string> touch_departure(std::span<const std::array<ToolTouch, 2>> recorded,
                                           std::span<const TickLog> replayed,
                                           const std::vector<std::string>& organ_names,
                                           double haptic_rate_hz) {
  const size_t n = std::min(recorded.size(), replayed.size());
  for (size_t t = 0; t < n; ++t) {
    for (size_t tool = 0; tool < 2; ++tool) {
      const ToolTouch& live = recorded[t][tool];
      const ToolTouch& again = replayed[t].touch[tool];
      if (live == again) continue;
      char when[48];
      std::snprintf(when, sizeof when, "%.3f s", static_cast<double>(t) / haptic_rate_hz);
      const std::string side = tool == 0 ? "left" : "right";
      return "the replay departs from the session at tick " + std::to_string(t) + " (" + when +
             "): live, the " + side + " tool " + describe_touch(live, organ_names) +
             "; replayed, it " + describe_touch(again, organ_names) +
             ". The replay's figures from there on are not the session's";
    }
  }
  return std::nullopt;
}

}  // namespace lap::sim
