#include "sim/setup/probe_path.h"

#include <cmath>
#include <sstream>
#include <string>

#include "core/bounded_file.h"

namespace lap::sim {

Result<std::vector<Eigen::Matrix<double, 6, 1>>> load_probe_path(const std::filesystem::path& file,
                                                                 int columns) {
  const Result<std::string> text =
      read_bounded_file(file, kMaxProbePathBytes, "a probe path (CSV)", "sim/setup/probe_path.h");
  if (!text.ok()) return text.diagnostics();
  std::istringstream in(text.value());
  const std::string expected =
      columns == 3 ? "3 numbers x,y,z in metres" : "6 numbers x1,y1,z1,x2,y2,z2 in metres";
  std::vector<Eigen::Matrix<double, 6, 1>> rows;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    Eigen::Matrix<double, 6, 1> row = Eigen::Matrix<double, 6, 1>::Zero();
    bool numeric = static_cast<int>(cells.size()) == columns;
    for (int c = 0; numeric && c < columns; ++c) {
      try {
        size_t used = 0;
        row[c] = std::stod(cells[c], &used);
        numeric =
            cells[c].find_first_not_of(" \t", used) == std::string::npos && std::isfinite(row[c]);
      } catch (const std::exception&) {
        numeric = false;
      }
    }
    if (!numeric) {
      if (rows.empty() && n == 1 && static_cast<int>(cells.size()) == columns) continue;  // header
      return Diagnostic{file.string(), n, "",
                        "expected " + expected + ", got " + quote_excerpt(line)};
    }
    rows.push_back(row);
  }
  if (rows.empty()) {
    return Diagnostic{file.string(), 0, "",
                      "the path has no rows (expected " + expected + " per line)"};
  }
  return rows;
}

}  // namespace lap::sim
