// laptrainer-cli: the headless command line (its contracts: README.md, docs/architecture.md).
// No Qt or VTK here: it must run on machines without a display.

#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/point_proxy.h"
#include "haptics/segment_proxy.h"
#include "haptics/setup/anatomy_parameters.h"
#include "haptics/setup/mesh_generators.h"
#include "haptics/setup/mesh_repair.h"
#include "haptics/setup/mesh_validation.h"
#include "hardware/device_spec.h"
#include "hardware/libusb_transport.h"
#include "hardware/replay_device.h"
#include "hardware/scripted_device.h"
#include "sim/authoring/expert_benchmarks.h"
#include "sim/authoring/expert_run.h"
#include "sim/authoring/perception_run.h"
#include "sim/report/session_pdf.h"
#include "sim/report/session_replay.h"
#include "sim/report/session_report.h"
#include "sim/runtime/session.h"
#include "sim/setup/anatomy_assets.h"
#include "sim/setup/device_factory.h"
#include "sim/setup/mesh_loader.h"
#include "sim/setup/probe_path.h"
#include "sim/setup/scenario_loader.h"
#include "sim/setup/scene.h"

namespace {

namespace fs = std::filesystem;

constexpr int kExitOk = 0;
// `run --record`: the session ran, but not all it was to write at its end could be written (a
// full disk); each file is named, and what was written is kept. Before a signal's 130 or 143.
// (1 is an unexpected exception's, main below.)
constexpr int kExitNotSaved = 3;
constexpr int kExitProblems = 2;  // the input has problems (validate contract)
constexpr int kExitUsage = 64;
// `run` ended early by SIGINT or SIGTERM, cleanly (the shell's 128 + signal number).
constexpr int kExitInterrupted = 128 + SIGINT;  // 130
constexpr int kExitTerminated = 128 + SIGTERM;  // 143

// The signal that asked `run` to stop, 0 while none did. The handler only stores it (an atomic
// store is async-signal-safe); the run's watcher thread acts on it.
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void on_stop_signal(int sig) { g_stop_signal.store(sig, std::memory_order_relaxed); }

// SIGINT and SIGTERM end `run` cleanly. SA_RESETHAND: a second signal ends the process at once,
// for a user whose clean shutdown hangs.
void install_stop_handlers() {
  struct sigaction action = {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

const char* const kUsage =
    "usage: laptrainer-cli COMMAND [options]\n"
    "commands:\n"
    "  validate --scenario FILE [--allow-path DIR]...\n"
    "      check a scenario and its meshes; prints file:line: field: problem; exit 2 on problems\n"
    "  mesh-info --mesh FILE [--scale S] [--repair] [--out FILE.obj]\n"
    "      diagnose a mesh (and optionally repair it and write the result)\n"
    "  probe --mesh FILE [--scale S] [--repair] --path CSV --probe point|segment\n"
    "        [--stiffness N/m] [--max-force N] [--out CSV]\n"
    "      run a proxy along a path (one row per 1 kHz tick) against one mesh and write, per "
    "tick,\n"
    "      the proxy position, force, contact primitive and step time\n"
    "  run --scenario FILE --left DEV --right DEV [--duration S] [--fast] [--record DIR]\n"
    "      [--rate HZ] [--model-rate HZ] [--dominant-hand left|right]\n"
    "      a headless session with the three loops; DEV is simulated, scripted:FILE,\n"
    "      replay:FILE or phantom[:NAME]; it ends with the task, at --duration, or (without\n"
    "      it) when scripted and replayed devices run out (10 s with any other device);\n"
    "      prints the metrics as JSON; SIGINT or SIGTERM\n"
    "      stop it cleanly (forces zeroed, metrics and recording written; exit 130 or 143);\n"
    "      exit 3 when not all of the recording could be written (each file named)\n"
    "  devices\n"
    "      list the actuated USB grippers plugged in (serial, bus path), to name each tool's\n"
    "      with DEV+gripper:SERIAL or DEV+gripper@BUS-PORTS\n"
    "  report --session DIR [--format json|csv|pdf] [--out FILE] [--scenario FILE]\n"
    "         [--allow-path DIR]...\n"
    "      replay a session recorded by run --record and print its task and training metrics,\n"
    "      recomputed from the recorded inputs (json: as run prints them, with the series;\n"
    "      csv: one metric,value row per metric; pdf: the plots and the metrics, needs --out);\n"
    "      the scenario the session names is read only from DIR or the shipped scenarios'\n"
    "      folders: --scenario FILE replays with FILE instead, --allow-path DIR allows DIR\n"
    "  generate-assets --out DIR [--anatomy PRESET|all]\n"
    "      write the project's generated stand-in organ meshes (OBJ) into DIR; with --anatomy,\n"
    "      the generated anatomy instead (glTF 2.0): DIR/PRESET/ per preset (default, easy,\n"
    "      moderate, hard), each with its textures\n"
    "  plan-expert --scenario FILE --out DIR [--mistake drop|overshoot|tear|cbd|time_limit]\n"
    "      plan the expert's catheter insertion for the scenario and write it as keyframe\n"
    "      scripts DIR/expert_left.csv and DIR/expert_right.csv (run them with scripted:FILE);\n"
    "      with --mistake, a clumsy run instead (the catheter dropped, pushed through the wall,\n"
    "      the duct torn, pushed on into the common bile duct, or held at the incision past the\n"
    "      time limit), written as DIR/clumsy_MISTAKE_left.csv and _right.csv\n"
    "  perception --left DEV --right DEV --out DIR [--seed N] [--repetitions 1-1000]\n"
    "             [--modes point,ray] [--size M] [--trial-limit S]\n"
    "      the shape-perception experiment (thesis 5.5): per trial a sphere, cone, cylinder or\n"
    "      cube at a seeded random orientation, felt with the right tool (a point or a ray\n"
    "      probe), nothing drawn; the participant types the shape on standard input; writes\n"
    "      DIR/answers.csv (each trial) and DIR/results.csv (the thesis' table); exit 2 when the\n"
    "      answers end early; SIGINT or SIGTERM stop it (exit 130 or 143); the files hold\n"
    "      the answers given, written after every trial\n"
    "  expert-benchmarks --scenario FILE [--runs N]\n"
    "      plan N expert runs with their approach varied, run each --fast, and print the mean\n"
    "      and SD of the training metrics over those that succeed as the scenario's\n"
    "      proficiency: section (YAML; a stand-in for measured experts)\n";

// Parses --key value pairs and bare --flags after the command.
struct Args {
  std::multimap<std::string, std::string> values;
  std::vector<std::string> errors;

  Args(int argc, char** argv, const std::vector<std::string>& flags) {
    for (int i = 2; i < argc; ++i) {
      const std::string a = argv[i];
      if (a.rfind("--", 0) != 0) {
        errors.push_back("unexpected argument '" + a + "'");
        continue;
      }
      if (std::find(flags.begin(), flags.end(), a) != flags.end()) {
        values.emplace(a, "");
      } else if (i + 1 < argc) {
        values.emplace(a, argv[++i]);
      } else {
        errors.push_back("option " + a + " needs a value");
      }
    }
  }
  [[nodiscard]] bool has(const std::string& k) const { return values.count(k) > 0; }
  [[nodiscard]] std::string get(const std::string& k, const std::string& fallback = "") const {
    const auto it = values.find(k);
    return it == values.end() ? fallback : it->second;
  }
  [[nodiscard]] std::vector<std::string> all(const std::string& k) const {
    std::vector<std::string> out;
    for (auto [it, end] = values.equal_range(k); it != end; ++it) out.push_back(it->second);
    return out;
  }
  bool only(const std::vector<std::string>& allowed) {
    for (const auto& [k, v] : values) {
      if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
        errors.push_back("unknown option " + k);
      }
    }
    return errors.empty();
  }
};

// The whole text as one number, or nothing.
std::optional<double> parse_number(const std::string& text) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// A positive finite number, or nothing.
std::optional<double> parse_positive(const std::string& text) {
  const std::optional<double> v = parse_number(text);
  if (v && std::isfinite(*v) && *v > 0.0) return v;
  return std::nullopt;
}

// Prints each problem as `file:line: field: message` (the app shows the same text) and returns
// the exit code for problems in the input.
int print_problems(const std::vector<lap::Diagnostic>& problems) {
  for (const lap::Diagnostic& d : problems) std::cerr << d.to_string() << "\n";
  return kExitProblems;
}

int usage_error(const Args& args) {
  for (const auto& e : args.errors) std::cerr << "laptrainer-cli: " << e << "\n";
  std::cerr << kUsage;
  return kExitUsage;
}

int cmd_validate(int argc, char** argv) {
  Args args(argc, argv, {});
  if (!args.only({"--scenario", "--allow-path"}) || !args.has("--scenario")) {
    if (!args.has("--scenario")) args.errors.push_back("validate needs --scenario FILE");
    return usage_error(args);
  }
  lap::sim::ScenarioLoadSettings settings;
  for (const auto& p : args.all("--allow-path")) settings.allowed_paths.emplace_back(p);
  const lap::sim::SceneLoadResult r = lap::sim::load_scene_file(args.get("--scenario"), settings);
  if (!r.ok()) {
    for (const auto& p : r.diagnostics()) std::cerr << p.to_string() << "\n";
    std::cerr << r.diagnostics().size() << (r.diagnostics().size() == 1 ? " problem" : " problems")
              << " found\n";
    return kExitProblems;
  }
  std::cout << args.get("--scenario") << ": ok\n" << lap::sim::describe_scene(r.value());
  return kExitOk;
}

int cmd_mesh_info(int argc, char** argv) {
  Args args(argc, argv, {"--repair"});
  if (!args.only({"--mesh", "--scale", "--repair", "--out"}) || !args.has("--mesh")) {
    if (!args.has("--mesh")) args.errors.push_back("mesh-info needs --mesh FILE");
    return usage_error(args);
  }
  lap::sim::MeshLoadSettings load;
  const std::optional<double> scale = parse_number(args.get("--scale", "1"));
  if (!scale) {  // a number that is not positive is the loader's to refuse (exit 2)
    args.errors.push_back("--scale expects a positive number");
    return usage_error(args);
  }
  load.scale = *scale;
  lap::Result<lap::haptics::TriangleMesh> loaded = lap::sim::load_mesh(args.get("--mesh"), load);
  if (!loaded.ok()) return print_problems(loaded.diagnostics());
  lap::haptics::TriangleMesh& mesh = loaded.value();
  {
    auto print = [](const lap::haptics::TriangleMesh& m, const char* label) {
      const lap::haptics::MeshDiagnostics d = lap::haptics::validate_mesh(m);
      // Area and volume index every triangle: not taken while an index is out of range.
      const bool indexable = d.invalid_index_triangles.empty();
      std::printf("%s: %d vertices, %d triangles, %d components, area %.6g m^2, volume %.6g m^3\n",
                  label, m.vertex_count(), m.triangle_count(), d.component_count,
                  indexable ? m.surface_area() : std::nan(""),
                  indexable ? m.signed_volume() : std::nan(""));
      std::printf(
          "  boundary edges %zu, non-manifold edges %zu, non-manifold vertices %zu, "
          "degenerate %zu, duplicate %zu, orientation conflicts %zu, flipped %zu, "
          "fragments %zu, inward components %zu, non-finite %zu\n",
          d.boundary_edges.size(), d.non_manifold_edges.size(), d.non_manifold_vertices.size(),
          d.degenerate_triangles.size(), d.duplicate_triangles.size(),
          d.orientation_conflict_edges.size(), d.flipped_triangles.size(),
          d.sliver_fragments.size(), d.inward_components.size(), d.non_finite_vertices.size());
      for (const auto& line : d.describe()) std::printf("  - %s\n", line.c_str());
      std::printf("  %s\n",
                  d.clean() ? "clean: closed, oriented, outward-facing manifold" : "NOT clean");
      return d.clean();
    };
    bool clean = print(mesh, args.get("--mesh").c_str());
    if (args.has("--repair")) {
      const auto report = lap::haptics::repair_mesh(mesh);
      std::printf("repair: %s\n", report.summary().c_str());
      clean = print(mesh, "after repair");
    }
    if (args.has("--out")) {
      if (lap::Status saved = lap::sim::save_obj(mesh, args.get("--out")); !saved.ok()) {
        return print_problems(saved.diagnostics());
      }
    }
    return clean ? kExitOk : kExitProblems;
  }
}

// The option `key` as a positive number (fallback when absent); false in *ok and a message when
// it is something else.
double positive_option(const Args& args, const std::string& key, double fallback, bool* ok) {
  if (!args.has(key)) return fallback;
  if (const std::optional<double> v = parse_positive(args.get(key))) return *v;
  std::cerr << "laptrainer-cli: " << key << " expects a positive number, got '" << args.get(key)
            << "'\n";
  *ok = false;
  return fallback;
}

using ProbePath = std::vector<Eigen::Matrix<double, 6, 1>>;

// Runs the segment proxy along the path (rows x1..z2) and writes one CSV row per tick.
void run_segment_probe(lap::haptics::HapticObject object, const lap::haptics::MeshDatabase& db,
                       const ProbePath& path, std::ostream& out) {
  // An open mesh is a thin surface, touched from either side (as by the point probe).
  lap::haptics::SegmentDatabaseSettings settings;
  settings.two_sided = object.two_sided;
  const lap::haptics::SegmentDatabase sd = lap::haptics::SegmentDatabase::build(db, settings);
  object.segments = &sd;
  out << "tick,ideal_a_x,ideal_a_y,ideal_a_z,ideal_b_x,ideal_b_y,ideal_b_z,force_x,force_y,"
         "force_z,torque_x,torque_y,torque_z,contact_type,primitive_kind,primitive_id,"
         "step_ns\n";
  lap::haptics::SegmentProxy proxy;
  proxy.reset(path.front().head<3>(), path.front().tail<3>());
  for (size_t i = 0; i < path.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const lap::haptics::SegmentProxyOutput r =
        proxy.step(std::span<const lap::haptics::HapticObject>(&object, 1), path[i].head<3>(),
                   path[i].tail<3>(), 0.001);
    const auto t1 = std::chrono::steady_clock::now();
    std::string type = "none";
    lap::haptics::PrimitiveRef prim;
    if (!proxy.contacts().empty()) {
      type = lap::haptics::to_string(proxy.contacts()[0].kind);
      prim = proxy.contacts()[0].primitive;
    }
    int32_t id = prim.index;
    if (prim.kind == lap::haptics::PrimitiveKind::kFace) id = db.original_face(id);
    out << i << ',' << r.ideal_a_W.x() << ',' << r.ideal_a_W.y() << ',' << r.ideal_a_W.z() << ','
        << r.ideal_b_W.x() << ',' << r.ideal_b_W.y() << ',' << r.ideal_b_W.z() << ','
        << r.force_W.x() << ',' << r.force_W.y() << ',' << r.force_W.z() << ',' << r.torque_W.x()
        << ',' << r.torque_W.y() << ',' << r.torque_W.z() << ',' << type << ','
        << lap::haptics::to_string(prim.kind) << ',' << id << ','
        << std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count() << '\n';
  }
}

// Runs the point proxy along the path (rows x,y,z) and writes one CSV row per tick.
void run_point_probe(const lap::haptics::HapticObject& object, const lap::haptics::MeshDatabase& db,
                     const ProbePath& path, std::ostream& out) {
  out << "tick,ihip_x,ihip_y,ihip_z,force_x,force_y,force_z,contact_kind,primitive_id,step_ns\n";
  lap::haptics::PointProxy proxy;
  proxy.reset(path.front().head<3>());
  for (size_t i = 0; i < path.size(); ++i) {
    const Eigen::Vector3d hip = path[i].head<3>();
    const auto t0 = std::chrono::steady_clock::now();
    const lap::haptics::PointProxyOutput r =
        proxy.step(std::span<const lap::haptics::HapticObject>(&object, 1), hip, 0.001);
    const auto t1 = std::chrono::steady_clock::now();
    // Faces are reported by their index in the input mesh, not the tree order.
    int32_t id = r.primitive.index;
    if (r.primitive.kind == lap::haptics::PrimitiveKind::kFace) id = db.original_face(id);
    out << i << ',' << r.ihip_W.x() << ',' << r.ihip_W.y() << ',' << r.ihip_W.z() << ','
        << r.force_W.x() << ',' << r.force_W.y() << ',' << r.force_W.z() << ','
        << lap::haptics::to_string(r.primitive.kind) << ',' << id << ','
        << std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count() << '\n';
  }
}

// Whether the proxies can run on the mesh: open surfaces are fine (two-sided) for the point
// proxy; anything else must be clean. Prints why not.
bool probeable(const std::string& file, const lap::haptics::TriangleMesh& mesh) {
  const lap::haptics::MeshDiagnostics d = lap::haptics::validate_mesh(mesh);
  const bool usable = d.non_finite_vertices.empty() && d.invalid_index_triangles.empty() &&
                      d.degenerate_triangles.empty() && d.duplicate_triangles.empty() &&
                      d.non_manifold_edges.empty() && d.non_manifold_vertices.empty() &&
                      d.orientation_conflict_edges.empty() && d.sliver_fragments.empty();
  if (!usable) {
    std::cerr << file << ": the mesh cannot be probed as it is:\n";
    for (const auto& line : d.describe()) std::cerr << "  " << line << "\n";
    std::cerr << "  (add --repair to fix what can be fixed)\n";
    return false;
  }
  return true;
}

int cmd_probe(int argc, char** argv) {
  Args args(argc, argv, {"--repair"});
  if (!args.only({"--mesh", "--scale", "--repair", "--path", "--probe", "--stiffness",
                  "--max-force", "--out"}) ||
      !args.has("--mesh") || !args.has("--path")) {
    if (!args.has("--mesh")) args.errors.push_back("probe needs --mesh FILE");
    if (!args.has("--path")) args.errors.push_back("probe needs --path CSV");
    return usage_error(args);
  }
  const std::string kind = args.get("--probe", "point");
  if (kind != "point" && kind != "segment") {
    args.errors.push_back("--probe expects point or segment, got '" + kind + "'");
    return usage_error(args);
  }
  bool ok = true;
  lap::sim::MeshLoadSettings load;
  load.scale = positive_option(args, "--scale", 1.0, &ok);
  lap::haptics::HapticObject object;
  object.law.stiffness_n_per_m = positive_option(args, "--stiffness", 500.0, &ok);
  object.law.max_force_n = positive_option(args, "--max-force", 10.0, &ok);
  if (!ok) return kExitUsage;
  lap::Result<lap::haptics::TriangleMesh> mesh = lap::sim::load_mesh(args.get("--mesh"), load);
  if (!mesh.ok()) return print_problems(mesh.diagnostics());
  if (args.has("--repair")) lap::haptics::repair_mesh(mesh.value());
  const bool segment = kind == "segment";
  if (!probeable(args.get("--mesh"), mesh.value())) return kExitProblems;
  const auto path = lap::sim::load_probe_path(args.get("--path"), segment ? 6 : 3);
  if (!path.ok()) return print_problems(path.diagnostics());
  std::unique_ptr<lap::haptics::MeshDatabase> built;
  try {  // the database's own checks (e.g. an edge shared by too many faces)
    built = std::make_unique<lap::haptics::MeshDatabase>(
        lap::haptics::MeshDatabase::build(mesh.value()));
  } catch (const std::invalid_argument& e) {
    std::cerr << args.get("--mesh") << ": " << e.what() << "\n";
    return kExitProblems;
  }
  const lap::haptics::MeshDatabase& db = *built;
  object.mesh = &db;
  object.two_sided = db.has_boundary();
  std::ofstream file;
  if (args.has("--out")) {
    file.open(args.get("--out"));
    if (!file) {
      std::cerr << args.get("--out") << ": cannot open for writing\n";
      return kExitProblems;
    }
  }
  std::ostream& out = args.has("--out") ? static_cast<std::ostream&>(file) : std::cout;
  out.precision(12);
  if (segment) {
    run_segment_probe(object, db, path.value(), out);
  } else {
    run_point_probe(object, db, path.value(), out);
  }
  return kExitOk;
}

// Without --duration a session of scripted or replayed devices runs until every one of them has
// run out (or the task ends): the longest of their lengths, a tick over so that the last
// keyframe is reached. A session with any other device keeps the default.
std::optional<double> scripts_length_s(
    const std::array<std::unique_ptr<lap::hardware::HapticDevice>, 2>& devices, double tick_s) {
  double longest = 0.0;
  for (const auto& d : devices) {
    if (const auto* s = dynamic_cast<const lap::hardware::ScriptedDevice*>(d.get())) {
      longest = std::max(longest, s->trajectory().duration_s());
    } else if (const auto* r = dynamic_cast<const lap::hardware::ReplayDevice*>(d.get())) {
      longest = std::max(longest, r->length_s());
    } else {
      return std::nullopt;
    }
  }
  return longest + tick_s;
}

// --left and --right as device specifications (errors into args; the default where absent).
std::array<lap::hardware::DeviceSpec, 2> device_specs(Args* args) {
  std::array<lap::hardware::DeviceSpec, 2> specs;
  for (int side = 0; side < 2; ++side) {
    const char* key = side == 0 ? "--left" : "--right";
    if (!args->has(key)) continue;
    const auto spec = lap::hardware::parse_device_spec(args->get(key));
    if (!spec.ok()) {
      args->errors.push_back(std::string(key) + ": " + spec.message());
    } else {
      specs[static_cast<size_t>(side)] = spec.value();
    }
  }
  return specs;
}

int cmd_run(int argc, char** argv) {
  Args args(argc, argv, {"--fast"});
  const bool ok = args.only({"--scenario", "--left", "--right", "--duration", "--fast", "--record",
                             "--rate", "--model-rate", "--dominant-hand"});
  for (const char* k : {"--scenario", "--left", "--right"}) {
    if (!args.has(k)) args.errors.push_back(std::string("run needs ") + k);
  }
  lap::sim::RuntimeSettings rs;
  rs.fast = args.has("--fast");
  for (const auto& [key, field] : {std::pair<const char*, double*>{"--duration", &rs.duration_s},
                                   {"--rate", &rs.haptic_rate_hz},
                                   {"--model-rate", &rs.model_rate_hz}}) {
    if (!args.has(key)) continue;
    if (const std::optional<double> v = parse_positive(args.get(key))) {
      *field = *v;
    } else {
      args.errors.push_back(std::string(key) + " expects a positive number, got '" + args.get(key) +
                            "'");
    }
  }
  if (args.has("--dominant-hand")) {
    const std::string hand = args.get("--dominant-hand");
    if (hand != "left" && hand != "right") {
      args.errors.push_back("--dominant-hand expects left or right, got '" + hand + "'");
    }
    rs.dominant_tool = hand == "left" ? 0 : 1;
  }
  const std::array<lap::hardware::DeviceSpec, 2> specs = device_specs(&args);
  if (!ok || !args.errors.empty()) return usage_error(args);

  install_stop_handlers();
  const lap::sim::SceneLoadResult r = lap::sim::load_scene_file(args.get("--scenario"));
  if (!r.ok()) return print_problems(r.diagnostics());
  std::array<std::unique_ptr<lap::hardware::HapticDevice>, 2> devices;
  for (int side = 0; side < 2; ++side) {
    auto device = lap::sim::make_device(specs[static_cast<size_t>(side)], r.value(), side);
    if (!device.ok()) {
      std::cerr << "laptrainer-cli run: " << (side == 0 ? "--left" : "--right") << ": "
                << device.message() << "\n";
      return kExitProblems;
    }
    devices[static_cast<size_t>(side)] = std::move(device).value();
  }
  if (!args.has("--duration")) {
    if (const std::optional<double> length = scripts_length_s(devices, 1.0 / rs.haptic_rate_hz)) {
      rs.duration_s = std::max(*length, 1.0 / rs.haptic_rate_hz);
    }
  }
  auto created = lap::sim::Session::create(r.value(), std::move(devices), rs);
  if (!created.ok()) {
    std::cerr << "laptrainer-cli run: " << created.message() << "\n";
    return kExitProblems;
  }
  const std::unique_ptr<lap::sim::Session> session = std::move(created).value();
  if (args.has("--record")) {
    // Streamed as it runs (a crash loses at most the last 100 ms), with what it was run with.
    const fs::path dir = args.get("--record");
    std::error_code ec;
    if (fs::exists(dir / "session.lrec", ec) || fs::exists(dir / "session.json", ec)) {
      std::cerr << "laptrainer-cli run: --record " << dir.string()
                << " already holds a recorded session; choose a new folder\n";
      return kExitProblems;
    }
    // The trainee's sessions are theirs: the folder and its files for its owner only.
    fs::create_directories(dir, ec);
    fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace, ec);
    // session.json now, once (atomically, never rewritten), with the digest of the scenario's
    // bytes as loaded: a scenario changed while the session runs replays with a note.
    const std::string header =
        lap::sim::session_record_json(args.get("--scenario"), r.value().scenario.digest, rs);
    lap::Status ready = lap::sim::write_session_record(dir, header);
    if (ready.ok()) ready = session->record_to(dir / "session.lrec", header);
    if (!ready.ok()) {
      std::cerr << "laptrainer-cli run: " << ready.message() << "\n";
      return kExitProblems;
    }
  }
  // A signal stops the session as the window's End Session does: the next tick only commands zero
  // force to both devices (Session::request_stop); then the metrics and recording so far are
  // written.
  std::atomic<bool> ran{false};
  std::thread watcher([&] {
    while (!ran.load()) {
      if (g_stop_signal.load(std::memory_order_relaxed) != 0) {
        session->request_stop();
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  lap::sim::SessionMetrics m = session->run();
  ran.store(true);
  watcher.join();
  // The scenario file changed on disk while it ran: said in the warnings (and metrics.json); the
  // session ran what was loaded, session.json keeps that digest, and a report notes the change.
  if (std::optional<std::string> changed =
          lap::sim::scenario_change_warning(r.value().scenario.file, r.value().scenario.digest)) {
    m.warnings.push_back(std::move(*changed));
  }
  for (const std::string& w : m.warnings) std::cerr << "laptrainer-cli run: warning: " << w << "\n";
  if (m.paused) {
    std::cerr << "laptrainer-cli run: the watchdog paused the session (forces zeroed):";
    for (const auto& e : m.events) {
      std::cerr << " tick " << e.tick << " "
                << lap::sim::describe(e.reason, e.model_fault, m.organ_names) << ";";
    }
    std::cerr << "\n";
  }
  const std::string out = lap::sim::metrics_json(m, args.get("--scenario"), rs.fast);
  std::cout << out;
  if (args.has("--record")) {
    const lap::Status saved =
        lap::sim::save_session(*session, m, args.get("--scenario"), rs.fast, args.get("--record"));
    if (!saved.ok()) {
      for (const lap::Diagnostic& d : saved.diagnostics()) {
        std::cerr << "laptrainer-cli run: " << d.to_string() << "\n";
      }
      std::cerr << "laptrainer-cli run: the session ran, but not all of its recording was written "
                   "(above); what was written in "
                << args.get("--record") << " is kept\n";
      return kExitNotSaved;
    }
  }
  if (const int sig = g_stop_signal.load(); sig != 0) {
    std::cerr << "laptrainer-cli run: stopped by " << (sig == SIGINT ? "SIGINT" : "SIGTERM")
              << " (forces zeroed; the metrics" << (args.has("--record") ? " and recording" : "")
              << " so far are written)\n";
    return sig == SIGINT ? kExitInterrupted : kExitTerminated;
  }
  return kExitOk;
}

int cmd_devices(int argc, char** argv) {
  Args args(argc, argv, {});
  if (!args.only({})) return usage_error(args);
  const auto found = lap::hardware::LibusbTransport::list();
  if (!found.ok()) {
    std::cerr << "laptrainer-cli devices: " << found.message() << "\n";
    return kExitProblems;
  }
  std::cout << found.value().size() << " actuated gripper(s) (USB 1209:4c54)\n";
  for (const lap::hardware::FoundGripper& g : found.value()) {
    std::cout << "  serial " << (g.serial.empty() ? "(unreadable)" : g.serial) << " at "
              << g.bus_path << ": use DEV+gripper"
              << (g.serial.empty() ? "@" + g.bus_path : ":" + g.serial) << "\n";
  }
  return kExitOk;
}

int cmd_report(int argc, char** argv) {
  Args args(argc, argv, {});
  const bool ok = args.only({"--session", "--format", "--out", "--scenario", "--allow-path"});
  if (!args.has("--session")) args.errors.push_back("report needs --session");
  const std::string format = args.get("--format", "json");
  if (format != "json" && format != "csv" && format != "pdf") {
    args.errors.push_back("--format expects json, csv or pdf, got '" + format + "'");
  }
  if (format == "pdf" && !args.has("--out")) args.errors.push_back("--format pdf needs --out FILE");
  if (!ok || !args.errors.empty()) return usage_error(args);
  // The report never overwrites what it reports on.
  if (args.has("--out")) {
    std::error_code ec;
    const fs::path out = fs::weakly_canonical(args.get("--out"), ec);
    const fs::path session = fs::weakly_canonical(args.get("--session"), ec);
    if (out.parent_path() == session &&
        (out.filename() == "session.lrec" || out.filename() == "session.json" ||
         out.filename() == "metrics.json" || out.extension() == ".lapdev")) {
      std::cerr << "laptrainer-cli report: --out " << args.get("--out")
                << " would overwrite the session's own " << out.filename().string()
                << "; write the report elsewhere\n";
      return kExitProblems;
    }
  }
  lap::sim::ReplaySettings replay;
  if (args.has("--scenario")) replay.scenario = fs::path(args.get("--scenario"));
  for (const auto& p : args.all("--allow-path")) replay.allowed_paths.emplace_back(p);
  const auto replayed = lap::sim::replay_session(args.get("--session"), replay);
  if (!replayed.ok()) return print_problems(replayed.diagnostics());
  const lap::sim::ReplayedSession& r = replayed.value();
  for (const std::string& n : r.notes) std::cerr << "laptrainer-cli report: note: " << n << "\n";
  for (const std::string& p : r.recording_problems) {
    std::cerr << "laptrainer-cli report: recording: " << p << "\n";
  }
  if (r.interrupted) {
    std::cerr << "laptrainer-cli report: the session was interrupted (its recording has no end); "
                 "replayed up to its last recorded tick\n";
  }
  std::string text;
  if (format == "pdf") {
    lap::sim::SessionPdfContext c;
    c.scenario_name = r.scenario_name;
    c.scenario_file = r.record.scenario.string();
    c.session = args.get("--session");
    c.mode = r.record.settings.fast ? "fast" : "realtime";
    if (r.task) {
      c.duct_injury_force_n = r.task->duct_injury_force_n;
      c.insertion_depth_m = r.task->insertion_depth_m;
    }
    c.notes = r.notes;
    text = lap::sim::session_pdf(r.metrics, c).bytes();
  } else if (format == "csv") {
    text = "metric,value\n";
    for (const lap::sim::Metric& x : r.metrics.training) {
      // The shortest text that reads back to the same double; empty where undefined (null).
      char value[64];
      const auto end =
          std::isfinite(x.value) ? std::to_chars(value, value + 63, x.value).ptr : value;
      text += x.name + "," + std::string(value, end) + "\n";
    }
  } else {
    nlohmann::ordered_json j =
        lap::sim::metrics_to_json(r.metrics, r.record.scenario.string(), r.record.settings.fast);
    j["session"] = args.get("--session");
    // A session whose recording has no end: the process was killed (at most 100 ms lost).
    j["interrupted"] = r.interrupted;
    j["recording"] = {{"file", r.streamed ? "session.lrec" : "left.lapdev, right.lapdev"},
                      {"ticks", r.streamed ? r.recorded_ticks : r.metrics.recorded_ticks},
                      {"problems", r.recording_problems}};
    j["notes"] = r.notes;
    j["series"] = lap::sim::series_to_json(r.metrics.series);
    text = j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  }
  if (!args.has("--out")) {
    std::cout << text;
    return kExitOk;
  }
  std::ofstream out(args.get("--out"), std::ios::binary);
  out << text;
  out.flush();
  if (!out) {
    std::cerr << "laptrainer-cli report: " << args.get("--out") << ": cannot write the report\n";
    return kExitProblems;
  }
  return kExitOk;
}

int cmd_generate_assets(int argc, char** argv) {
  Args args(argc, argv, {});
  if (!args.only({"--out", "--anatomy"}) || !args.has("--out")) {
    if (!args.has("--out")) args.errors.push_back("generate-assets needs --out DIR");
    return usage_error(args);
  }
  const fs::path dir = args.get("--out");
  if (args.has("--anatomy")) {
    const std::string preset = args.get("--anatomy");
    const std::vector<std::string> presets =
        preset == "all" ? lap::haptics::anatomy_preset_names() : std::vector<std::string>{preset};
    if (lap::Status saved = lap::sim::save_anatomy_presets(dir, presets); !saved.ok()) {
      return print_problems(saved.diagnostics());
    }
    std::cout << "wrote the anatomy ("
              << (preset == "all" ? "default, easy, moderate, hard" : preset)
              << ") and its textures to " << dir.string() << "\n";
    return kExitOk;
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  for (const auto& [mesh, name] :
       {std::pair{lap::haptics::make_stand_in_liver(), "liver.obj"},
        std::pair{lap::haptics::make_stand_in_gallbladder(), "gallbladder.obj"},
        std::pair{lap::haptics::make_stand_in_cystic_duct(), "cystic_duct.obj"}}) {
    if (lap::Status saved = lap::sim::save_obj(mesh, dir / name); !saved.ok()) {
      return print_problems(saved.diagnostics());
    }
  }
  std::cout << "wrote liver.obj, gallbladder.obj, cystic_duct.obj to " << dir.string() << "\n";
  return kExitOk;
}

int cmd_expert_benchmarks(int argc, char** argv) {
  Args args(argc, argv, {});
  lap::sim::ExpertBenchmarkSettings settings;
  if (args.has("--runs")) {
    const std::optional<double> n = parse_positive(args.get("--runs"));
    if (!n || *n < 2 || *n > 1000 || std::floor(*n) != *n) {
      args.errors.push_back("--runs expects a whole number from 2 to 1000, got '" +
                            args.get("--runs") + "'");
    } else {
      settings.runs = static_cast<int>(*n);
    }
  }
  if (!args.only({"--scenario", "--runs"}) || !args.has("--scenario") || !args.errors.empty()) {
    if (!args.has("--scenario")) args.errors.push_back("expert-benchmarks needs --scenario FILE");
    return usage_error(args);
  }
  const lap::sim::SceneLoadResult r = lap::sim::load_scene_file(args.get("--scenario"));
  if (!r.ok()) return print_problems(r.diagnostics());
  auto found = lap::sim::plan_expert_benchmarks(r.value(), settings);
  if (!found.ok()) return print_problems(found.diagnostics());
  const lap::sim::ExpertBenchmarks& b = found.value();
  std::cout << lap::sim::proficiency_yaml(b.spec);
  for (const std::string& f : b.failures) {
    std::cerr << "laptrainer-cli expert-benchmarks: a run did not succeed (left out): " << f
              << "\n";
  }
  for (const std::string& m : b.left_out) {
    std::cerr << "laptrainer-cli expert-benchmarks: no benchmark for " << m << "\n";
  }
  return kExitOk;
}

int cmd_plan_expert(int argc, char** argv) {
  Args args(argc, argv, {});
  lap::sim::ExpertMistake mistake_run = lap::sim::ExpertMistake::kNone;
  std::string prefix = "expert";
  if (args.has("--mistake")) {
    const std::string m = args.get("--mistake");
    if (const std::optional<lap::sim::ExpertMistake> mistake = lap::sim::parse_mistake(m)) {
      mistake_run = *mistake;
    } else {
      args.errors.push_back("--mistake: expected drop, overshoot, tear, cbd or time_limit, got '" +
                            m + "'");
    }
    prefix = "clumsy_" + m;
  }
  if (!args.only({"--scenario", "--out", "--mistake"}) || !args.has("--scenario") ||
      !args.has("--out") || !args.errors.empty()) {
    if (!args.has("--scenario")) args.errors.push_back("plan-expert needs --scenario FILE");
    if (!args.has("--out")) args.errors.push_back("plan-expert needs --out DIR");
    return usage_error(args);
  }
  const lap::sim::SceneLoadResult r = lap::sim::load_scene_file(args.get("--scenario"));
  if (!r.ok()) return print_problems(r.diagnostics());
  lap::sim::RuntimeSettings rs;
  rs.fast = true;
  const std::array<lap::sim::DeviceDescription, 2> devices{
      lap::sim::DeviceDescription{"left", {}}, lap::sim::DeviceDescription{"right", {}}};
  auto model = lap::sim::SessionModel::build(r.value(), rs, devices);
  if (!model.ok()) return print_problems(model.diagnostics());
  lap::sim::ExpertRunSettings settings = lap::sim::expert_run_settings(r.value().scenario);
  settings.mistake = mistake_run;
  const auto plan = lap::sim::plan_expert_run(r.value(), *model.value(), settings);
  if (!plan.ok()) return print_problems(plan.diagnostics());
  const fs::path dir = args.get("--out");
  std::error_code ec;
  fs::create_directories(dir, ec);
  for (const auto& [trajectory, side] :
       {std::pair{&plan.value().left, "left"}, std::pair{&plan.value().right, "right"}}) {
    const fs::path file = dir / (prefix + "_" + side + ".csv");
    if (lap::Status saved = lap::sim::save_trajectory_csv(*trajectory, file); !saved.ok()) {
      return print_problems(saved.diagnostics());
    }
  }
  const std::optional<double> site = plan.value().steady_site_m;
  char left[128];
  if (site) {
    std::snprintf(left, sizeof(left), "the left hand steadies the duct %.1f mm along it",
                  *site * 1e3);
  } else {
    std::snprintf(left, sizeof(left), "%s",
                  "the left hand waits in view (no clear line to the duct beside the incision)");
  }
  std::printf(
      "wrote %s_left.csv, %s_right.csv to %s (%.1f s; the catheter within %.1f deg of "
      "the planned entry direction, %.1f deg to the duct's axis%s; %s)\n",
      prefix.c_str(), prefix.c_str(), dir.string().c_str(), plan.value().right.duration_s(),
      plan.value().worst_direction_error_deg, settings.entry_slant_deg,
      r.value().scenario.task && r.value().scenario.task->expert_entry_slant_deg
          ? ", the scenario's"
          : "",
      left);
  // How near the right hand comes to the organs it must not touch: an author placing a new
  // patient's ports sees where it would press into one (the planner does not steer round them).
  // (The expert's run only: a clumsy run may press where it goes wrong, into the common bile
  // duct.)
  const std::vector<std::string>& names = model.value()->organ_names();
  if (mistake_run != lap::sim::ExpertMistake::kNone) return kExitOk;
  for (const auto& [what, c] : {std::pair{"the right tool's shaft", plan.value().right_shaft},
                                std::pair{"the held catheter", plan.value().held_catheter}}) {
    if (c.organ < 0) continue;
    const std::string organ = static_cast<size_t>(c.organ) < names.size()
                                  ? names[static_cast<size_t>(c.organ)]
                                  : "organ " + std::to_string(c.organ);
    if (c.least_m >= 0.0) {
      std::printf("%s comes within %.2f mm of the %s (at %.1f s)\n", what, c.least_m * 1e3,
                  organ.c_str(), c.time_s);
    } else {
      std::printf("%s passes %.2f mm inside the %s (at %.1f s)\n", what, -c.least_m * 1e3,
                  organ.c_str(), c.time_s);
    }
    if (c.pressed_in_m() > 0.0) {
      std::fprintf(stderr,
                   "laptrainer-cli: warning: %s presses %.2f mm into the %s at %.1f s (its axis "
                   "%+.2f mm from the surface, negative inside; its radius %.2f mm): move the "
                   "port or the catheter's start\n",
                   what, c.pressed_in_m() * 1e3, organ.c_str(), c.time_s, c.least_m * 1e3,
                   c.radius_m * 1e3);
    }
  }
  return kExitOk;
}

}  // namespace

// The answers so far and their table into `dir` (after every trial: a crash or a signal keeps
// what was answered).
lap::Status write_perception_results(const fs::path& dir,
                                     const std::vector<lap::sim::PerceptionAnswer>& answers) {
  for (const auto& [name, text] :
       {std::pair<const char*, std::string>{"answers.csv", lap::sim::to_csv(answers)},
        {"results.csv", lap::sim::to_csv(lap::sim::tabulate(answers))}}) {
    std::ofstream f(dir / name, std::ios::binary | std::ios::trunc);
    f << text;
    if (!f.flush()) return lap::diagnostic("cannot write " + (dir / name).string());
  }
  return {};
}

// The §5.5 experiment's settings from the command line (errors into args).
lap::sim::PerceptionSettings perception_settings(Args* args) {
  lap::sim::PerceptionSettings ps;
  if (args->has("--seed")) {
    const std::string text = args->get("--seed");
    uint32_t seed = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), seed);
    if (ec != std::errc() || end != text.data() + text.size() || text.empty()) {
      args->errors.push_back("--seed expects a whole number from 0 to 4294967295, got '" + text +
                             "'");
    }
    ps.seed = seed;
  }
  if (args->has("--repetitions")) {
    const std::string text = args->get("--repetitions");
    int32_t n = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
    if (ec != std::errc() || end != text.data() + text.size() || n < 1 || n > 1000) {
      args->errors.push_back("--repetitions expects a whole number from 1 to 1000, got '" + text +
                             "'");
    }
    ps.repetitions = n;
  }
  if (args->has("--modes")) {
    const std::string text = args->get("--modes");
    ps.modes.clear();
    bool bad = text.empty() || text.back() == ',';
    std::stringstream list(text);
    for (std::string m; !bad && std::getline(list, m, ',');) {
      const std::optional<lap::sim::ProbeMode> mode = lap::sim::parse_probe_mode(m);
      bad = !mode || std::find(ps.modes.begin(), ps.modes.end(), *mode) != ps.modes.end();
      if (mode) ps.modes.push_back(*mode);
    }
    if (bad) {
      args->errors.push_back("--modes expects point, ray or point,ray (each once), got '" + text +
                             "'");
    }
  }
  return ps;
}

// The §5.5 experiment with a participant at the devices (sim/authoring/perception_run.h).
int cmd_perception(int argc, char** argv) {
  Args args(argc, argv, {});
  const bool ok = args.only({"--left", "--right", "--out", "--seed", "--repetitions", "--modes",
                             "--size", "--trial-limit"});
  for (const char* k : {"--left", "--right", "--out"}) {
    if (!args.has(k)) args.errors.push_back(std::string("perception needs ") + k);
  }
  const lap::sim::PerceptionSettings ps = perception_settings(&args);
  lap::sim::PerceptionRunSettings run;
  run.runtime.duration_s = 600.0;
  for (const auto& [key, field] : {std::pair<const char*, double*>{"--size", &run.shape_size_m},
                                   {"--trial-limit", &run.runtime.duration_s}}) {
    if (!args.has(key)) continue;
    if (const std::optional<double> v = parse_positive(args.get(key))) {
      *field = *v;
    } else {
      args.errors.push_back(std::string(key) + " expects a positive number, got '" + args.get(key) +
                            "'");
    }
  }
  run.devices = device_specs(&args);
  if (!ok || !args.errors.empty()) return usage_error(args);
  auto experiment = lap::sim::PerceptionExperiment::create(ps);
  if (!experiment.ok()) {
    std::cerr << "laptrainer-cli perception: " << experiment.message() << "\n";
    return kExitProblems;
  }
  const fs::path dir = args.get("--out");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) {
    std::cerr << "laptrainer-cli perception: --out " << dir.string()
              << " is not a folder that can be made\n";
    return kExitProblems;
  }
  // SIGINT or SIGTERM interrupt the wait for an answer: the trial's forces are zeroed and the
  // answers so far are kept (written after every trial).
  install_stop_handlers();
  lap::Status written;
  run.before_trial = [] {
    if (isatty(STDIN_FILENO) != 0) tcflush(STDIN_FILENO, TCIFLUSH);  // no typed-ahead answer
  };
  run.after_trial = [&](const lap::sim::PerceptionExperiment& e) {
    if (written.ok()) written = write_perception_results(dir, e.answers());
  };
  const lap::Status ran =
      lap::sim::run_perception_trials(&experiment.value(), run, std::cin, std::cerr);
  const std::vector<lap::sim::PerceptionAnswer>& answers = experiment.value().answers();
  if (written.ok()) written = write_perception_results(dir, answers);
  if (!written.ok()) {
    std::cerr << "laptrainer-cli perception: " << written.message() << "\n";
    return kExitProblems;
  }
  const std::string kept = (dir / "answers.csv").string() + " and results.csv hold the " +
                           std::to_string(answers.size()) + " answered";
  if (const int sig = g_stop_signal.load(); sig != 0) {
    std::cerr << "laptrainer-cli perception: stopped by " << (sig == SIGINT ? "SIGINT" : "SIGTERM")
              << " (forces zeroed); " << kept << "\n";
    return sig == SIGINT ? kExitInterrupted : kExitTerminated;
  }
  if (!ran.ok()) {
    std::cerr << "laptrainer-cli perception: " << ran.message() << "; " << kept << "\n";
    return kExitProblems;
  }
  std::cerr << "laptrainer-cli perception: " << answers.size() << " trials answered; "
            << (dir / "results.csv").string() << "\n";
  return kExitOk;
}

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::cout << kUsage;
    return argc < 2 ? kExitUsage : kExitOk;
  }
  const std::string cmd = argv[1];
  try {
    if (cmd == "validate") return cmd_validate(argc, argv);
    if (cmd == "mesh-info") return cmd_mesh_info(argc, argv);
    if (cmd == "generate-assets") return cmd_generate_assets(argc, argv);
    if (cmd == "plan-expert") return cmd_plan_expert(argc, argv);
    if (cmd == "expert-benchmarks") return cmd_expert_benchmarks(argc, argv);
    if (cmd == "probe") return cmd_probe(argc, argv);
    if (cmd == "run") return cmd_run(argc, argv);
    if (cmd == "report") return cmd_report(argc, argv);
    if (cmd == "devices") return cmd_devices(argc, argv);
    if (cmd == "perception") return cmd_perception(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "laptrainer-cli " << cmd << ": " << e.what() << "\n";
    return 1;
  }
  std::cerr << "laptrainer-cli: unknown command '" << cmd << "'\n" << kUsage;
  return kExitUsage;
}
