#include "tests/fuzz/fuzz_targets.h"

#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "haptics/setup/mesh_repair.h"
#include "haptics/setup/mesh_validation.h"
#include "hardware/device_recording.h"
#include "hardware/gripper_protocol.h"
#include "hardware/scripted_trajectory.h"
#include "sim/report/recorded_frames.h"
#include "sim/report/recorded_tunings.h"
#include "sim/report/recording_reader.h"
#include "sim/report/session_replay.h"
#include "sim/setup/gltf_albedo.h"
#include "sim/setup/height_image_loader.h"
#include "sim/setup/mesh_loader.h"
#include "sim/setup/scenario_loader.h"
#include "sim/setup/scene.h"

namespace lap::fuzz {
namespace {

// A folder of this process's own, made once, for the readers that take a path (the file's
// extension chooses the reader, as it does for a user's file). Removed at exit.
const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern =
        std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/laptrainer-fuzz-XXXXXX";
    if (mkdtemp(pattern.data()) == nullptr) std::abort();
    std::filesystem::path made(pattern);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratch_dir(), ec);
    });
    return made;
  }();
  return dir;
}

// The bytes as the file input.<extension> in the scratch folder.
std::filesystem::path as_file(std::span<const uint8_t> data, std::string_view extension) {
  const std::filesystem::path file = scratch_dir() / ("input." + std::string(extension));
  FILE* f = std::fopen(file.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (!data.empty() && std::fwrite(data.data(), 1, data.size(), f) != data.size()) std::abort();
  if (std::fclose(f) != 0) std::abort();
  return file;
}

std::string_view as_text(std::span<const uint8_t> data) {
  return {reinterpret_cast<const char*>(data.data()), data.size()};
}

// A result the reader accepted must hold what its documentation promises; a broken promise is
// a crash the fuzzer reports (abort), as an ASan finding is.
void require(bool promise) {
  if (!promise) std::abort();
}

bool fuzz_scenario(std::span<const uint8_t> data) {
  // Paths in the text resolve against the scratch folder, which holds the meshes the seeds name
  // (the loader checks that they exist; reading them is the mesh targets' work), so that the
  // fuzzer starts from scenarios the loader accepts and mutates every field's checks from there.
  static const bool meshes_made = [] {
    constexpr std::string_view kTetra =
        "v 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nv 0 0 0.01\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    const std::span<const uint8_t> tetra(reinterpret_cast<const uint8_t*>(kTetra.data()),
                                         kTetra.size());
    for (const char* name : {"liver", "gallbladder", "cystic_duct"}) {
      std::filesystem::rename(as_file(tetra, "obj"), scratch_dir() / (std::string(name) + ".obj"));
    }
    return true;
  }();
  (void)meshes_made;
  // The whole loader, as `validate` runs it: the file read (its limits), the YAML checked, the
  // meshes and height maps it names loaded and validated.
  return sim::load_scene_file(as_file(data, "yaml")).ok();
}

// A recorded session's record, as `report --session` reads it (sim/report/session_replay.h).
bool fuzz_session_record(std::span<const uint8_t> data) {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = scratch_dir() / "session";
    std::filesystem::create_directory(d);
    return d;
  }();
  std::filesystem::rename(as_file(data, "json"), dir / "session.json");
  const Result<sim::SessionRecord> r = sim::read_session_record(dir);
  if (!r.ok()) return false;
  // What the replay relies on: rates and a duration within the record's limits, the modelling
  // loop no faster than the haptic one, an absolute path to the scenario.
  const sim::RuntimeSettings& s = r.value().settings;
  require(s.haptic_rate_hz > 0.0 && s.haptic_rate_hz <= 10000.0);
  require(s.model_rate_hz > 0.0 && s.model_rate_hz <= s.haptic_rate_hz);
  require(s.duration_s > 0.0 && s.duration_s <= 86400.0);
  require(r.value().scenario.is_absolute());
  return true;
}

// As `laptrainer-cli mesh-info --repair` does: read, validate, measure, repair, validate again.
bool fuzz_mesh(std::span<const uint8_t> data, std::string_view extension) {
  Result<haptics::TriangleMesh> loaded = sim::load_mesh(as_file(data, extension));
  if (!loaded.ok()) return false;
  haptics::TriangleMesh& mesh = loaded.value();
  // The reader promises finite vertices and in-range indices (issue 25: validation crashed on
  // a face pointing past a dropped vertex).
  for (const Eigen::Vector3d& v : mesh.positions) require(v.allFinite());
  for (const haptics::Triangle& t : mesh.triangles) {
    for (const int32_t corner : t) require(corner >= 0 && corner < mesh.vertex_count());
  }
  const haptics::MeshDiagnostics before = haptics::validate_mesh(mesh);
  (void)before.describe();
  (void)mesh.surface_area();
  (void)mesh.signed_volume();
  (void)haptics::repair_mesh(mesh);
  (void)haptics::validate_mesh(mesh);
  return true;
}

