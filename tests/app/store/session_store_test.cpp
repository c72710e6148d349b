// The training-record database (app/store/session_store.h), the same suite on both set-ups: a
// station's SQLite file, and a programme's PostgreSQL server (the fixture's, a fresh database per
// test) with the station's SQLite file as its outbox. Sessions round-trip every field; adding one
// twice keeps one; reading is newest first and filtered; metrics are rows a query can cross
// sessions with; bad rows are refused naming their field, and bad rows already in a database are
// named when read; older schemas are migrated and newer ones refused; instructors' accounts and
// who may see what.

#include "app/store/session_store.h"

#include <gtest/gtest.h>

#include <QSqlQuery>
#include <QTimeZone>
#include <QUuid>
#include <cmath>
#include <set>

#include "app/store/session_table.h"
#include "app/store/store_schema.h"
#include "tests/app/store/store_test_support.h"

namespace lap::app {
namespace {

using testing::Backend;
using testing::BackendFixture;
using testing::sample_session;

// Accounts in tests hash with few iterations (the default's 600,000 are tested once, below).
constexpr int kTestIterations = 1000;

QDateTime at(int minute) {
  return QDateTime(QDate(2025, 3, 1), QTime(9, 0), QTimeZone::utc()).addSecs(60 * minute);
}

bool mentions(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class StoreTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    backend_ = std::make_unique<BackendFixture>(GetParam());
    if (!backend_->available()) GTEST_SKIP() << backend_->why_not();
  }
  std::unique_ptr<SessionStore> open(const QString& station = QStringLiteral("station-a")) {
    Result<std::unique_ptr<SessionStore>> store = SessionStore::open(backend_->station(station));
    EXPECT_TRUE(store.ok()) << store.message();
    if (!store.ok()) return nullptr;
    if (GetParam() == Backend::kPostgresql) {
      EXPECT_TRUE(store.value()->sync_status().server_reachable)
          << store.value()->sync_status().last_error.toStdString();
    }
    return std::move(store).value();
  }
  bool postgres() const { return GetParam() == Backend::kPostgresql; }
  std::unique_ptr<BackendFixture> backend_;
};

void expect_same(const SessionRow& a, const SessionRow& b) {
  EXPECT_EQ(a.uuid, b.uuid);
  EXPECT_EQ(a.trainee, b.trainee);
  EXPECT_EQ(a.scenario_file, b.scenario_file);
  EXPECT_EQ(a.scenario_name, b.scenario_name);
  EXPECT_EQ(a.scenario_version, b.scenario_version);
  EXPECT_EQ(a.devices, b.devices);
  EXPECT_EQ(a.station, b.station);
  EXPECT_EQ(a.started_utc, b.started_utc);
  EXPECT_EQ(a.duration_s, b.duration_s);  // exactly: doubles round-trip
  EXPECT_EQ(a.result, b.result);
  EXPECT_EQ(a.reasons, b.reasons);
  if (std::isnan(a.completion_time_s)) {
    EXPECT_TRUE(std::isnan(b.completion_time_s));
  } else {
    EXPECT_EQ(a.completion_time_s, b.completion_time_s);
  }
  EXPECT_EQ(a.report_json, b.report_json);
  EXPECT_EQ(a.recording_dir, b.recording_dir);
  EXPECT_EQ(a.interrupted, b.interrupted);
}

TEST_P(StoreTest, EveryFieldRoundTrips) {
  auto store = open();
  ASSERT_TRUE(store);
  SessionRow row = sample_session(QStringLiteral("resident-07"), at(0).addMSecs(123));
  row.duration_s = 0.1 + 0.2;  // not a short decimal: must come back bit for bit
  row.devices = QStringLiteral("left=simulated; right=phantom:Left Omni+gripper:AB12 ’ü");
  ASSERT_TRUE(store->add_session(row).ok());
  Result<std::vector<SessionRow>> rows = store->sessions(QStringLiteral("resident-07"));
  ASSERT_TRUE(rows.ok()) << rows.message();
  ASSERT_EQ(rows->size(), 1U);
  expect_same(row, rows->front());
  EXPECT_EQ(rows->front().started_utc.timeSpec(), Qt::UTC);
}

TEST_P(StoreTest, NoCompletionTimeAndAnInterruptedSession) {
  auto store = open();
  ASSERT_TRUE(store);
  SessionRow row = sample_session(QStringLiteral("r1"), at(5));
  row.completion_time_s = std::nan("");
  row.result = QStringLiteral("incomplete");
  row.reasons.clear();
  row.interrupted = true;
  row.report_json.clear();  // a crashed session may have no report yet
  Status added = store->add_session(row);
  ASSERT_TRUE(added.ok()) << added.message();
  Result<SessionRow> back = store->session(row.uuid);
  ASSERT_TRUE(back.ok()) << back.message();
  expect_same(row, back.value());
}

TEST_P(StoreTest, AddingASessionTwiceKeepsOne) {
  auto store = open();
  ASSERT_TRUE(store);
  const SessionRow row = sample_session(QStringLiteral("r1"), at(0));
  ASSERT_TRUE(store->add_session(row).ok());
  ASSERT_TRUE(store->add_session(row).ok());
  // The same UUID spelt with braces and in capitals is the same session; its first copy stands.
  SessionRow again = row;
  again.uuid = QStringLiteral("{") + row.uuid.toUpper() + QStringLiteral("}");
  again.result = QStringLiteral("success");
  ASSERT_TRUE(store->add_session(again).ok());
  Result<std::vector<SessionRow>> rows = store->all_sessions();
  ASSERT_TRUE(rows.ok()) << rows.message();
  ASSERT_EQ(rows->size(), 1U);
  EXPECT_EQ(rows->front().result, QStringLiteral("failure"));
  Result<std::vector<MetricValue>> metrics = store->metrics(row.uuid);
  ASSERT_TRUE(metrics.ok());
  EXPECT_EQ(metrics->size(), 6U);
}

TEST_P(StoreTest, NewestFirstFilteredByTraineeAndScenario) {
  auto store = open();
  ASSERT_TRUE(store);
  const QString easy = QStringLiteral("scenarios/easy.yaml");
  std::vector<SessionRow> added;
  // Added out of time order; two trainees, two scenarios.
  for (int minute : {30, 10, 50, 20, 40}) {
    added.push_back(
        sample_session(QStringLiteral("ana"), at(minute), 0.5,
                       minute % 20 == 0 ? easy : QStringLiteral("scenarios/introductory.yaml")));
    ASSERT_TRUE(store->add_session(added.back()).ok());
  }
  ASSERT_TRUE(store->add_session(sample_session(QStringLiteral("ben"), at(35))).ok());
  Result<std::vector<SessionRow>> ana = store->sessions(QStringLiteral("ana"));
  ASSERT_TRUE(ana.ok()) << ana.message();
  ASSERT_EQ(ana->size(), 5U);
  const int expected_minutes[] = {50, 40, 30, 20, 10};
  for (size_t i = 0; i < 5; ++i)
    EXPECT_EQ((ana.value())[i].started_utc, at(expected_minutes[i])) << i;
  Result<std::vector<SessionRow>> ana_easy = store->sessions(QStringLiteral("ana"), easy);
  ASSERT_TRUE(ana_easy.ok());
  ASSERT_EQ(ana_easy->size(), 2U);
  EXPECT_EQ((ana_easy.value())[0].started_utc, at(40));
  EXPECT_EQ((ana_easy.value())[1].started_utc, at(20));
  Result<std::vector<SessionRow>> all = store->all_sessions();
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->size(), 6U);
  EXPECT_EQ((all.value())[2].trainee, QStringLiteral("ben"));  // 50, 40, 35, ...
  EXPECT_FALSE(store->sessions(QString()).ok());               // no trainee: not "everyone"
}

