#include "hardware/scripted_trajectory.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/bounded_file.h"

namespace lap::hardware {
namespace {

bool parse_double(std::string_view s, double* v) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  // A leading '+', as spreadsheets and hand-written files have it (from_chars takes none); one
  // sign only.
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && (s.front() == '+' || s.front() == '-')) return false;
  }
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  const auto r = std::from_chars(s.data(), end, *v);
  return r.ec == std::errc() && r.ptr == end && std::isfinite(*v);
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

// `file:line: field: message`. Without a file name the text is kept as it always printed
// (":line: ...").

constexpr const char* kFieldNames[] = {"time_s", "x_m", "y_m", "z_m",         "qw",
                                       "qx",     "qy",  "qz",  "gripper_rad", "buttons"};

}  // namespace

void ScriptedTrajectory::sample(double t, size_t* cursor, DeviceSample* out) const {
  const size_t n = keyframes.size();
  size_t i = *cursor < n ? *cursor : 0;
  if (keyframes[i].time_s > t) i = 0;
  while (i + 1 < n && keyframes[i + 1].time_s <= t) ++i;
  *cursor = i;
  const Keyframe& k0 = keyframes[i];
  out->time_s = t;
  out->buttons = k0.buttons;
  if (i + 1 == n || t <= k0.time_s) {
    // Held at either end, and exactly the keyframe at its own time.
    out->position_W = k0.position_W;
    out->orientation_W = k0.orientation_W;
    out->gripper_angle_rad = k0.gripper_angle_rad;
    out->velocity_W.setZero();
    if (i + 1 < n && t == k0.time_s) {
      const Keyframe& k1 = keyframes[i + 1];
      out->velocity_W = (k1.position_W - k0.position_W) / (k1.time_s - k0.time_s);
    }
    return;
  }
  const Keyframe& k1 = keyframes[i + 1];
  const double span = k1.time_s - k0.time_s;
  const double alpha = (t - k0.time_s) / span;
  out->position_W = k0.position_W + alpha * (k1.position_W - k0.position_W);
  out->orientation_W = k0.orientation_W.slerp(alpha, k1.orientation_W);
  out->gripper_angle_rad =
      k0.gripper_angle_rad + alpha * (k1.gripper_angle_rad - k0.gripper_angle_rad);
  out->velocity_W = (k1.position_W - k0.position_W) / span;
}

Result<ScriptedTrajectory> parse_scripted_trajectory(const std::string& text,
                                                     const std::string& source) {
  ScriptedTrajectory tr;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  bool first_content = true;
  auto fail = [&](const std::string& what,
                  const std::string& field = "") -> Result<ScriptedTrajectory> {
    return file_diagnostic(source, line_no, field, what);
  };
  while (std::getline(in, line)) {
    ++line_no;
    std::string_view v(line);
    while (!v.empty() && (v.back() == '\r' || v.back() == ' ' || v.back() == '\t')) {
      v.remove_suffix(1);
    }
    size_t lead = 0;
    while (lead < v.size() && (v[lead] == ' ' || v[lead] == '\t')) ++lead;
    v.remove_prefix(lead);
    if (v.empty() || v.front() == '#') continue;
    const bool numeric = std::isdigit(static_cast<unsigned char>(v.front())) != 0 ||
                         v.front() == '-' || v.front() == '+' || v.front() == '.';
    if (first_content && !numeric) {
      first_content = false;
      continue;  // header
    }
    first_content = false;
    const std::vector<std::string_view> f = split(v);
    if (f.size() != 9 && f.size() != 10) {
      return fail(
          "expected 9 or 10 comma-separated fields "
          "(time_s,x_m,y_m,z_m,qw,qx,qy,qz,gripper_rad[,buttons]), got " +
          std::to_string(f.size()));
    }
    double x[10] = {};
    for (size_t k = 0; k < f.size(); ++k) {
      if (!parse_double(f[k], &x[k])) {
        return fail("expected a finite number, got '" + std::string(f[k]) + "'", kFieldNames[k]);
      }
    }
    Keyframe kf;
    kf.time_s = x[0];
    kf.position_W = {x[1], x[2], x[3]};
    const Eigen::Quaterniond q(x[4], x[5], x[6], x[7]);
    if (!(q.norm() > 1e-12)) return fail("expected a non-zero quaternion", "qw,qx,qy,qz");
    kf.orientation_W = q.normalized();
    kf.gripper_angle_rad = x[8];
    if (f.size() == 10) {
      if (x[9] < 0.0 || x[9] > 4294967295.0 || x[9] != std::floor(x[9])) {
        return fail("expected a whole number from 0 to 4294967295", "buttons");
      }
      kf.buttons = static_cast<uint32_t>(x[9]);
    }
    if (kf.time_s < 0.0) return fail("expected a time >= 0", "time_s");
    if (!tr.keyframes.empty() && !(kf.time_s > tr.keyframes.back().time_s)) {
      return fail("expected times to increase, " + std::string(f[0]) +
                      " does not follow the previous keyframe",
                  "time_s");
    }
    if (tr.keyframes.size() >= kMaxKeyframes) {
      return fail("expected at most " + std::to_string(kMaxKeyframes) +
                  " keyframes (the limit, hardware/scripted_trajectory.h)");
    }
    tr.keyframes.push_back(kf);
  }
  if (tr.keyframes.empty()) {
    line_no = std::max(line_no, 1);
    return fail("expected at least one keyframe");
  }
  return tr;
}

Result<ScriptedTrajectory> load_scripted_trajectory(const std::filesystem::path& file) {
  const Result<std::string> text = read_bounded_file(
      file, kMaxScriptFileBytes, "a keyframe script (CSV)", "hardware/scripted_trajectory.h");
  if (!text.ok()) return text.diagnostics();
  return parse_scripted_trajectory(text.value(), file.string());
}

}  // namespace lap::hardware
