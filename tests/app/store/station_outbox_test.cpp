// A residency programme's stations and its PostgreSQL server (the fixture's real server): a
// station keeps working while the server is down (sessions go into its SQLite outbox) and uploads
// them when it is back; the server killed in the middle of an upload loses nothing and doubles
// nothing; an upload repeated after a crash between the server's commit and the outbox's update
// doubles nothing; two stations share the records and the accounts; wrong credentials and an
// unreachable server are clear errors that lose nothing.

#include <gtest/gtest.h>

#include <QFile>
#include <QTimeZone>
#include <QUuid>
#include <set>

#include "app/store/session_store.h"
#include "tests/app/store/store_test_support.h"

namespace lap::app {
namespace {

using testing::Backend;
using testing::BackendFixture;
using testing::PostgresServer;
using testing::sample_session;

QDateTime at(int minute) {
  return QDateTime(QDate(2025, 3, 1), QTime(9, 0), QTimeZone::utc()).addSecs(60 * minute);
}

bool mentions(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class StationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    backend_ = std::make_unique<BackendFixture>(Backend::kPostgresql);
    if (!backend_->available()) GTEST_SKIP() << backend_->why_not();
    server_ = PostgresServer::get(nullptr);
  }
  void TearDown() override {
    // Whatever a test did to the server, the next one finds it running.
    if (server_ != nullptr && crashed_) {
      EXPECT_TRUE(server_->restart());
    }
  }
  void crash() {
    ASSERT_TRUE(server_->crash());
    crashed_ = true;
  }
  void restart() {
    ASSERT_TRUE(server_->restart());
    crashed_ = false;
  }
  std::unique_ptr<SessionStore> open(const QString& station) {
    Result<std::unique_ptr<SessionStore>> store = SessionStore::open(backend_->station(station));
    EXPECT_TRUE(store.ok()) << store.message();
    return store.ok() ? std::move(store).value() : nullptr;
  }
  long long on_server(const QString& sql) {
    return testing::raw_count(backend_->station("any"), true, sql);
  }
  std::unique_ptr<BackendFixture> backend_;
  const PostgresServer* server_ = nullptr;
  bool crashed_ = false;
};

TEST_F(StationTest, SessionsWaitInTheOutboxWhileTheServerIsDown) {
  crash();
  auto station = open(QStringLiteral("lab-1"));
  ASSERT_TRUE(station);
  SyncStatus status = station->sync_status();
  EXPECT_TRUE(status.server_configured);
  EXPECT_FALSE(status.server_reachable);
  EXPECT_TRUE(mentions(status.last_error.toStdString(), "cannot connect"))
      << status.last_error.toStdString();
  EXPECT_TRUE(mentions(status.last_error.toStdString(), "postgresql://station@127.0.0.1:"))
      << status.last_error.toStdString();

  std::vector<SessionRow> added;
  for (int i = 0; i < 3; ++i) {
    added.push_back(sample_session(QStringLiteral("ana"), at(i)));
    ASSERT_TRUE(station->add_session(added.back()).ok());  // kept: the server is not needed
  }
  EXPECT_EQ(station->sync_status().pending, 3);
  // The station reads its own while offline.
  Result<std::vector<SessionRow>> offline = station->sessions(QStringLiteral("ana"));
  ASSERT_TRUE(offline.ok()) << offline.message();
  EXPECT_EQ(offline->size(), 3U);
  Status upload = station->upload_pending();
  ASSERT_FALSE(upload.ok());
  EXPECT_TRUE(mentions(upload.message(), "3 session(s) stay queued")) << upload.message();

  restart();
  ASSERT_TRUE(station->upload_pending().ok());
  EXPECT_EQ(station->sync_status().pending, 0);
  EXPECT_TRUE(station->sync_status().server_reachable);
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(*) FROM sessions")), 3);
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(*) FROM session_metrics")), 3 * 6);
}

TEST_F(StationTest, TheServerKilledMidUploadLosesNothingAndDoublesNothing) {
  auto station = open(QStringLiteral("lab-1"));
  ASSERT_TRUE(station);
  crash();
  std::set<QString> uuids;
  for (int i = 0; i < 10; ++i) {
    SessionRow row = sample_session(i % 2 ? QStringLiteral("ana") : QStringLiteral("ben"), at(i));
    uuids.insert(row.uuid);
    ASSERT_TRUE(station->add_session(row).ok());
  }
  EXPECT_EQ(station->sync_status().pending, 10);
  restart();
  // Upload, and kill the server (every process at once) after the fourth session is committed.
  int seen = 0;
  Status upload = station->upload_pending([&](int done, int total) {
    EXPECT_EQ(total, 10);
    seen = done;
    if (done == 4) crash();
    return true;
  });
  ASSERT_FALSE(upload.ok());
  EXPECT_EQ(seen, 4);
  EXPECT_TRUE(mentions(upload.message(), "the server went away after 4 of 10")) << upload.message();
  EXPECT_EQ(station->sync_status().pending, 6);
  // More sessions while it is down.
  for (int i = 10; i < 12; ++i) {
    SessionRow row = sample_session(QStringLiteral("ana"), at(i));
    uuids.insert(row.uuid);
    ASSERT_TRUE(station->add_session(row).ok());
  }
  EXPECT_EQ(station->sync_status().pending, 8);
  restart();
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(*) FROM sessions")), 4);  // committed stays
  ASSERT_TRUE(station->upload_pending().ok());
  EXPECT_EQ(station->sync_status().pending, 0);
  // Every session once, with its metrics once.
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(*) FROM sessions")), 12);
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(DISTINCT uuid) FROM sessions")), 12);
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(*) FROM session_metrics")), 12 * 6);
  Result<std::vector<SessionRow>> all = station->all_sessions();
  ASSERT_TRUE(all.ok()) << all.message();
  std::set<QString> stored;
  for (const SessionRow& r : all.value()) stored.insert(r.uuid);
  EXPECT_EQ(stored, uuids);
  EXPECT_EQ(all->size(), 12U);
}

TEST_F(StationTest, AnUploadRepeatedAfterACrashDoublesNothing) {
  auto station = open(QStringLiteral("lab-1"));
  ASSERT_TRUE(station);
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(station->add_session(sample_session(QStringLiteral("ana"), at(i))).ok());
  }
  EXPECT_EQ(station->sync_status().pending, 0);  // uploaded as they were added
  // As if the station had died after the server's commits but before its outbox was updated:
  // every session queued again.
  ASSERT_TRUE(testing::raw_sql(backend_->station("lab-1"), false,
                               QStringLiteral("INSERT INTO outbox (session_uuid, queued_utc) "
                                              "SELECT uuid, added_utc FROM sessions")));
  EXPECT_EQ(station->sync_status().pending, 5);
  ASSERT_TRUE(station->upload_pending().ok());
  EXPECT_EQ(station->sync_status().pending, 0);
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(*) FROM sessions")), 5);
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(*) FROM session_metrics")), 5 * 6);
}

