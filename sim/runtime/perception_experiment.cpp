#include "sim/runtime/perception_experiment.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

namespace lap::sim {
namespace {

// A uniform number in [0, 1) from the generator's raw 32-bit output (platform-independent, unlike
// the standard distributions).
double unit(std::mt19937* rng) { return static_cast<double>((*rng)()) / 4294967296.0; }

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  const size_t b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

}  // namespace

std::string_view to_string(PerceivedShape shape) {
  switch (shape) {
    case PerceivedShape::kSphere:
      return "sphere";
    case PerceivedShape::kCone:
      return "cone";
    case PerceivedShape::kCylinder:
      return "cylinder";
    case PerceivedShape::kCube:
      return "cube";
  }
  return "sphere";
}

std::optional<PerceivedShape> parse_perceived_shape(std::string_view text) {
  for (const PerceivedShape s : kPerceivedShapes) {
    if (to_string(s) == text) return s;
  }
  return std::nullopt;
}

std::string_view to_string(ProbeMode mode) { return mode == ProbeMode::kPoint ? "point" : "ray"; }

std::optional<ProbeMode> parse_probe_mode(std::string_view text) {
  if (text == "point") return ProbeMode::kPoint;
  if (text == "ray") return ProbeMode::kRay;
  return std::nullopt;
}

Result<PerceptionExperiment> PerceptionExperiment::create(const PerceptionSettings& settings) {
  if (settings.repetitions < 1 || settings.repetitions > 1000) {
    return Diagnostic{"", 0, "repetitions", "expected 1 to 1000 per shape and mode"};
  }
  if (settings.modes.empty() || settings.modes.size() > 2 ||
      (settings.modes.size() == 2 && settings.modes[0] == settings.modes[1])) {
    return Diagnostic{"", 0, "modes", "expected point, ray or both, each once"};
  }
  PerceptionExperiment e;
  for (const ProbeMode mode : settings.modes) {
    for (const PerceivedShape shape : kPerceivedShapes) {
      for (int32_t r = 0; r < settings.repetitions; ++r) {
        PerceptionTrial t;
        t.shape = shape;
        t.mode = mode;
        t.repetition = r;
        e.trials_.push_back(t);
      }
    }
  }
  std::mt19937 rng(settings.seed);
  for (size_t i = e.trials_.size(); i > 1; --i) {
    std::swap(e.trials_[i - 1], e.trials_[rng() % i]);
  }
  for (size_t i = 0; i < e.trials_.size(); ++i) {
    PerceptionTrial& t = e.trials_[i];
    t.index = static_cast<int32_t>(i);
    // Shoemake (Graphics Gems III): a uniformly distributed unit quaternion from three uniforms.
    const double u1 = unit(&rng);
    const double u2 = 2.0 * M_PI * unit(&rng);
    const double u3 = 2.0 * M_PI * unit(&rng);
    const double a = std::sqrt(1.0 - u1);
    const double b = std::sqrt(u1);
    t.orientation =
        Eigen::Quaterniond(a * std::sin(u2), a * std::cos(u2), b * std::sin(u3), b * std::cos(u3))
            .normalized();
  }
  e.answers_.reserve(e.trials_.size());
  return e;
}

Status PerceptionExperiment::start_trial(double t_s) {
  if (done()) return diagnostic("the experiment is over: no trial to start");
  if (!std::isfinite(t_s)) return diagnostic("the start time must be finite");
  started_s_ = t_s;
  return {};
}

Status PerceptionExperiment::answer(PerceivedShape named, double t_s) {
  if (done()) return diagnostic("the experiment is over: no trial to answer");
  if (!started_s_) return diagnostic("trial " + std::to_string(next_) + " was not started");
  if (!(t_s >= *started_s_)) return diagnostic("an answer before its trial started");
  answers_.push_back({trials_[next_], named, t_s - *started_s_});
  ++next_;
  started_s_.reset();
  return {};
}

PerceptionTable tabulate(const std::vector<PerceptionAnswer>& answers) {
  PerceptionTable table;
  for (size_t s = 0; s < kPerceivedShapes.size(); ++s) {
    std::array<std::optional<double>, 2> mean{};
    for (const ProbeMode mode : {ProbeMode::kPoint, ProbeMode::kRay}) {
      PerceptionRow row;
      row.shape = kPerceivedShapes[s];
      row.mode = mode;
      double sum = 0.0;
      for (const PerceptionAnswer& a : answers) {
        if (a.trial.shape != row.shape || a.trial.mode != mode) continue;
        ++row.trials;
        if (a.correct()) ++row.correct;
        sum += a.time_s;
      }
      if (row.trials == 0) continue;
      row.mean_time_s = sum / row.trials;
      double sq = 0.0;
      for (const PerceptionAnswer& a : answers) {
        if (a.trial.shape != row.shape || a.trial.mode != mode) continue;
        sq += (a.time_s - row.mean_time_s) * (a.time_s - row.mean_time_s);
      }
      row.sd_time_s = row.trials > 1 ? std::sqrt(sq / (row.trials - 1)) : 0.0;
      mean[mode == ProbeMode::kPoint ? 0 : 1] = row.mean_time_s;
      table.rows.push_back(row);
    }
    if (mean[0] && mean[1] && *mean[0] > 0.0) {
      table.ray_faster_percent[s] = (*mean[0] - *mean[1]) / *mean[0] * 100.0;
    }
  }
  return table;
}

std::string to_csv(const PerceptionTable& table) {
  std::string out =
      "shape,mode,trials,correct,percent_correct,mean_time_s,sd_time_s,ray_faster_percent\n";
  char buf[256];
  for (const PerceptionRow& r : table.rows) {
    std::string faster;
    const auto s = static_cast<size_t>(r.shape);
    if (r.mode == ProbeMode::kRay && table.ray_faster_percent[s]) {
      char f[32];
      std::snprintf(f, sizeof f, "%.2f", *table.ray_faster_percent[s]);
      faster = f;
    }
    std::snprintf(buf, sizeof buf, "%s,%s,%d,%d,%.2f,%.4f,%.4f,%s\n",
                  std::string(to_string(r.shape)).c_str(), std::string(to_string(r.mode)).c_str(),
                  r.trials, r.correct, 100.0 * r.correct / r.trials, r.mean_time_s, r.sd_time_s,
                  faster.c_str());
    out += buf;
  }
  return out;
}

std::string to_csv(const std::vector<PerceptionAnswer>& answers) {
  std::string out =
      "trial,shape,mode,repetition,orientation_w,orientation_x,orientation_y,orientation_z,named,"
      "correct,time_s\n";
  char buf[320];
  for (const PerceptionAnswer& a : answers) {
    const PerceptionTrial& t = a.trial;
    const Eigen::Quaterniond& q = t.orientation;
    std::snprintf(buf, sizeof buf, "%d,%s,%s,%d,%.6f,%.6f,%.6f,%.6f,%s,%d,%.4f\n", t.index + 1,
                  std::string(to_string(t.shape)).c_str(), std::string(to_string(t.mode)).c_str(),
                  t.repetition, q.w(), q.x(), q.y(), q.z(), std::string(to_string(a.named)).c_str(),
                  a.correct() ? 1 : 0, a.time_s);
    out += buf;
  }
  return out;
}

Result<std::vector<ScriptedAnswer>> parse_scripted_answers(const std::string& text,
                                                           const std::string& source) {
  std::vector<ScriptedAnswer> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    if (out.empty() && t.rfind("shape,", 0) == 0) continue;  // the header
    std::vector<std::string> f;
    std::stringstream cells(t);
    std::string cell;
    while (std::getline(cells, cell, ',')) f.push_back(trim(cell));
    auto problem = [&](const std::string& field, const std::string& what) {
      return Diagnostic{source, number, field, what};
    };
    if (f.size() != 5) {
      return problem("", "expected shape,mode,repetition,named,time_s, got " +
                             std::to_string(f.size()) + " fields");
    }
    ScriptedAnswer a;
    const auto shape = parse_perceived_shape(f[0]);
    if (!shape)
      return problem("shape", "expected sphere, cone, cylinder or cube, got '" + f[0] + "'");
    a.shape = *shape;
    const auto mode = parse_probe_mode(f[1]);
    if (!mode) return problem("mode", "expected point or ray, got '" + f[1] + "'");
    a.mode = *mode;
    char* end = nullptr;
    const long rep = std::strtol(f[2].c_str(), &end, 10);
    if (f[2].empty() || *end != '\0' || rep < 0 || rep > 1000) {
      return problem("repetition", "expected a whole number from 0 to 1000, got '" + f[2] + "'");
    }
    a.repetition = static_cast<int32_t>(rep);
    const auto named = parse_perceived_shape(f[3]);
    if (!named)
      return problem("named", "expected sphere, cone, cylinder or cube, got '" + f[3] + "'");
    a.named = *named;
    const double time = std::strtod(f[4].c_str(), &end);
    if (f[4].empty() || *end != '\0' || !std::isfinite(time) || time < 0.0) {
      return problem("time_s", "expected a time of 0 s or more, got '" + f[4] + "'");
    }
    a.time_s = time;
    out.push_back(a);
  }
  return out;
}

Status run_scripted_answers(PerceptionExperiment* experiment,
                            const std::vector<ScriptedAnswer>& script) {
  double t = 0.0;
  while (const PerceptionTrial* trial = experiment->current()) {
    const ScriptedAnswer* found = nullptr;
    for (const ScriptedAnswer& a : script) {
      if (a.shape == trial->shape && a.mode == trial->mode && a.repetition == trial->repetition) {
        found = &a;
        break;
      }
    }
    if (found == nullptr) {
      return diagnostic("no scripted answer for the " + std::string(to_string(trial->shape)) +
                        " in " + std::string(to_string(trial->mode)) + " mode, repetition " +
                        std::to_string(trial->repetition));
    }
    if (Status s = experiment->start_trial(t); !s.ok()) return s;
    t += found->time_s;
    if (Status s = experiment->answer(found->named, t); !s.ok()) return s;
  }
  return {};
}

}  // namespace lap::sim