TEST_P(StoreTest, TraineesAreListedOnceSorted) {
  auto store = open();
  ASSERT_TRUE(store);
  for (const char* name : {"zoe", "Ali", "ben", "zoe"}) {
    ASSERT_TRUE(store->add_session(sample_session(QString::fromLatin1(name), at(0))).ok());
  }
  ASSERT_TRUE(store->add_trainee(QStringLiteral("carl")).ok());  // signed in, no session yet
  EXPECT_FALSE(store->add_trainee(QStringLiteral(" padded")).ok());
  Result<std::vector<QString>> names = store->trainees();
  ASSERT_TRUE(names.ok()) << names.message();
  EXPECT_EQ(names.value(), (std::vector<QString>{"Ali", "ben", "carl", "zoe"}));
}

TEST_P(StoreTest, MetricsAreRowsAQueryCanCrossSessionsWith) {
  auto store = open();
  ASSERT_TRUE(store);
  const SessionRow first = sample_session(QStringLiteral("ana"), at(0), 1.5);
  ASSERT_TRUE(store->add_session(first).ok());
  ASSERT_TRUE(store->add_session(sample_session(QStringLiteral("ana"), at(20), 0.75)).ok());
  ASSERT_TRUE(store->add_session(sample_session(QStringLiteral("ana"), at(10), 1.0)).ok());
  ASSERT_TRUE(store->add_session(sample_session(QStringLiteral("ben"), at(5), 2.0)).ok());
  ASSERT_TRUE(store
                  ->add_session(sample_session(QStringLiteral("ana"), at(30), 0.5,
                                               QStringLiteral("scenarios/hard.yaml")))
                  .ok());

  Result<std::vector<MetricValue>> metrics = store->metrics(first.uuid);
  ASSERT_TRUE(metrics.ok()) << metrics.message();
  std::map<QString, double> by_name;
  for (const MetricValue& m : metrics.value()) by_name[m.name] = m.value;
  ASSERT_EQ(by_name.size(), 6U);
  EXPECT_EQ(by_name["path_length_left_m"], 1.5);
  EXPECT_EQ(by_name["path_length_right_m"], 0.75);
  EXPECT_EQ(by_name["max_force_duct_n"], 2.5);
  EXPECT_EQ(by_name["catheter_drops"], 1.0);
  EXPECT_EQ(by_name["completion_time_s"], 40.125);
  EXPECT_TRUE(std::isnan(by_name["mean_jerk_left_m_per_s3"]));  // null: undefined

  // A learning curve: one trainee's metric, oldest first, on one scenario.
  Result<std::vector<MetricPoint>> curve =
      store->metric_history(QStringLiteral("path_length_left_m"), QStringLiteral("ana"),
                            QStringLiteral("scenarios/introductory.yaml"));
  ASSERT_TRUE(curve.ok()) << curve.message();
  ASSERT_EQ(curve->size(), 3U);
  EXPECT_EQ((curve.value())[0].value, 1.5);
  EXPECT_EQ((curve.value())[1].value, 1.0);
  EXPECT_EQ((curve.value())[2].value, 0.75);
  EXPECT_EQ((curve.value())[0].started_utc, at(0));
  // The cohort: every trainee, every scenario.
  Result<std::vector<MetricPoint>> cohort =
      store->metric_history(QStringLiteral("path_length_left_m"), QString());
  ASSERT_TRUE(cohort.ok());
  ASSERT_EQ(cohort->size(), 5U);
  EXPECT_EQ((cohort.value())[1].trainee, QStringLiteral("ben"));
  EXPECT_EQ((cohort.value())[1].value, 2.0);
  EXPECT_EQ((cohort.value())[4].scenario_file, QStringLiteral("scenarios/hard.yaml"));
}

