#include "tests/test_support.h"

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

namespace lap::test {
namespace fs = std::filesystem;

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

fs::path source_dir() { return fs::path(LAP_SOURCE_DIR); }

fs::path shared_meshes_dir() {
  const char* env = std::getenv("LAP_SHARED_DIR");
  const fs::path dir = (env != nullptr && *env != '\0') ? fs::path(env) / "meshes"
                                                        : fs::path(LAP_SHARED_DIR) / "meshes";
  std::error_code ec;
  return fs::is_directory(dir, ec) ? dir : fs::path();
}

fs::path bin_dir() { return fs::path(LAP_BIN_DIR); }

TempDir::TempDir() {
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    path_ = fs::temp_directory_path() / ("laptrainer-test-" + std::to_string(rd()));
    if (fs::create_directory(path_)) return;
  }
  throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

fs::path TempDir::write(const std::string& name, const std::string& text) const {
  const fs::path p = path_ / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

CommandResult run_command(const std::string& command) {
  TempDir tmp;
  const fs::path out = tmp.path() / "out.txt";
  const fs::path err = tmp.path() / "err.txt";
  const std::string full = command + " >" + out.string() + " 2>" + err.string();
  CommandResult r;
  const int status = std::system(full.c_str());
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

haptics::TriangleMesh tetrahedron(const Eigen::Vector3d& offset, double size) {
  haptics::TriangleMesh m;
  m.positions = {offset, offset + Eigen::Vector3d(size, 0, 0), offset + Eigen::Vector3d(0, size, 0),
                 offset + Eigen::Vector3d(0, 0, size)};
  // Outward (counter-clockwise from outside).
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

}  // namespace lap::test
