// What a training station remembers (app/station_settings.h): written and read back, and a
// settings file edited by hand or left by another version is never trusted.

#include "app/station_settings.h"

#include <gtest/gtest.h>

#include <QSettings>

#include "tests/test_support.h"

namespace lap::test {
namespace {

QString file_in(const TempDir& dir) {
  return QString::fromStdString((dir.path() / "station.conf").string());
}

TEST(StationSettings, RemembersTheTraineesTheScenarioAndTheDevices) {
  TempDir dir;
  {
    app::StationSettings s(file_in(dir));
    EXPECT_EQ(s.last_trainee(), "");
    EXPECT_EQ(s.devices()[0], "simulated");
    EXPECT_EQ(s.dominant_hand(), 1);
    s.remember_trainee("  alice ");
    s.remember_trainee("R-2041");
    s.remember_trainee("alice");  // again: first of the recent ones, not twice
    s.set_last_scenario("/x/patient_easy.yaml");
    s.set_devices({"phantom:Left+gripper:A1", "scripted:/x/expert_right.csv"});
    s.set_dominant_hand(0);
    s.set_full_screen(true);
    EXPECT_EQ(s.render_quality(), "auto");
    s.set_render_quality("fast");
    s.sync();
  }
  app::StationSettings s(file_in(dir));
  EXPECT_EQ(s.last_trainee(), "alice");
  EXPECT_EQ(s.recent_trainees(), QStringList({"alice", "R-2041"}));
  EXPECT_EQ(s.last_scenario(), "/x/patient_easy.yaml");
  EXPECT_EQ(s.devices()[0], "phantom:Left+gripper:A1");
  EXPECT_EQ(s.devices()[1], "scripted:/x/expert_right.csv");
  EXPECT_EQ(s.dominant_hand(), 0);
  EXPECT_TRUE(s.full_screen());
  EXPECT_EQ(s.render_quality(), "fast");
}

TEST(StationSettings, ValuesThatDoNotParseAreIgnored) {
  TempDir dir;
  {
    QSettings raw(file_in(dir), QSettings::IniFormat);
    raw.setValue("devices/left", "teleporter:3");
    raw.setValue("devices/right", "phantom+gripper@not-a-path");
    raw.setValue("trainee/dominant_hand", 7);
    raw.setValue("trainee/last", QString(200, 'x'));
    raw.setValue("trainee/recent", QStringList({"bob", "", "bob", QString("a\u0007b")}));
    raw.setValue("view/render_quality", "ultra");
  }
  app::StationSettings s(file_in(dir));
  EXPECT_EQ(s.devices()[0], "simulated");
  EXPECT_EQ(s.devices()[1], "simulated");
  EXPECT_EQ(s.dominant_hand(), 1);
  EXPECT_EQ(s.last_trainee(), "");
  EXPECT_EQ(s.recent_trainees(), QStringList({"bob"}));
  EXPECT_EQ(s.render_quality(), "auto");
}

TEST(StationSettings, KeepsTheTwentyMostRecentTrainees) {
  TempDir dir;
  app::StationSettings s(file_in(dir));
  for (int i = 0; i < 25; ++i) s.remember_trainee(QString("trainee %1").arg(i));
  const QStringList recent = s.recent_trainees();
  ASSERT_EQ(recent.size(), app::StationSettings::kRecentTrainees);
  EXPECT_EQ(recent.front(), "trainee 24");
  EXPECT_EQ(recent.back(), "trainee 5");
}

TEST(CheckedTrainee, TrimsAndRefusesWhatIsNotANameOrId) {
  QString why;
  EXPECT_EQ(app::checked_trainee("  Dr A. Rivera  ", &why), "Dr A. Rivera");
  EXPECT_TRUE(why.isEmpty());
  EXPECT_EQ(app::checked_trainee("   ", &why), "");
  EXPECT_EQ(why, "Type your name or trainee ID.");
  EXPECT_EQ(app::checked_trainee(QString(65, 'a'), &why), "");
  EXPECT_EQ(why, "A name or ID of at most 64 characters, please.");
  EXPECT_EQ(app::checked_trainee(QString(64, 'a')), QString(64, 'a'));
  EXPECT_EQ(app::checked_trainee("tab\there", &why), "");
  EXPECT_EQ(why, "Letters, digits, spaces and punctuation only, please.");
  EXPECT_EQ(app::checked_trainee("Zoë Ødegård"), "Zoë Ødegård");
}

}  // namespace
}  // namespace lap::test
