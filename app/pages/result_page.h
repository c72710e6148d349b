#pragma once
/// \file
/// The result of an attempt: success or failure with its reasons in words, when each phase was
/// reached, the main training metrics (docs/metrics.md) beside the scenario's expert
/// benchmarks, and this trainee's earlier attempts on the same patient; then the next attempt,
/// another patient, or signing out. Everything shown comes from the session's report (the
/// metrics JSON that metrics.json holds: "task", "metrics", "proficiency").

#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QWidget>
#include <nlohmann/json.hpp>
#include <vector>

#include "app/session_archive.h"

namespace lap::app {

class ResultPage : public QWidget {
  Q_OBJECT

 public:
  explicit ResultPage(QWidget* parent = nullptr);

  /// Shows an attempt: its report, its record (the patient, where it is saved) and the
  /// trainee's attempts on this patient, newest first (this one among them when filed).
  void show_result(const nlohmann::ordered_json& report, const SessionRow& attempt,
                   const std::vector<SessionRow>& attempts);
  /// Only the attempts (when they are known after the result: the database answered later).
  void show_attempts(const std::vector<SessionRow>& attempts, const QString& current_uuid);
  /// Where the attempts come from, when they cannot be shown (no session database).
  void show_attempts_unavailable(const QString& why);

 signals:
  void next_attempt();
  void another_patient();
  void sign_out();

 private:
  QLabel* headline_ = nullptr;
  QLabel* reasons_ = nullptr;
  QTableWidget* phases_ = nullptr;
  QTableWidget* metrics_ = nullptr;
  QTableWidget* attempts_ = nullptr;
  QLabel* attempts_note_ = nullptr;
  QLabel* saved_ = nullptr;
};

/// A task's failure reason (task_engine.h's vocabulary) in words.
[[nodiscard]] QString reason_in_words(const QString& reason);

}  // namespace lap::app
