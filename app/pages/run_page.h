#pragma once
/// \file
/// The run: the operative field (OperativeView, the running session) under a bar with the
/// patient, the trainee, the session's clock, what the keys move, and Pause, Restart and End.
/// Pausing zeroes the forces and stops the task's clock (LiveSession::pause); a watchdog's pause
/// is shown with its reason. When the session ends by itself (its task succeeded or failed, its
/// scripted devices ran out) the page says so (ended()), and the window shows the result.

#include <QLabel>
#include <QPushButton>
#include <QTimer>
#include <QWidget>
#include <array>

#include "app/live_session.h"
#include "app/operative_view.h"
#include "sim/setup/scene.h"

namespace lap::app {

class RunPage : public QWidget {
  Q_OBJECT

 public:
  explicit RunPage(QWidget* parent = nullptr);

  [[nodiscard]] OperativeView* operative() { return operative_; }
  [[nodiscard]] LiveSession& session() { return operative_->session(); }

  /// Starts a session on `scene` with `devices`, run as `options` says; `who` heads the bar
  /// (the patient and the trainee). The diagnostics say why it did not start.
  [[nodiscard]] Status start(const sim::Scene& scene,
                             const std::array<hardware::DeviceSpec, 2>& devices,
                             const LiveSessionOptions& options, const QString& who);
  /// Pause or resume (the bar's button, P, Esc, Space).
  void toggle_pause();
  [[nodiscard]] bool paused() { return session().user_paused(); }

 signals:
  /// The session has ended by itself (task ended, devices ran out, time up).
  void ended();
  void restart_requested();
  void end_requested();

 private:
  void tick();

  OperativeView* operative_ = nullptr;
  QWidget* bar_ = nullptr;
  QLabel* who_ = nullptr;
  QLabel* state_ = nullptr;
  QLabel* clock_ = nullptr;
  QLabel* hand_ = nullptr;
  QPushButton* pause_ = nullptr;
  QPushButton* restart_ = nullptr;
  QPushButton* end_ = nullptr;
  QTimer timer_;
  double rate_hz_ = 1000.0;
  bool ended_signalled_ = true;
};

}  // namespace lap::app
