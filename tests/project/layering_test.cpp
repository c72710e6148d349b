// The layering of docs/architecture.md, enforced: Qt and VTK only in app/, libusb only in
// hardware/; haptics and models depend only on Eigen/OpenMesh (and Spectra); core on nothing of
// the project; and the folders that say when code runs keep their direction: the haptic step
// (haptics/) uses nothing of mesh set-up (haptics/setup/), sim/setup/ nothing of sim/runtime/ or
// sim/report/, sim/runtime/ nothing of sim/report/.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

#include "tests/test_support.h"

namespace lap::test {
namespace {

namespace fs = std::filesystem;

struct Violation {
  std::string file;
  int line;
  std::string text;
};

// Lists #include lines in C/C++ files below the given folders of root whose header matches
// `forbidden`, leaving out the subfolders (relative to root) in `except`.
std::vector<Violation> find_includes(const fs::path& root, const std::vector<std::string>& folders,
                                     const std::regex& forbidden,
                                     const std::vector<std::string>& except = {}) {
  std::vector<Violation> found;
  const std::regex include_line(R"(^\s*#\s*include\s*[<"]([^>"]+)[>"])");
  for (const std::string& folder : folders) {
    const fs::path dir = root / folder;
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() ||
          (ext != ".h" && ext != ".hpp" && ext != ".cpp" && ext != ".cc")) {
        continue;
      }
      const std::string rel = fs::relative(entry.path(), root).string();
      const bool excepted = std::any_of(except.begin(), except.end(), [&](const std::string& e) {
        return rel.rfind(e + "/", 0) == 0;
      });
      if (excepted) continue;
      std::ifstream in(entry.path());
      std::string line;
      for (int n = 1; std::getline(in, line); ++n) {
        std::smatch m;
        if (std::regex_search(line, m, include_line) && std::regex_search(m[1].str(), forbidden)) {
          found.push_back({fs::relative(entry.path(), root).string(), n, line});
        }
      }
    }
  }
  return found;
}

const std::regex kQtOrVtk(R"(^(Q[A-Za-z0-9]*(/|$)|Qt[A-Za-z0-9]*/|vtk|QVTK))");
const std::regex kLibusb(R"(^(libusb-1\.0/|libusb\.h))");
const std::regex kNotForCore(
    R"(^(yaml-cpp/|tiny_gltf|sqlite3|sim/|app/|hardware/|thread$|mutex$|fstream$))");
const std::regex kProject(R"(^(haptics|models|hardware|sim|app|tests)/)");
const std::regex kHapticsSetup(R"(^haptics/setup/)");
const std::regex kSimRuntimeOrReport(R"(^sim/(runtime|report)/)");
const std::regex kSimReport(R"(^sim/report/)");

std::string report(const std::vector<Violation>& v) {
  std::ostringstream s;
  for (const auto& x : v) s << x.file << ":" << x.line << ": " << x.text << "\n";
  return s.str();
}

TEST(Layering, QtAndVtkOnlyInApp) {
  const auto v = find_includes(source_dir(),
                               {"haptics", "models", "hardware", "sim", "tests/haptics",
                                "tests/models", "tests/hardware", "tests/sim"},
                               kQtOrVtk);
  EXPECT_TRUE(v.empty()) << report(v);
}

TEST(Layering, LibusbOnlyInHardware) {
  const auto v = find_includes(source_dir(),
                               {"haptics", "models", "sim", "app", "tests/haptics", "tests/models",
                                "tests/sim", "tests/app"},
                               kLibusb);
  EXPECT_TRUE(v.empty()) << report(v);
}

TEST(Layering, HapticsAndModelsUseNoFilesThreadsOrUpperLayers) {
  const auto v = find_includes(source_dir(), {"haptics", "models"}, kNotForCore);
  EXPECT_TRUE(v.empty()) << report(v);
}

TEST(Layering, CoreUsesNothingOfTheProject) {
  const auto v = find_includes(source_dir(), {"core"}, kProject);
  EXPECT_TRUE(v.empty()) << report(v);
}

TEST(Layering, TheHapticStepUsesNoMeshSetUp) {
  const auto v = find_includes(source_dir(), {"haptics", "models", "hardware", "sim/runtime"},
                               kHapticsSetup, {"haptics/setup"});
  EXPECT_TRUE(v.empty()) << report(v);
}

TEST(Layering, SimFoldersPointFromSetUpToRuntimeToReport) {
  const auto setup = find_includes(source_dir(), {"sim/setup"}, kSimRuntimeOrReport);
  EXPECT_TRUE(setup.empty()) << report(setup);
  const auto runtime = find_includes(source_dir(), {"sim/runtime"}, kSimReport);
  EXPECT_TRUE(runtime.empty()) << report(runtime);
}

TEST(Layering, TheCheckCatchesAPlantedViolation) {
  // The scanner itself must be able to fail: plant each kind of violation in a scratch tree.
  TempDir dir;
  dir.write("sim/bad.cpp",
            "#include <QWidget>\n#include \"vtkActor.h\"\n#include <Qt6/QtCore/qglobal.h>\n");
  dir.write("app/usb.cpp", "  #  include <libusb-1.0/libusb.h>\n");
  dir.write("haptics/io.cpp", "#include <fstream>\n#include \"sim/scene.h\"\n");
  dir.write("haptics/fine.cpp",
            "#include <Eigen/Core>\n#include <QueueIsNotQt>\n#include \"haptics/x.h\"\n");
  EXPECT_EQ(find_includes(dir.path(), {"sim"}, kQtOrVtk).size(), 3U);
  EXPECT_EQ(find_includes(dir.path(), {"app"}, kLibusb).size(), 1U);
  EXPECT_EQ(find_includes(dir.path(), {"haptics"}, kNotForCore).size(), 2U);
  dir.write("haptics/step.cpp", "#include \"haptics/setup/mesh_repair.h\"\n");
  dir.write("haptics/setup/fine.cpp", "#include \"haptics/setup/mesh_topology.h\"\n");
  EXPECT_EQ(find_includes(dir.path(), {"haptics"}, kHapticsSetup, {"haptics/setup"}).size(), 1U);
  dir.write("sim/setup/late.cpp",
            "#include \"sim/runtime/session.h\"\n#include \"sim/report/r.h\"\n");
  EXPECT_EQ(find_includes(dir.path(), {"sim/setup"}, kSimRuntimeOrReport).size(), 2U);
  dir.write("core/up.h", "#include \"sim/setup/scene.h\"\n#include <string>\n");
  EXPECT_EQ(find_includes(dir.path(), {"core"}, kProject).size(), 1U);
}

}  // namespace
}  // namespace lap::test
