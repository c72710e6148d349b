#include "app/pages/run_page.h"

#include <QHBoxLayout>
#include <QVBoxLayout>
#include <cmath>

#include "app/pages/page_style.h"

namespace lap::app {
namespace {

constexpr int kTickMs = 100;  // the bar's refresh; the end is seen within it

QString run_clock_text(double s) {
  const int whole = static_cast<int>(std::floor(s));
  return QString("%1:%2.%3")
      .arg(whole / 60)
      .arg(whole % 60, 2, 10, QChar('0'))
      .arg(static_cast<int>(std::floor((s - whole) * 10.0)));
}

}  // namespace

RunPage::RunPage(QWidget* parent) : QWidget(parent) {
  auto* v = new QVBoxLayout(this);
  v->setContentsMargins(0, 0, 0, 0);
  v->setSpacing(0);
  bar_ = new QWidget(this);
  bar_->setObjectName("run_bar");
  bar_->setAttribute(Qt::WA_StyledBackground);
  bar_->setStyleSheet("QWidget#run_bar { background: #151a20; border-bottom: 1px solid #323c48; }");
  auto* h = new QHBoxLayout(bar_);
  h->setContentsMargins(16, 8, 12, 8);
  h->setSpacing(14);
  who_ = new QLabel(bar_);
  who_->setObjectName("run_who");
  who_->setTextFormat(Qt::RichText);
  h->addWidget(who_, 1);
  state_ = new QLabel(bar_);
  state_->setObjectName("run_state");
  h->addWidget(state_);
  hand_ = new QLabel(bar_);
  hand_->setObjectName("run_hand");
  hand_->setStyleSheet("color: #9aa7b4;");
  h->addWidget(hand_);
  clock_ = new QLabel("0:00.0", bar_);
  clock_->setObjectName("run_clock");
  clock_->setMinimumWidth(80);
  clock_->setAlignment(Qt::AlignRight | Qt::AlignVCenter);
  clock_->setStyleSheet("font-family: 'DejaVu Sans Mono'; font-size: 15pt; font-weight: 600;");
  h->addWidget(clock_);
  pause_ = secondary_button("Pause", bar_);
  pause_->setObjectName("pause");
  pause_->setToolTip("Pause (P or Esc): no force, the clock stops; Space resumes");
  pause_->setFocusPolicy(Qt::NoFocus);  // the keys stay with the operative field
  restart_ = secondary_button("Restart", bar_);
  restart_->setObjectName("restart");
  restart_->setToolTip("A fresh attempt on the same patient (Ctrl+R)");
  restart_->setFocusPolicy(Qt::NoFocus);
  end_ = secondary_button("End Attempt", bar_);
  end_->setObjectName("end_attempt");
  end_->setToolTip("End this attempt now and see its result (Ctrl+E)");
  end_->setFocusPolicy(Qt::NoFocus);
  for (QPushButton* b : {pause_, restart_, end_}) h->addWidget(b);
  v->addWidget(bar_);

  operative_ = new OperativeView(this);
  v->addWidget(operative_, 1);

  connect(pause_, &QPushButton::clicked, this, &RunPage::toggle_pause);
  connect(restart_, &QPushButton::clicked, this, &RunPage::restart_requested);
  connect(end_, &QPushButton::clicked, this, &RunPage::end_requested);
  timer_.setInterval(kTickMs);
  connect(&timer_, &QTimer::timeout, this, &RunPage::tick);
}

Status RunPage::start(const sim::Scene& scene, const std::array<hardware::DeviceSpec, 2>& devices,
                      const LiveSessionOptions& options, const QString& who) {
  who_->setText(who);
  session().set_options(options);
  const Status started = operative_->start(scene, devices);
  ended_signalled_ = !started.ok();
  rate_hz_ = 1000.0;  // RuntimeSettings' haptic rate, which the window does not change
  pause_->setEnabled(started.ok() && !options.fast);
  // The keys go to whichever hand is driven from the keyboard; the right one first.
  if (session().keyboard_driven(1)) {
    operative_->set_active_tool(1);
  } else if (session().keyboard_driven(0)) {
    operative_->set_active_tool(0);
  }
  operative_->setFocus();
  timer_.start();
  tick();
  return started;
}

void RunPage::toggle_pause() {
  LiveSession& s = session();
  if (!s.running() || s.finished()) return;
  if (s.user_paused()) {
    s.resume();
  } else {
    s.pause();
  }
  operative_->setFocus();
  tick();
}

void RunPage::tick() {
  LiveSession& s = session();
  if (!s.running()) {
    state_->setText("");
    return;
  }
  if (s.finished()) {
    if (!ended_signalled_) {
      ended_signalled_ = true;
      state_->setText("Ended");
      emit ended();
    }
    return;
  }
  const sim::HapticSnapshot& h = s.haptic();
  clock_->setText(run_clock_text(h.tick < 0 ? 0.0 : static_cast<double>(h.tick) / rate_hz_));
  QString style = "border-radius: 10px; padding: 3px 12px; font-weight: 600;";
  if (s.user_paused()) {
    state_->setText("PAUSED: no force, the clock is stopped. P or Space resumes");
    state_->setStyleSheet(style + QString("background: %1; color: #10151a;").arg(kWarning));
    pause_->setText("Resume");
  } else if (h.paused) {
    state_->setText(QString("PAUSED by the safety watchdog (%1): no force. Space resumes")
                        .arg(QString::fromStdString(
                            sim::describe(h.last_reason, h.last_model_fault, s.organ_names()))));
    state_->setStyleSheet(style + QString("background: %1; color: #10151a;").arg(kFailure));
    pause_->setText("Resume");
  } else {
    state_->setText("Running");
    state_->setStyleSheet(style + QString("background: #23402f; color: %1;").arg(kSuccess));
    pause_->setText("Pause");
  }
  const bool keys_left = s.keyboard_driven(0);
  const bool keys_right = s.keyboard_driven(1);
  if (keys_left || keys_right) {
    hand_->setText(QString("Keys move the <b>%1 hand</b>%2")
                       .arg(operative_->active_tool() == 0 ? "left" : "right",
                            keys_left && keys_right ? " (T switches)" : ""));
  } else {
    hand_->setText("");
  }
}

}  // namespace lap::app
