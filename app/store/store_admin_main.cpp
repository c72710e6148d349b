// laptrainer-store: the training-record database's set-up at a station (app/store/README.md).
//   laptrainer-store status                 where the store is, the server, the queued sessions
//   laptrainer-store upload                 upload the queued sessions now
//   laptrainer-store set-password NAME [--as INSTRUCTOR]
//                                           add an instructor or set a new password (the first
//                                           instructor needs no --as; later ones are set by a
//                                           signed-in instructor). Passwords are read from the
//                                           terminal without echo, or one per line from stdin.
// Exit codes: 0 ok, 2 a problem (printed as file: field: message), 64 wrong usage.

#include <termios.h>
#include <unistd.h>

#include <QCoreApplication>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "app/store/session_store.h"
#include "app/store/store_schema.h"

namespace {

constexpr int kExitProblems = 2;
constexpr int kExitUsage = 64;

const char* const kUsage =
    "usage: laptrainer-store status\n"
    "       laptrainer-store upload\n"
    "       laptrainer-store set-password NAME [--as INSTRUCTOR]\n";

// A line from the terminal with its echo off (or from stdin as it is when it is not a terminal).
std::string read_secret(const char* prompt) {
  const bool tty = ::isatty(STDIN_FILENO) != 0;
  termios saved{};
  if (tty) {
    std::cerr << prompt << std::flush;
    ::tcgetattr(STDIN_FILENO, &saved);
    termios quiet = saved;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    ::tcsetattr(STDIN_FILENO, TCSANOW, &quiet);
  }
  std::string line;
  std::getline(std::cin, line);
  if (tty) {
    ::tcsetattr(STDIN_FILENO, TCSANOW, &saved);
    std::cerr << "\n";
  }
  return line;
}

int problem(const std::string& message) {
  std::cerr << "laptrainer-store: " << message << "\n";
  return kExitProblems;
}

}  // namespace

int main(int argc, char** argv) {
  QCoreApplication app(argc, argv);  // Qt SQL loads its drivers as plugins
  const QStringList args = QCoreApplication::arguments().mid(1);
  if (args.isEmpty()) {
    std::cerr << kUsage;
    return kExitUsage;
  }
  const QString& command = args.front();
  if (command != QLatin1String("status") && command != QLatin1String("upload") &&
      command != QLatin1String("set-password")) {
    std::cerr << kUsage;
    return kExitUsage;
  }
  lap::Result<std::unique_ptr<lap::app::SessionStore>> opened =
      lap::app::SessionStore::open_default();
  if (!opened.ok()) return problem(opened.message());
  lap::app::SessionStore& store = *opened.value();

  if (command == QLatin1String("status")) {
    const lap::app::SyncStatus s = store.sync_status();
    std::cout << "station: " << store.connection().station.toStdString() << "\n"
              << "local database: " << store.local_path().toStdString() << "\n"
              << "schema version: " << lap::app::kSchemaVersion << "\n";
    if (!s.server_configured) {
      std::cout << "server: none (this station's database is the store)\n";
      return 0;
    }
    std::cout << "server: " << store.connection().server_name().toStdString()
              << (s.server_reachable ? " (answers)" : " (does not answer)") << "\n"
              << "queued sessions: " << s.pending << "\n";
    if (!s.last_error.isEmpty()) std::cout << "last error: " << s.last_error.toStdString() << "\n";
    return s.server_reachable ? 0 : kExitProblems;
  }
  if (command == QLatin1String("upload")) {
    const lap::Status uploaded = store.upload_pending([](int done, int total) {
      std::cerr << "laptrainer-store: uploaded " << done << " of " << total << "\n";
      return true;
    });
    if (!uploaded.ok()) return problem(uploaded.message());
    std::cout << "queued sessions: " << store.sync_status().pending << "\n";
    return 0;
  }
  // set-password NAME [--as INSTRUCTOR]
  if (args.size() != 2 && !(args.size() == 4 && args[2] == QLatin1String("--as"))) {
    std::cerr << kUsage;
    return kExitUsage;
  }
  std::optional<lap::app::Viewer> by;
  if (args.size() == 4) {
    const std::string own = read_secret("password of the instructor signing in: ");
    lap::Result<lap::app::Viewer> signed_in =
        store.sign_in_instructor(args[3], QString::fromStdString(own));
    if (!signed_in.ok()) return problem(signed_in.message());
    by = signed_in.value();
  }
  const std::string password = read_secret("new password: ");
  const std::string again = read_secret("the same again: ");
  if (password != again) return problem("the two passwords differ; nothing changed");
  const lap::Status set =
      store.set_instructor_password(by ? &*by : nullptr, args[1], QString::fromStdString(password));
  if (!set.ok()) return problem(set.message());
  std::cout << "instructor " << args[1].toStdString() << ": password set\n";
  return 0;
}