bool fuzz_height_image(std::span<const uint8_t> data) {
  const Result<haptics::HeightImage> image = sim::load_height_image(as_file(data, "png"));
  if (!image.ok()) return false;
  const haptics::HeightImage& h = image.value();
  require(h.width > 0 && h.height > 0);
  require(static_cast<int64_t>(h.width) * h.height <= sim::kMaxHeightMapPixels);
  require(static_cast<int64_t>(h.values.size()) == static_cast<int64_t>(h.width) * h.height);
  for (const float v : h.values) require(v >= 0.0F && v <= 1.0F);
  return true;
}

// An organ's colour texture as the scene's set-up reads it (sim/setup/gltf_albedo.h): the bytes
// are the image a fixed, valid .gltf names as its base colour.
bool fuzz_gltf_albedo(std::span<const uint8_t> data) {
  static const std::filesystem::path gltf = [] {
    const std::filesystem::path dir = scratch_dir() / "albedo";
    std::filesystem::create_directory(dir);
    const std::filesystem::path file = dir / "organ.gltf";
    constexpr std::string_view kGltf =
        R"({"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {}, )"
        R"("material": 0}]}], "materials": [{"pbrMetallicRoughness": {"baseColorTexture": )"
        R"({"index": 0}}}], "textures": [{"source": 0}], "images": [{"uri": "albedo.png"}]})";
    std::filesystem::rename(
        as_file({reinterpret_cast<const uint8_t*>(kGltf.data()), kGltf.size()}, "gltf"), file);
    return file;
  }();
  std::filesystem::rename(as_file(data, "png"), gltf.parent_path() / "albedo.png");
  const Result<std::shared_ptr<const haptics::RgbImage>> image = sim::load_gltf_albedo(gltf);
  if (!image.ok()) return false;
  require(image.value() != nullptr);  // the file names an image: decoded or refused
  const haptics::RgbImage& rgb = *image.value();
  require(rgb.width > 0 && rgb.height > 0 && rgb.width <= sim::kMaxAlbedoSide &&
          rgb.height <= sim::kMaxAlbedoSide);
  require(static_cast<int64_t>(rgb.width) * rgb.height <= sim::kMaxAlbedoPixels);
  require(rgb.rgb.size() == static_cast<size_t>(rgb.width) * rgb.height * 3);
  return true;
}

bool fuzz_keyframes(std::span<const uint8_t> data) {
  const Result<hardware::ScriptedTrajectory> script =
      hardware::parse_scripted_trajectory(std::string(as_text(data)), "fuzz.csv");
  if (!script.ok()) return false;
  // Sampled forwards across the script and past both ends: every sample finite.
  const double end_s = script.value().duration_s();
  size_t cursor = 0;
  hardware::DeviceSample s;
  for (int k = -2; k <= 102; ++k) {
    script.value().sample(end_s * k / 100.0, &cursor, &s);
    require(s.position_W.allFinite());
  }
  return true;
}

bool fuzz_device_recording(std::span<const uint8_t> data) {
  return hardware::read_device_recording(as_file(data, "lapdev")).ok();
}