TEST_P(StoreTest, BadSessionsAreRefusedNamingTheField) {
  auto store = open();
  ASSERT_TRUE(store);
  struct Case {
    const char* field;
    std::function<void(SessionRow&)> spoil;
  };
  const std::vector<Case> cases = {
      {"sessions.uuid", [](SessionRow& r) { r.uuid = QStringLiteral("not-a-uuid"); }},
      {"sessions.trainee", [](SessionRow& r) { r.trainee.clear(); }},
      {"sessions.trainee", [](SessionRow& r) { r.trainee = QStringLiteral("tab\there"); }},
      {"sessions.scenario_file", [](SessionRow& r) { r.scenario_file.clear(); }},
      {"sessions.scenario_version", [](SessionRow& r) { r.scenario_version = "abc"; }},
      {"sessions.station", [](SessionRow& r) { r.station.clear(); }},
      {"sessions.started_utc", [](SessionRow& r) { r.started_utc = QDateTime(); }},
      {"sessions.duration_s", [](SessionRow& r) { r.duration_s = -1.0; }},
      {"sessions.duration_s", [](SessionRow& r) { r.duration_s = std::nan(""); }},
      {"sessions.result", [](SessionRow& r) { r.result = QStringLiteral("passed"); }},
      {"sessions.reasons", [](SessionRow& r) { r.reasons << QStringLiteral("Duct Injury!"); }},
      {"sessions.completion_time_s", [](SessionRow& r) { r.completion_time_s = -3.0; }},
      {"sessions.report_json", [](SessionRow& r) { r.report_json = QStringLiteral("{oops"); }},
      {"report_json.metrics.catheter_drops",
       [](SessionRow& r) {
         r.report_json = QStringLiteral(R"({"metrics": {"catheter_drops": "one"}})");
       }},
  };
  for (const Case& c : cases) {
    SessionRow row = sample_session(QStringLiteral("r1"), at(0));
    c.spoil(row);
    Status added = store->add_session(row);
    ASSERT_FALSE(added.ok()) << c.field;
    bool named = false;
    for (const Diagnostic& d : added.diagnostics()) named = named || d.field == c.field;
    EXPECT_TRUE(named) << c.field << ": " << added.message();
    EXPECT_TRUE(mentions(added.message(), store->local_path().toStdString())) << added.message();
  }
  Result<std::vector<SessionRow>> rows = store->all_sessions();
  ASSERT_TRUE(rows.ok());
  EXPECT_TRUE(rows->empty());  // nothing half-stored
}

