#include "sim/report/replay_timeline.h"

#include <algorithm>
#include <cmath>

#include "sim/report/recorded_frames.h"
#include "sim/setup/device_factory.h"

namespace lap::sim {

SurfaceDeformation compact(const SurfaceDeformation& d) {
  const auto n = static_cast<size_t>(std::max<int32_t>(0, d.count));
  SurfaceDeformation c(0);
  c.count = d.count;
  c.vertex.assign(d.vertex.begin(), d.vertex.begin() + static_cast<std::ptrdiff_t>(n));
  c.position.assign(d.position.begin(), d.position.begin() + static_cast<std::ptrdiff_t>(n));
  return c;
}

// What the 3D view needs once, from the session set up over the scene (replay_timeline.h).
ReplayScene replay_scene(const Session& session, const Scene& scene) {
  ReplayScene s;
  for (int32_t o = 0; o < session.organ_count(); ++o) {
    s.organ_surfaces.push_back(session.organ_surface(o));
  }
  for (const Organ& o : scene.organs) {
    s.organ_colours.push_back(o.color);
    s.organ_albedos.push_back(o.albedo);
  }
  s.tools = {session.tool_geometry(0), session.tool_geometry(1)};
  for (size_t side = 0; side < 2; ++side) {
    const ToolSpec* tool =
        scene.scenario.tool(side == 0 ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight);
    if (tool != nullptr) {
      s.tool_kinds[side] = tool->kind;
      s.tool_shaft_radius_m[side] = tool->shaft_radius_m;
    }
    s.tool_port_W[side] = session.model().tool(side).trocar.port_W;
  }
  s.catheter_radius_m = session.model().tissue().catheter_model().radius_m();
  // Drawn where the scenario has a catheter or a task (app/session_actors.cpp): -1, none.
  if (!scene.scenario.catheter && !scene.scenario.task) s.catheter_points = -1;
  s.camera = scene.scenario.camera;
  return s;
}

Result<ReplayTimeline> ReplayTimeline::from_recorded_frames(const std::filesystem::path& dir) {
  Result<RecordedFrames> opened = RecordedFrames::open(dir / "session.lrec");
  if (!opened.ok()) return opened.diagnostics();
  Result<ReplayScenario> loaded = load_replay_scenario(dir);
  if (!loaded.ok()) return loaded.diagnostics();
  // The organs, tools and ports as the session set them up; simulated devices stand in for the
  // recorded ones (the geometry does not depend on them), and the session is never run.
  const Scene& scene = loaded.value().scene;
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices;
  for (int side = 0; side < 2; ++side) {
    hardware::DeviceSpec spec;
    spec.kind = hardware::DeviceKind::kSimulated;
    auto device = make_device(spec, scene, side);
    if (!device.ok()) return device.diagnostics();
    devices[static_cast<size_t>(side)] = std::move(device).value();
  }
  RuntimeSettings rs = loaded.value().session.record.settings;
  rs.fast = true;
  rs.duration_s = 1.0;  // never run: no room for a long recording
  auto session = Session::create(scene, std::move(devices), rs);
  if (!session.ok()) return session.diagnostics();
  ReplayTimeline timeline;
  timeline.scene_ = replay_scene(*session.value(), scene);
  timeline.frames_ = opened.value().all();
  if (timeline.frames_.empty()) {
    return file_diagnostic((dir / "session.lrec").string(), 0, "", "no frame reads");
  }
  if (timeline.scene_.catheter_points == 0) {
    timeline.scene_.catheter_points = static_cast<int>(timeline.frames_.front().catheter.size());
  }
  timeline.session_ = std::move(loaded.value().session);
  timeline.session_.recording_problems = opened.value().problems();
  return timeline;
}

Result<ReplayTimeline> ReplayTimeline::replay(const std::filesystem::path& dir,
                                              double frame_period_s,
                                              const std::function<bool(double)>& progress) {
  if (!(frame_period_s > 0.0) || !std::isfinite(frame_period_s)) {
    return diagnostic("replay: frame period: expected a positive number of seconds");
  }
  ReplayTimeline timeline;
  bool stopped = false;
  Result<ReplayedSession> replayed =
      replay_session(dir, {}, [&](Session& session, const Scene& scene) {
        timeline.scene_ = replay_scene(session, scene);
        const SessionTiming& timing = session.model().timing();
        const double dt_s = timing.dt_s;
        const double max_ticks = std::max<double>(1.0, static_cast<double>(timing.max_ticks));
        const auto every =
            std::max<int64_t>(1, static_cast<int64_t>(std::llround(frame_period_s / dt_s)));
        timeline.frames_.reserve(static_cast<size_t>(max_ticks / static_cast<double>(every)) + 2);
        session.observe_fast(
            [&timeline, &session, &stopped, &progress, dt_s, max_ticks](
                int64_t tick, const HapticSnapshot& haptic, const ModelSnapshot& model) {
              ReplayFrame f;
              f.tick = tick;
              f.t_s = static_cast<double>(tick) * dt_s;
              for (size_t i = 0; i < 2; ++i) {
                f.tools[i] = haptic.tools[i].pose;
                f.proxy_a_W[i] = haptic.tools[i].proxy_a_W;
                f.proxy_b_W[i] = haptic.tools[i].proxy_b_W;
                f.proxy_normal_W[i] = haptic.tools[i].proxy_normal_W;
              }
              f.model_steps = model.steps;
              f.catheter = model.catheter;
              f.organs.reserve(model.organs.size());
              for (const SurfaceDeformation& d : model.organs) f.organs.push_back(compact(d));
              if (timeline.scene_.catheter_points == 0) {
                timeline.scene_.catheter_points = static_cast<int>(model.catheter.size());
              }
              timeline.frames_.push_back(std::move(f));
              if (progress && !progress(static_cast<double>(tick) / max_ticks)) {
                stopped = true;
                session.request_stop();
              }
            },
            every);
      });
  if (!replayed.ok()) return replayed.diagnostics();
  timeline.session_ = std::move(replayed).value();
  if (stopped) {
    timeline.session_.notes.push_back("the replay was stopped at " +
                                      std::to_string(timeline.duration_s()) +
                                      " s: its figures cover that much of the session");
  }
  return timeline;
}

ReplayTimeline ReplayTimeline::from_frames(ReplayScene scene, std::vector<ReplayFrame> frames) {
  ReplayTimeline t;
  t.scene_ = std::move(scene);
  t.frames_ = std::move(frames);
  return t;
}

size_t ReplayTimeline::seek(double t_s) const {
  if (frames_.empty()) return 0;
  // The first frame after t, then one back: the frame at or before t. A frame's time is
  // tick × period and a time asked for is often a rounded one (the scrub bar's milliseconds):
  // a nanosecond's tolerance keeps 9.95 from landing on the frame before 9.950000000000001.
  constexpr double kToleranceS = 1e-9;
  const auto after = std::upper_bound(frames_.begin(), frames_.end(), t_s + kToleranceS,
                                      [](double t, const ReplayFrame& f) { return t < f.t_s; });
  if (after == frames_.begin()) return 0;
  return static_cast<size_t>(after - frames_.begin()) - 1;
}

double ReplayTimeline::duration_s() const { return frames_.empty() ? 0.0 : frames_.back().t_s; }

void ReplayTimeline::snapshots(size_t i, HapticSnapshot* haptic, ModelSnapshot* model) const {
  if (frames_.empty()) return;
  const ReplayFrame& f = frames_[std::min(i, frames_.size() - 1)];
  haptic->tick = f.tick;
  for (size_t k = 0; k < 2; ++k) {
    haptic->tools[k].pose = f.tools[k];
    haptic->tools[k].proxy_a_W = f.proxy_a_W[k];
    haptic->tools[k].proxy_b_W = f.proxy_b_W[k];
    haptic->tools[k].proxy_normal_W = f.proxy_normal_W[k];
  }
  model->tick = f.tick;
  model->steps = f.model_steps;
  model->catheter.assign(f.catheter.begin(), f.catheter.end());
  model->organs.resize(f.organs.size());
  for (size_t o = 0; o < f.organs.size(); ++o) {
    SurfaceDeformation& d = model->organs[o];
    d.count = f.organs[o].count;
    d.vertex.assign(f.organs[o].vertex.begin(), f.organs[o].vertex.end());
    d.position.assign(f.organs[o].position.begin(), f.organs[o].position.end());
  }
}

}  // namespace lap::sim
