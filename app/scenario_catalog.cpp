#include "app/scenario_catalog.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "sim/setup/scenario_loader.h"

namespace lap::app {
namespace fs = std::filesystem;

namespace {

// A number as a person writes it: no trailing zeros, at most `digits` decimals.
std::string num(double v, int digits = 1) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

std::string duration_words(double s) {
  if (s >= 120.0 && std::fmod(s, 60.0) == 0.0) return num(s / 60.0, 0) + " minutes";
  return num(s) + " s";
}

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " or " : ", ";
    std::string n = names[i];
    std::replace(n.begin(), n.end(), '_', ' ');
    out += "the " + n;
  }
  return out;
}

}  // namespace

int difficulty_rank(const std::string& difficulty) {
  if (difficulty == "introductory") return 0;
  if (difficulty == "easy") return 1;
  if (difficulty == "moderate") return 2;
  if (difficulty == "hard") return 3;
  return 4;
}

CatalogEntry catalog_entry(const fs::path& file) {
  CatalogEntry e;
  e.file = file;
  e.stem = file.stem().string();
  e.name = e.stem;
  std::error_code ec;
  const fs::path preview = file.parent_path() / "previews" / (e.stem + ".png");
  if (fs::is_regular_file(preview, ec)) e.preview = preview;
  const sim::ScenarioLoadResult r = sim::load_scenario(file);
  if (!r.ok()) {
    e.problems = r.message();
    return e;
  }
  const sim::Scenario& s = r.value();
  e.name = s.name;
  e.description = s.description;
  // YAML's folded text keeps its final newline.
  while (!e.description.empty() && std::isspace(static_cast<unsigned char>(e.description.back()))) {
    e.description.pop_back();
  }
  e.difficulty = s.difficulty;
  e.task = s.task;
  return e;
}

std::vector<CatalogEntry> scan_scenarios(const fs::path& folder) {
  std::vector<CatalogEntry> out;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    if (!it->is_regular_file(ec)) continue;
    if (p.extension() != ".yaml" && p.extension() != ".yml") continue;
    out.push_back(catalog_entry(p));
  }
  std::sort(out.begin(), out.end(), [](const CatalogEntry& a, const CatalogEntry& b) {
    const int ra = difficulty_rank(a.difficulty);
    const int rb = difficulty_rank(b.difficulty);
    return ra != rb ? ra < rb : a.name < b.name;
  });
  return out;
}

fs::path scenarios_folder() { return sim::default_scenario_path().parent_path(); }

std::vector<std::string> task_in_words(const sim::TaskSpec& t) {
  std::vector<std::string> lines;
  if (t.kind != "catheter-insertion") {
    lines.push_back("Explore freely: there is no goal and no time limit.");
  } else {
    std::string target = t.target.empty() ? "duct" : t.target;
    std::replace(target.begin(), target.end(), '_', ' ');
    lines.push_back("Take the catheter with a grasper, bring its tip to the incision in the " +
                    target + "'s wall and insert it " + num(t.insertion_depth_m * 1000.0) +
                    " mm into the lumen.");
    lines.push_back("Hold it at that depth for " + num(t.hold_s) +
                    " s: the attempt then succeeds by itself.");
    lines.push_back("You have " + duration_words(t.time_limit_s) + ".");
  }
  lines.push_back("The attempt fails if you:");
  lines.push_back("- push or pull the duct harder than " + num(t.duct_injury_force_n) +
                  " N, or squeeze it harder than " + num(t.duct_squeeze_n) + " N, for more than " +
                  num(t.duct_injury_time_s) + " s;");
  lines.push_back("- push any other organ harder than " + num(t.organ_injury_force_n) +
                  " N for more than " + num(t.organ_injury_time_s) + " s;");
  if (t.kind == "catheter-insertion") {
    lines.push_back("- let go of the catheter, its tip outside the duct, for " +
                    num(t.drop_grace_s) + " s;");
    lines.push_back("- push the catheter's tip through the duct's wall;");
  }
  if (!t.common_bile_duct.empty()) {
    lines.push_back("- put the catheter's tip into the common bile duct;");
  }
  if (!t.forbidden_organs.empty()) {
    lines.push_back("- touch " + join_names(t.forbidden_organs) + ";");
  }
  lines.push_back("- keep an instrument's tip out of the laparoscope's view for " +
                  num(t.out_of_view_grace_s) + " s.");
  return lines;
}

}  // namespace lap::app