TEST_P(StoreTest, ABadRowInTheDatabaseIsNamedWhenRead) {
  auto store = open();
  ASSERT_TRUE(store);
  const SessionRow good = sample_session(QStringLiteral("r1"), at(0));
  const SessionRow bad = sample_session(QStringLiteral("r1"), at(1));
  ASSERT_TRUE(store->add_session(good).ok());
  ASSERT_TRUE(store->add_session(bad).ok());
  // Changed behind the store's back (an edit by hand, a faulty tool): values the schema's types
  // let through but the store does not take. On PostgreSQL the server's copy is the one read.
  const QString spoil =
      QStringLiteral(
          "UPDATE sessions SET started_utc = 'yesterday', reasons = 'duct_injury' "
          "WHERE uuid = '%1'")
          .arg(bad.uuid);
  std::string error;
  ASSERT_TRUE(testing::raw_sql(backend_->station("station-a"), postgres(), spoil, &error)) << error;
  Result<std::vector<SessionRow>> rows = store->sessions(QStringLiteral("r1"));
  ASSERT_FALSE(rows.ok());
  const std::string message = rows.message();
  EXPECT_TRUE(mentions(message, "sessions.started_utc")) << message;
  EXPECT_TRUE(mentions(message, "sessions.reasons")) << message;
  EXPECT_TRUE(mentions(message, bad.uuid.toStdString())) << message;
  EXPECT_TRUE(mentions(message, "'yesterday'")) << message;
  // The good one still reads on its own.
  Result<SessionRow> one = store->session(good.uuid);
  ASSERT_TRUE(one.ok()) << one.message();
  if (!postgres()) {
    // SQLite keeps text in a number column: named too.
    ASSERT_TRUE(
        testing::raw_sql(backend_->station("station-a"), false,
                         QStringLiteral("UPDATE sessions SET duration_s = 'long' WHERE uuid = '%1'")
                             .arg(good.uuid)));
    Result<SessionRow> spoilt = store->session(good.uuid);
    ASSERT_FALSE(spoilt.ok());
    EXPECT_TRUE(mentions(spoilt.message(), "sessions.duration_s")) << spoilt.message();
    EXPECT_TRUE(mentions(spoilt.message(), "'long'")) << spoilt.message();
  }
}

// The store's own database (SQLite file or server) opened outside the store.
std::unique_ptr<Database> open_raw(const BackendFixture& backend, const StoreConnection& c) {
  Result<std::unique_ptr<Database>> db = backend.backend() == Backend::kPostgresql
                                             ? Database::open_postgresql(c, c.password)
                                             : Database::open_sqlite(c.sqlite_path);
  EXPECT_TRUE(db.ok()) << db.message();
  return db.ok() ? std::move(db).value() : nullptr;
}