TEST_F(StationTest, TwoStationsShareRecordsAndAccounts) {
  auto lab1 = open(QStringLiteral("lab-1"));
  ASSERT_TRUE(lab1);
  ASSERT_TRUE(lab1->set_instructor_password(nullptr, QStringLiteral("dr-lee"),
                                            QStringLiteral("laparoscopy-2025"), 1000)
                  .ok());
  auto lab2 = open(QStringLiteral("lab-2"));
  ASSERT_TRUE(lab2);
  SessionRow a = sample_session(QStringLiteral("ana"), at(0));
  a.station = QStringLiteral("lab-1");
  SessionRow b = sample_session(QStringLiteral("ana"), at(1));
  b.station = QStringLiteral("lab-2");
  ASSERT_TRUE(lab1->add_session(a).ok());
  ASSERT_TRUE(lab2->add_session(b).ok());
  ASSERT_TRUE(lab2->add_trainee(QStringLiteral("carl")).ok());
  for (SessionStore* s : {lab1.get(), lab2.get()}) {
    Result<std::vector<SessionRow>> ana = s->sessions(QStringLiteral("ana"));
    ASSERT_TRUE(ana.ok()) << ana.message();
    ASSERT_EQ(ana->size(), 2U);
    EXPECT_EQ((ana.value())[0].station, QStringLiteral("lab-2"));
    EXPECT_EQ((ana.value())[1].station, QStringLiteral("lab-1"));
    EXPECT_EQ(s->trainees().value(), (std::vector<QString>{"ana", "carl"}));
  }
  // The account made at lab-1 signs in at lab-2, and still does with the server down (the
  // station's copy), where lab-2 shows its own sessions.
  EXPECT_TRUE(
      lab2->sign_in_instructor(QStringLiteral("dr-lee"), QStringLiteral("laparoscopy-2025")).ok());
  crash();
  Result<Viewer> offline =
      lab2->sign_in_instructor(QStringLiteral("dr-lee"), QStringLiteral("laparoscopy-2025"));
  ASSERT_TRUE(offline.ok()) << offline.message();
  Result<std::vector<SessionRow>> own = lab2->all_sessions(offline.value());
  ASSERT_TRUE(own.ok()) << own.message();
  ASSERT_EQ(own->size(), 1U);
  EXPECT_EQ(own->front().uuid, b.uuid);
  // Accounts are the server's: none set while it is down.
  Status refused = lab2->set_instructor_password(&offline.value(), QStringLiteral("dr-kim"),
                                                 QStringLiteral("laparoscopy-2025"), 1000);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(mentions(refused.message(), "does not answer")) << refused.message();
}

