// The scenario chooser's catalog (app/scenario_catalog.h): every shipped scenario is offered
// with its name, difficulty and preview picture, ordered by difficulty; a broken file is listed
// with its problems; the briefing's task in words carries the scenario's own thresholds.

#include "app/scenario_catalog.h"

#include <gtest/gtest.h>

#include <QImage>
#include <set>

#include "tests/test_support.h"

namespace lap::test {
namespace {

namespace fs = std::filesystem;

TEST(ScenarioCatalog, EveryShippedScenarioHasAPreviewADifficultyAndLoads) {
  const std::vector<app::CatalogEntry> entries = app::scan_scenarios(source_dir() / "scenarios");
  std::set<std::string> stems;
  for (const app::CatalogEntry& e : entries) {
    stems.insert(e.stem);
    EXPECT_TRUE(e.problems.empty()) << e.stem << ": " << e.problems;
    EXPECT_FALSE(e.name.empty()) << e.stem;
    EXPECT_FALSE(e.description.empty()) << e.stem;
    EXPECT_LT(app::difficulty_rank(e.difficulty), 4) << e.stem << " is not graded";
    ASSERT_FALSE(e.preview.empty())
        << e.stem << " has no previews/" << e.stem << ".png: run app/make-previews.sh";
    // A picture of the operative field: 16:9, and not blank.
    const QImage image(QString::fromStdString(e.preview.string()));
    ASSERT_FALSE(image.isNull()) << e.preview;
    EXPECT_EQ(image.width() * 9, image.height() * 16) << e.preview;
    std::set<QRgb> colours;
    for (int y = 0; y < image.height(); y += 4) {
      for (int x = 0; x < image.width(); x += 4) colours.insert(image.pixel(x, y));
    }
    EXPECT_GT(colours.size(), 100U) << e.preview << " looks blank";
  }
  for (const char* stem :
       {"introductory", "default", "patient_easy", "patient_moderate", "patient_hard"}) {
    EXPECT_EQ(stems.count(stem), 1U) << stem << " is not offered";
  }
  // Easiest first.
  for (size_t i = 1; i < entries.size(); ++i) {
    EXPECT_LE(app::difficulty_rank(entries[i - 1].difficulty),
              app::difficulty_rank(entries[i].difficulty));
  }
  // The textbook patient (the default) is graded with the moderate one, and its name comes
  // first.
  ASSERT_GE(entries.size(), 5U);
  EXPECT_EQ(entries[0].stem, "introductory");
  EXPECT_EQ(entries[1].stem, "patient_easy");
  EXPECT_EQ(entries[2].stem, "default");
  EXPECT_EQ(entries[3].stem, "patient_moderate");
  EXPECT_EQ(entries[4].stem, "patient_hard");
}

TEST(ScenarioCatalog, ABrokenScenarioIsListedWithItsProblems) {
  TempDir dir;
  dir.write("broken.yaml", "version: 1\nname: broken\ndifficulty: tricky\norgans: []\n");
  const std::vector<app::CatalogEntry> entries = app::scan_scenarios(dir.path());
  ASSERT_EQ(entries.size(), 1U);
  EXPECT_EQ(entries[0].name, "broken");  // its stem: the file did not load
  EXPECT_NE(entries[0].problems.find("difficulty: expected introductory, easy, moderate or hard"),
            std::string::npos)
      << entries[0].problems;
  EXPECT_TRUE(entries[0].preview.empty());
}

TEST(ScenarioCatalog, TheTaskInWordsCarriesTheScenariosThresholds) {
  sim::TaskSpec t;
  t.target = "cystic_duct";
  t.insertion_depth_m = 0.012;
  t.hold_s = 2.5;
  t.time_limit_s = 300.0;
  t.duct_injury_force_n = 1.5;
  t.duct_squeeze_n = 4.0;
  t.duct_injury_time_s = 0.5;
  t.forbidden_organs = {"common_hepatic_duct", "liver"};
  std::string all;
  for (const std::string& line : app::task_in_words(t)) all += line + "\n";
  for (const char* expected :
       {"insert it 12 mm into the lumen", "for 2.5 s", "You have 5 minutes.",
        "harder than 1.5 N, or squeeze it harder than 4 N, for more than 0.5 s",
        "touch the common hepatic duct or the liver"}) {
    EXPECT_NE(all.find(expected), std::string::npos) << expected << "\n in:\n" << all;
  }
}

}  // namespace
}  // namespace lap::test