TEST_P(StoreTest, AnOlderSchemaIsMigratedKeepingItsSessions) {
  const StoreConnection c = backend_->station("station-a");
  const SessionRow old = sample_session(QStringLiteral("r1"), at(0), 1.25);
  {
    // A database as the first version of the schema left it, with a session in it.
    std::unique_ptr<Database> db = open_raw(*backend_, c);
    ASSERT_TRUE(db);
    ASSERT_TRUE(migrate(*db, 1).ok());
    Result<int> version = schema_version(*db);
    ASSERT_TRUE(version.ok());
    EXPECT_EQ(version.value(), 1);
    EXPECT_FALSE(db->handle().tables().contains(QStringLiteral("outbox")));
    ASSERT_TRUE(db->begin_write().ok());
    Result<std::vector<MetricValue>> metrics = report_metrics(old.report_json, db->name());
    ASSERT_TRUE(metrics.ok());
    ASSERT_TRUE(insert_session(*db, old, metrics.value()).ok());
    ASSERT_TRUE(db->commit().ok());
  }
  auto store = open();
  ASSERT_TRUE(store);
  Result<SessionRow> back = store->session(old.uuid);
  ASSERT_TRUE(back.ok()) << back.message();
  expect_same(old, back.value());
  std::unique_ptr<Database> db = open_raw(*backend_, c);
  ASSERT_TRUE(db);
  Result<int> version = schema_version(*db);
  ASSERT_TRUE(version.ok());
  EXPECT_EQ(version.value(), kSchemaVersion);
  EXPECT_TRUE(db->handle().tables().contains(QStringLiteral("outbox")));
  // One row per step, each applied once.
  Result<QSqlQuery> steps =
      db->run(QStringLiteral("SELECT COUNT(*), COUNT(DISTINCT version) FROM schema_version"), {},
              "schema_version", "count");
  ASSERT_TRUE(steps.ok() && steps->next());
  EXPECT_EQ(steps->value(0).toInt(), kSchemaVersion);
  EXPECT_EQ(steps->value(1).toInt(), kSchemaVersion);
}

TEST_P(StoreTest, ANewerSchemaIsRefused) {
  {
    auto store = open();
    ASSERT_TRUE(store);
  }
  const StoreConnection c = backend_->station("station-a");
  std::string error;
  ASSERT_TRUE(testing::raw_sql(c, postgres(),
                               QStringLiteral("INSERT INTO schema_version VALUES (99, "
                                              "'2030-01-01T00:00:00.000Z', 'from the future')"),
                               &error))
      << error;
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(c);
  if (!postgres()) {
    ASSERT_FALSE(store.ok());
    EXPECT_TRUE(mentions(store.message(), "schema version 99")) << store.message();
    EXPECT_TRUE(mentions(store.message(), "newer than this laptrainer knows")) << store.message();
    return;
  }
  // A station whose server is newer keeps working on its own, and says why it does not upload.
  ASSERT_TRUE(store.ok()) << store.message();
  const SyncStatus status = store.value()->sync_status();
  EXPECT_FALSE(status.server_reachable);
  EXPECT_TRUE(mentions(status.last_error.toStdString(), "newer than this laptrainer knows"))
      << status.last_error.toStdString();
  EXPECT_TRUE(store.value()->add_session(sample_session(QStringLiteral("r1"), at(0))).ok());
  EXPECT_EQ(store.value()->sync_status().pending, 1);
}

TEST_P(StoreTest, ADatabaseThatIsNotAStoreIsRefused) {
  const StoreConnection c = backend_->station("station-a");
  {
    std::unique_ptr<Database> db = open_raw(*backend_, c);
    ASSERT_TRUE(db);
    ASSERT_TRUE(db->run(QStringLiteral("CREATE TABLE sessions (id INTEGER)"), {}, "", "make").ok());
  }
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(c);
  const std::string message =
      store.ok() ? store.value()->sync_status().last_error.toStdString() : store.message();
  if (!postgres()) {
    EXPECT_FALSE(store.ok());
  }
  EXPECT_TRUE(mentions(message, "not a laptrainer store")) << message;
}

// --- Accounts and access ---------------------------------------------------------------------