TEST_F(StationTest, WrongCredentialsAreClearAndLoseNothing) {
  StoreConnection c = backend_->station(QStringLiteral("lab-1"));
  c.password = QStringLiteral("not-the-password");
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(c);
  ASSERT_TRUE(store.ok()) << store.message();
  const std::string why = store.value()->sync_status().last_error.toStdString();
  EXPECT_TRUE(mentions(why, "password authentication failed")) << why;
  ASSERT_TRUE(store.value()->add_session(sample_session(QStringLiteral("ana"), at(0))).ok());
  EXPECT_EQ(store.value()->sync_status().pending, 1);
  Status upload = store.value()->upload_pending();
  ASSERT_FALSE(upload.ok());
  EXPECT_TRUE(mentions(upload.message(), "password authentication failed")) << upload.message();
  EXPECT_TRUE(mentions(upload.message(), "1 session(s) stay queued")) << upload.message();
  EXPECT_EQ(on_server(QStringLiteral("SELECT COUNT(*) FROM sessions")), -1);  // no tables made
}

TEST_F(StationTest, ThePasswordCanComeFromAnOwnerOnlyFile) {
  StoreConnection c = backend_->station(QStringLiteral("lab-1"));
  const QString file = backend_->folder() + QStringLiteral("/db-password");
  {
    QFile f(file);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    f.write(c.password.toUtf8() + "\n");
    f.setPermissions(QFileDevice::ReadOwner | QFileDevice::WriteOwner);
  }
  c.password.clear();
  c.password_file = file;
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(c);
  ASSERT_TRUE(store.ok()) << store.message();
  EXPECT_TRUE(store.value()->sync_status().server_reachable)
      << store.value()->sync_status().last_error.toStdString();
}

TEST_F(StationTest, AnUnreachableServerIsToldNotWaitedOn) {
  StoreConnection c = backend_->station(QStringLiteral("lab-1"));
  c.host = backend_->folder();  // a folder with no server's socket in it
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(c);
  ASSERT_TRUE(store.ok()) << store.message();
  const std::string why = store.value()->sync_status().last_error.toStdString();
  EXPECT_TRUE(mentions(why, "cannot connect")) << why;
  EXPECT_TRUE(mentions(why, backend_->folder().toStdString())) << why;
  ASSERT_TRUE(store.value()->add_session(sample_session(QStringLiteral("ana"), at(0))).ok());
  Result<std::vector<SessionRow>> own = store.value()->sessions(QStringLiteral("ana"));
  ASSERT_TRUE(own.ok());
  EXPECT_EQ(own->size(), 1U);
}

}  // namespace
}  // namespace lap::app
