#include "app/pages/result_page.h"

#include <QHBoxLayout>
#include <QHeaderView>
#include <QVBoxLayout>
#include <cmath>

#include "app/pages/page_style.h"

namespace lap::app {
namespace {

struct MetricRow {
  const char* key;
  const char* label;
  double scale;
  const char* unit;
  int decimals;
};

// The main metrics (docs/metrics.md), in the order a trainee reads them.
constexpr MetricRow kMainMetrics[] = {
    {"completion_time_s", "Completion time", 1.0, "s", 1},
    {"max_force_duct_n", "Largest force on the duct", 1.0, "N", 2},
    {"max_squeeze_duct_n", "Largest squeeze on the duct", 1.0, "N", 2},
    {"time_over_threshold_s", "Time over an injury threshold", 1.0, "s", 1},
    {"max_insertion_depth_m", "Deepest insertion", 1000.0, "mm", 1},
    {"catheter_drops", "Catheter drops", 1.0, "", 0},
    {"grasp_attempts", "Grasp attempts", 1.0, "", 0},
    {"path_length_left_m", "Path of the left instrument", 100.0, "cm", 1},
    {"path_length_right_m", "Path of the right instrument", 100.0, "cm", 1},
    {"economy_of_motion_right", "Economy of motion, right (1 is the straightest)", 1.0, "", 2},
    {"time_out_of_view_s", "Instruments out of view", 1.0, "s", 1},
};

constexpr std::pair<const char*, const char*> kPhases[] = {
    {"catheter_grasped", "Catheter grasped"},
    {"tip_at_incision", "Tip at the incision"},
    {"tip_in_lumen", "Tip in the lumen"},
    {"target_depth_reached", "Target depth reached"},
    {"held", "Held there: done"},
};

QTableWidget* table(const QStringList& headers, const char* name, QWidget* parent) {
  auto* t = new QTableWidget(0, static_cast<int>(headers.size()), parent);
  t->setObjectName(name);
  t->setHorizontalHeaderLabels(headers);
  t->verticalHeader()->hide();
  t->setEditTriggers(QAbstractItemView::NoEditTriggers);
  t->setSelectionMode(QAbstractItemView::NoSelection);
  t->setFocusPolicy(Qt::NoFocus);
  t->setShowGrid(false);
  t->setAlternatingRowColors(true);
  t->horizontalHeader()->setSectionResizeMode(0, QHeaderView::Stretch);
  for (int c = 1; c < headers.size(); ++c) {
    t->horizontalHeader()->setSectionResizeMode(c, QHeaderView::ResizeToContents);
  }
  t->horizontalHeader()->setDefaultAlignment(Qt::AlignLeft | Qt::AlignVCenter);
  t->verticalHeader()->setDefaultSectionSize(30);
  return t;
}

void add_row(QTableWidget* t, const QStringList& cells, const QColor& colour = QColor()) {
  const int r = t->rowCount();
  t->insertRow(r);
  for (int c = 0; c < cells.size(); ++c) {
    auto* item = new QTableWidgetItem(cells[c]);
    if (colour.isValid() && c == 1) item->setForeground(colour);
    t->setItem(r, c, item);
  }
}

QString number(const nlohmann::ordered_json& v, double scale, int decimals) {
  if (!v.is_number()) return "-";
  return QString::number(v.get<double>() * scale, 'f', decimals);
}

QFrame* panel(const QString& title, QWidget* body, QWidget* parent, QLabel* note = nullptr) {
  QFrame* card = card_frame(parent);
  auto* v = new QVBoxLayout(card);
  v->setContentsMargins(18, 14, 18, 16);
  v->setSpacing(8);
  v->addWidget(section_title(title, card));
  if (note != nullptr) v->addWidget(note);
  v->addWidget(body, 1);
  return card;
}

QString result_words(const QString& result) {
  if (result == "success") return "Success";
  if (result == "failure") return "Failed";
  return "Not completed";
}

QColor result_colour(const QString& result) {
  if (result == "success") return QColor(kSuccess);
  if (result == "failure") return QColor(kFailure);
  return QColor(kWarning);
}

}  // namespace

QString reason_in_words(const QString& r) {
  if (r == "catheter_dropped") return "the catheter was let go of, its tip outside the duct";
  if (r == "duct_injury") return "the duct was pushed, pulled or squeezed too hard for too long";
  if (r == "organ_injury") return "an organ was pushed too hard for too long";
  if (r == "wall_perforation") return "the catheter's tip went through the duct's wall";
  if (r == "time_limit") return "the time ran out";
  if (r == "out_of_view") return "an instrument was out of the laparoscope's view too long";
  if (r == "forbidden_contact") return "an instrument touched an organ it must not touch";
  if (r == "common_bile_duct") return "the catheter went into the common bile duct";
  QString words = r;
  return words.replace('_', ' ');
}

ResultPage::ResultPage(QWidget* parent) : QWidget(parent) {
  auto* v = new QVBoxLayout(this);
  v->setContentsMargins(40, 26, 40, 22);
  v->setSpacing(4);
  headline_ = page_title("", this);
  headline_->setObjectName("result_headline");
  v->addWidget(headline_);
  reasons_ = page_subtitle("", this);
  reasons_->setObjectName("result_reasons");
  v->addWidget(reasons_);
  v->addSpacing(14);

  // The metrics on the left, the whole column; the phases and the earlier attempts beside them.
  auto* columns = new QHBoxLayout;
  columns->setSpacing(18);
  metrics_ = table({"Metric", "You", "Experts"}, "metrics_table", this);
  columns->addWidget(panel("Main metrics", metrics_, this), 1);
  auto* right = new QVBoxLayout;
  right->setSpacing(18);
  phases_ = table({"Phase", "Reached at"}, "phases_table", this);
  phases_->setFixedHeight(36 + 5 * 30 + 4);  // the header and the five phases, no scrolling
  right->addWidget(panel("Phases", phases_, this));
  attempts_ = table({"When", "Result", "Time", "Why"}, "earlier_attempts", this);
  attempts_note_ = hint_label("", this);
  attempts_note_->setObjectName("attempts_note");
  right->addWidget(panel("Your attempts on this patient", attempts_, this, attempts_note_), 1);
  columns->addLayout(right, 1);
  v->addLayout(columns, 1);

  v->addSpacing(8);
  saved_ = hint_label("", this);
  saved_->setObjectName("result_saved");
  saved_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  v->addWidget(saved_);
  v->addSpacing(8);
  auto* buttons = new QHBoxLayout;
  auto* out = secondary_button("Sign Out", this);
  out->setObjectName("sign_out");
  buttons->addWidget(out);
  buttons->addStretch(1);
  auto* another = secondary_button("Choose Another Patient", this);
  another->setObjectName("another_patient");
  buttons->addWidget(another);
  auto* next = primary_button("Next Attempt", this);
  next->setObjectName("next_attempt");
  buttons->addWidget(next);
  v->addLayout(buttons);

  connect(out, &QPushButton::clicked, this, &ResultPage::sign_out);
  connect(another, &QPushButton::clicked, this, &ResultPage::another_patient);
  connect(next, &QPushButton::clicked, this, &ResultPage::next_attempt);
}

void ResultPage::show_result(const nlohmann::ordered_json& report, const SessionRow& attempt,
                             const std::vector<SessionRow>& attempts) {
  const nlohmann::ordered_json task = report.value("task", nlohmann::ordered_json::object());
  const nlohmann::ordered_json metrics = report.value("metrics", nlohmann::ordered_json::object());
  const QString result = QString::fromStdString(task.value("result", std::string("incomplete")));
  const char* mark = result == "success" ? "\u2713  " : result == "failure" ? "\u2717  " : "";
  headline_->setText(QString::fromUtf8(mark) + result_words(result));
  headline_->setStyleSheet(QString("color: %1;").arg(result_colour(result).name()));

  // Why, in words, each with when it happened (its event).
  QStringList why;
  if (task.contains("reasons") && task["reasons"].is_array()) {
    for (const auto& r : task["reasons"]) {
      if (!r.is_string()) continue;
      const QString reason = QString::fromStdString(r.get<std::string>());
      QString at;
      if (task.contains("events") && task["events"].is_array()) {
        for (const auto& e : task["events"]) {
          if (e.is_object() && e.value("kind", std::string()) == r.get<std::string>() &&
              e.contains("t_s") && e["t_s"].is_number()) {
            at = QString(" (at %1 s)").arg(e["t_s"].get<double>(), 0, 'f', 1);
            break;
          }
        }
      }
      why << reason_in_words(reason) + at;
    }
  }
  QString sub;
  if (result == "success") {
    sub = QString("The catheter is in the duct and was held there. Completed in %1 s.")
              .arg(number(metrics.value("completion_time_s", nlohmann::ordered_json()), 1.0, 1));
  } else if (!why.isEmpty()) {
    sub = "Why: " + why.join("; ") + ".";
    sub[5] = sub[5].toUpper();
  } else if (attempt.interrupted) {
    sub = "The attempt was interrupted before its end.";
  } else {
    sub = "The attempt ended before the task did.";
  }
  reasons_->setText(sub);

  phases_->setRowCount(0);
  const nlohmann::ordered_json phases =
      task.value("phase_times_s", nlohmann::ordered_json::object());
  for (const auto& [key, label] : kPhases) {
    const auto it = phases.find(key);
    const bool reached = it != phases.end() && it->is_number();
    add_row(phases_,
            {label, reached ? QString("%1 s").arg(it->get<double>(), 0, 'f', 1) : "not reached"},
            reached ? QColor() : QColor("#6b7784"));
  }

  metrics_->setRowCount(0);
  const nlohmann::ordered_json bench =
      report.contains("proficiency") && report["proficiency"].is_object()
          ? report["proficiency"].value("metrics", nlohmann::ordered_json::object())
          : nlohmann::ordered_json::object();
  for (const MetricRow& m : kMainMetrics) {
    const auto it = metrics.find(m.key);
    if (it == metrics.end()) continue;
    QString you = number(*it, m.scale, m.decimals);
    if (you != "-" && *m.unit != '\0') you += QString(" ") + m.unit;
    QString experts = "";
    QColor colour;
    const auto b = bench.find(m.key);
    if (b != bench.end() && b->is_object() && b->contains("limit") && (*b)["limit"].is_number()) {
      const bool higher = b->value("better", std::string("lower")) == "higher";
      experts =
          QString("%1 %2").arg(higher ? "≥" : "≤", number((*b)["limit"], m.scale, m.decimals));
      if (*m.unit != '\0') experts += QString(" ") + m.unit;
      const bool met = b->value("met", false);
      colour = met ? QColor(kSuccess) : QColor(kWarning);
    }
    add_row(metrics_, {m.label, you, experts}, colour);
  }
  if (report.contains("proficiency") && report["proficiency"].is_object()) {
    const auto& p = report["proficiency"];
    metrics_->setToolTip(
        QString("Experts: within two standard deviations of the experts' mean (%1). Met: %2 of %3.")
            .arg(QString::fromStdString(p.value("source", std::string())))
            .arg(p.value("met", 0))
            .arg(p.value("of", 0)));
  }

  // The folder on one line; how to review it (a command for instructors) as its tooltip.
  saved_->setText(attempt.recording_dir.isEmpty()
                      ? QString()
                      : QString("Saved for review in %1").arg(attempt.recording_dir));
  saved_->setToolTip(attempt.recording_dir.isEmpty()
                         ? QString()
                         : QString("laptrainer-cli report --session \"%1\" reviews it")
                               .arg(attempt.recording_dir));
  show_attempts(attempts, attempt.uuid);
}

void ResultPage::show_attempts(const std::vector<SessionRow>& attempts,
                               const QString& current_uuid) {
  attempts_->setRowCount(0);
  attempts_note_->clear();
  attempts_note_->setVisible(false);
  for (const SessionRow& a : attempts) {
    QString when = a.started_utc.toLocalTime().toString("d MMM yyyy, HH:mm");
    if (a.uuid == current_uuid) when += "  (this one)";
    QString time = "-";
    if (std::isfinite(a.completion_time_s)) {
      time = QString("%1 s").arg(a.completion_time_s, 0, 'f', 1);
    } else if (a.duration_s > 0.0) {
      time = QString("%1 s").arg(a.duration_s, 0, 'f', 1);
    }
    QStringList why;
    for (const QString& r : a.reasons) why << QString(r).replace('_', ' ');
    if (a.interrupted) why << "interrupted";
    add_row(attempts_, {when, result_words(a.result), time, why.join(", ")},
            result_colour(a.result));
    if (a.uuid == current_uuid) {
      QFont bold = attempts_->font();
      bold.setBold(true);
      for (int c = 0; c < attempts_->columnCount(); ++c) {
        attempts_->item(attempts_->rowCount() - 1, c)->setFont(bold);
      }
    }
  }
  if (attempts.empty()) {
    attempts_note_->setText("No attempts filed yet.");
    attempts_note_->setVisible(true);
  }
}

void ResultPage::show_attempts_unavailable(const QString& why) {
  attempts_->setRowCount(0);
  attempts_note_->setText(why);
  attempts_note_->setVisible(true);
}

}  // namespace lap::app