TEST_P(StoreTest, InstructorsSignInWithTheirPasswordOnly) {
  auto store = open();
  ASSERT_TRUE(store);
  Result<bool> any = store->has_instructors();
  ASSERT_TRUE(any.ok());
  EXPECT_FALSE(any.value());
  // The first instructor is set up at the station, with nobody signed in.
  ASSERT_TRUE(store
                  ->set_instructor_password(nullptr, QStringLiteral("dr-lee"),
                                            QStringLiteral("laparoscopy-2025"), kTestIterations)
                  .ok());
  EXPECT_TRUE(store->has_instructors().value());
  Result<Viewer> lee =
      store->sign_in_instructor(QStringLiteral("dr-lee"), QStringLiteral("laparoscopy-2025"));
  ASSERT_TRUE(lee.ok()) << lee.message();
  EXPECT_TRUE(lee->is_instructor());
  EXPECT_EQ(lee->name(), QStringLiteral("dr-lee"));

  // Wrong password and unknown name: the same answer.
  Result<Viewer> wrong =
      store->sign_in_instructor(QStringLiteral("dr-lee"), QStringLiteral("laparoscopy-2024"));
  Result<Viewer> unknown =
      store->sign_in_instructor(QStringLiteral("dr-who"), QStringLiteral("laparoscopy-2025"));
  ASSERT_FALSE(wrong.ok());
  ASSERT_FALSE(unknown.ok());
  EXPECT_TRUE(mentions(wrong.message(), "wrong name or password")) << wrong.message();
  EXPECT_EQ(wrong.diagnostics().front().message, unknown.diagnostics().front().message);

  // Only a signed-in instructor adds more; never a trainee; short passwords never.
  EXPECT_FALSE(store
                   ->set_instructor_password(nullptr, QStringLiteral("mallory"),
                                             QStringLiteral("let-me-in-please"), kTestIterations)
                   .ok());
  const Viewer trainee = Viewer::trainee(QStringLiteral("r1"));
  EXPECT_FALSE(store
                   ->set_instructor_password(&trainee, QStringLiteral("r1"),
                                             QStringLiteral("let-me-in-please"), kTestIterations)
                   .ok());
  EXPECT_FALSE(store
                   ->set_instructor_password(&lee.value(), QStringLiteral("dr-kim"),
                                             QStringLiteral("short"), kTestIterations)
                   .ok());
  ASSERT_TRUE(store
                  ->set_instructor_password(&lee.value(), QStringLiteral("dr-kim"),
                                            QStringLiteral("laparoscopy-2025"), kTestIterations)
                  .ok());
  EXPECT_TRUE(
      store->sign_in_instructor(QStringLiteral("dr-kim"), QStringLiteral("laparoscopy-2025")).ok());

  // Stored as salt and hash, never the password; the same password under two salts.
  const StoreConnection c = backend_->station("station-a");
  EXPECT_EQ(testing::raw_count(c, postgres(),
                               QStringLiteral("SELECT COUNT(DISTINCT hash_hex) FROM instructors")),
            2);
  EXPECT_EQ(testing::raw_count(c, postgres(),
                               QStringLiteral("SELECT COUNT(*) FROM instructors WHERE hash_hex "
                                              "LIKE '%laparoscopy%' OR salt_hex = ''")),
            0);
  EXPECT_EQ(
      testing::raw_count(c, postgres(), QStringLiteral("SELECT MIN(iterations) FROM instructors")),
      kTestIterations);
}

TEST_P(StoreTest, TheDefaultWorkFactorIsStoredAndChecked) {
  auto store = open();
  ASSERT_TRUE(store);
  ASSERT_TRUE(store
                  ->set_instructor_password(nullptr, QStringLiteral("dr-lee"),
                                            QStringLiteral("laparoscopy-2025"))
                  .ok());
  EXPECT_EQ(testing::raw_count(backend_->station("station-a"), postgres(),
                               QStringLiteral("SELECT iterations FROM instructors")),
            600000);
  EXPECT_TRUE(
      store->sign_in_instructor(QStringLiteral("dr-lee"), QStringLiteral("laparoscopy-2025")).ok());
}