bool fuzz_session_recording(std::span<const uint8_t> data) {
  const Result<sim::RecordedSession> r = sim::read_session_recording(as_file(data, "lrec"));
  if (!r.ok()) return false;
  // What a replay relies on: the devices' samples and the ticks cover the same ticks.
  for (const hardware::DeviceRecording& d : r.value().devices) {
    require(d.samples.empty() || d.samples.size() == r.value().ticks.size());
    for (const hardware::RecordedSample& s : d.samples) require(s.sample.position_W.allFinite());
  }
  // What a lockstep replay relies on: finite lateness, reads of no negative step, steps reading
  // ticks in order.
  for (const sim::TickLog& t : r.value().ticks) {
    require(std::isfinite(t.lateness_s) && t.model_steps_read >= 0 && t.surface_steps_read >= 0);
    // What the touches' description and the replay's check rely on (touch_departure.h).
    for (const sim::ToolTouch& touch : t.touch) {
      require(touch.organs <= touch.contacts);
      int32_t listed = 0;
      for (size_t k = 0; k < touch.listed(); ++k) {
        require(std::isfinite(touch.force_n[k]) && touch.force_n[k] >= 0.0F);
        listed += touch.organ_contacts[k];
      }
      require(listed <= touch.contacts);
    }
  }
  int64_t last = -1;
  for (const sim::StepLog& s : r.value().steps) {
    require(s.haptic_tick_read >= last);
    last = s.haptic_tick_read;
  }
  // What a replay's tunings rely on (TunedSurfaces::set would refuse the rest): in tick order,
  // values finite, not negative, μd at most μs; and the notes on them (recorded_tunings.h).
  int64_t tuned = 0;
  for (const sim::TuningLog& t : r.value().tunings) {
    const sim::SurfaceParameters& p = t.parameters;
    require(t.tick >= tuned && t.organ >= 0 && p.friction_dynamic <= p.friction_static);
    for (const double v : {p.stiffness_n_per_m, p.damping_n_s_per_m, p.friction_static,
                           p.friction_dynamic, p.texture_scale}) {
      require(std::isfinite(v) && v >= 0.0);
    }
    tuned = t.tick;
  }
  (void)sim::recorded_tuning_notes(r.value().ticks, r.value().tunings, r.value().version, 8,
                                   1000.0);
  // Seeking by its frames (LAPREC05, recorded_frames.h): every frame a seek gives is whole and
  // finite, whatever the chunks hold.
  Result<sim::RecordedFrames> frames = sim::RecordedFrames::open(as_file(data, "lrec"));
  if (frames.ok()) {
    sim::ReplayFrame f;
    const double end_s = frames.value().duration_s();
    require(std::isfinite(end_s) && end_s >= 0.0);
    for (int k = -1; k <= 11; ++k) {
      if (!frames.value().seek(end_s * k / 10.0, &f).ok()) continue;
      require(f.tick >= 0 && std::isfinite(f.t_s) && f.tools[0].hinge_W.allFinite());
      for (const Eigen::Vector3d& x : f.catheter) require(x.allFinite());
      for (const sim::SurfaceDeformation& d : f.organs) {
        require(d.count >= 0 && static_cast<size_t>(d.count) == d.vertex.size() &&
                d.vertex.size() == d.position.size());
      }
    }
    // What the review loads at once (ReplayTimeline::from_recorded_frames): in time order.
    const std::vector<sim::ReplayFrame> all = frames.value().all();
    for (size_t k = 1; k < all.size(); ++k) require(all[k].tick > all[k - 1].tick);
  }
  return r.value().problems.empty();
}

// A report that decodes, encoded again, decodes to the same values (reserved bytes aside).
bool fuzz_gripper_report(std::span<const uint8_t> data) {
  namespace g = hardware::gripper;
  if (const Result<g::StateReport> s = g::decode_state(data); s.ok()) {
    const Result<g::StateReport> again = g::decode_state(g::encode(s.value()));
    require(again.ok());
    const g::StateReport& a = s.value();
    const g::StateReport& b = again.value();
    require(a.flags == b.flags && a.sequence == b.sequence &&
            a.encoder_counts == b.encoder_counts && a.motor_current_ma == b.motor_current_ma &&
            a.device_time_ms == b.device_time_ms);
    return true;
  }
  if (const Result<g::CommandReport> c = g::decode_command(data); c.ok()) {
    const Result<g::CommandReport> again = g::decode_command(g::encode(c.value()));
    require(again.ok());
    const g::CommandReport& a = c.value();
    const g::CommandReport& b = again.value();
    require(a.motor_enabled == b.motor_enabled && a.sequence == b.sequence &&
            a.squeeze_mn == b.squeeze_mn);
    return true;
  }
  return false;
}

constexpr std::array kTargets = {
    FuzzTarget{"scenario", &fuzz_scenario},
    FuzzTarget{"mesh_obj", [](std::span<const uint8_t> d) { return fuzz_mesh(d, "obj"); }},
    FuzzTarget{"mesh_stl", [](std::span<const uint8_t> d) { return fuzz_mesh(d, "stl"); }},
    FuzzTarget{"mesh_ply", [](std::span<const uint8_t> d) { return fuzz_mesh(d, "ply"); }},
    FuzzTarget{"mesh_off", [](std::span<const uint8_t> d) { return fuzz_mesh(d, "off"); }},
    FuzzTarget{"mesh_gltf", [](std::span<const uint8_t> d) { return fuzz_mesh(d, "gltf"); }},
    FuzzTarget{"mesh_glb", [](std::span<const uint8_t> d) { return fuzz_mesh(d, "glb"); }},
    FuzzTarget{"height_image", &fuzz_height_image},
    FuzzTarget{"gltf_albedo", &fuzz_gltf_albedo},
    FuzzTarget{"keyframes", &fuzz_keyframes},
    FuzzTarget{"device_recording", &fuzz_device_recording},
    FuzzTarget{"session_recording", &fuzz_session_recording},
    FuzzTarget{"session_record", &fuzz_session_record},
    FuzzTarget{"gripper_report", &fuzz_gripper_report},
};

}  // namespace

std::span<const FuzzTarget> fuzz_targets() { return kTargets; }

const FuzzTarget* find_fuzz_target(std::string_view name) {
  for (const FuzzTarget& t : kTargets) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

}  // namespace lap::fuzz