TEST_P(StoreTest, ADamagedAccountIsNamed) {
  auto store = open();
  ASSERT_TRUE(store);
  ASSERT_TRUE(store
                  ->set_instructor_password(nullptr, QStringLiteral("dr-lee"),
                                            QStringLiteral("laparoscopy-2025"), kTestIterations)
                  .ok());
  ASSERT_TRUE(testing::raw_sql(backend_->station("station-a"), postgres(),
                               QStringLiteral("UPDATE instructors SET hash_hex = 'zz'")));
  Result<Viewer> lee =
      store->sign_in_instructor(QStringLiteral("dr-lee"), QStringLiteral("laparoscopy-2025"));
  ASSERT_FALSE(lee.ok());
  EXPECT_TRUE(mentions(lee.message(), "instructors.hash_hex")) << lee.message();
}

TEST_P(StoreTest, TraineesSeeTheirOwnSessionsInstructorsEveryones) {
  auto store = open();
  ASSERT_TRUE(store);
  const SessionRow ana = sample_session(QStringLiteral("ana"), at(0));
  const SessionRow ben = sample_session(QStringLiteral("ben"), at(1));
  ASSERT_TRUE(store->add_session(ana).ok());
  ASSERT_TRUE(store->add_session(ben).ok());
  ASSERT_TRUE(store
                  ->set_instructor_password(nullptr, QStringLiteral("dr-lee"),
                                            QStringLiteral("laparoscopy-2025"), kTestIterations)
                  .ok());
  const Viewer as_ana = Viewer::trainee(QStringLiteral("ana"));

  Result<std::vector<SessionRow>> own = store->sessions(as_ana, QStringLiteral("ana"));
  ASSERT_TRUE(own.ok());
  ASSERT_EQ(own->size(), 1U);
  Result<std::vector<SessionRow>> others = store->sessions(as_ana, QStringLiteral("ben"));
  ASSERT_FALSE(others.ok());
  EXPECT_TRUE(mentions(others.message(), "'ana' may see only their own sessions, not 'ben''s"))
      << others.message();
  Result<std::vector<SessionRow>> everyone = store->all_sessions(as_ana);
  ASSERT_TRUE(everyone.ok());
  ASSERT_EQ(everyone->size(), 1U);
  EXPECT_EQ(everyone->front().trainee, QStringLiteral("ana"));
  EXPECT_EQ(store->trainees(as_ana).value(), std::vector<QString>{QStringLiteral("ana")});
  EXPECT_FALSE(store->session(as_ana, ben.uuid).ok());
  EXPECT_FALSE(store->metrics(as_ana, ben.uuid).ok());
  EXPECT_TRUE(store->metrics(as_ana, ana.uuid).ok());
  EXPECT_TRUE(
      store->metric_history(as_ana, QStringLiteral("completion_time_s"), QStringLiteral("ana"))
          .ok());
  EXPECT_FALSE(store->metric_history(as_ana, QStringLiteral("completion_time_s"), QString()).ok());
  // A trainee with no name sees nobody's (not everyone's).
  const Viewer nobody = Viewer::trainee(QString());
  EXPECT_FALSE(store->sessions(nobody, QString()).ok());
  EXPECT_FALSE(store->all_sessions(nobody).ok());

  Result<Viewer> lee =
      store->sign_in_instructor(QStringLiteral("dr-lee"), QStringLiteral("laparoscopy-2025"));
  ASSERT_TRUE(lee.ok());
  EXPECT_EQ(store->all_sessions(lee.value()).value().size(), 2U);
  EXPECT_EQ(store->sessions(lee.value(), QStringLiteral("ben")).value().size(), 1U);
  EXPECT_EQ(store->trainees(lee.value()).value().size(), 2U);
  EXPECT_TRUE(store->session(lee.value(), ben.uuid).ok());
  EXPECT_EQ(store->metric_history(lee.value(), QStringLiteral("completion_time_s"), QString())
                .value()
                .size(),
            2U);
}

std::string backend_name(const ::testing::TestParamInfo<Backend>& info) {
  return info.param == Backend::kSqlite ? "sqlite" : "postgresql";
}

INSTANTIATE_TEST_SUITE_P(Backends, StoreTest,
                         ::testing::Values(Backend::kSqlite, Backend::kPostgresql), backend_name);

}  // namespace
}  // namespace lap::app
