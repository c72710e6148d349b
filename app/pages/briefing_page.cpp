#include "app/pages/briefing_page.h"

#include <QFileInfo>
#include <QHBoxLayout>
#include <QScrollArea>
#include <QVBoxLayout>

#include "app/pages/page_style.h"
#include "hardware/device_spec.h"

namespace lap::app {
namespace {

QString key(const QString& k) {
  return QString(
             "<span style='background:#141a20; border:1px solid #3d4a58; "
             "font-family:\"DejaVu Sans Mono\"; padding:1px 5px;'>&nbsp;%1&nbsp;</span>")
      .arg(k.toHtmlEscaped());
}

QString row(const QString& keys, const QString& what) {
  return QString(
             "<tr><td style='padding:3px 14px 3px 0; white-space:nowrap;'>%1</td>"
             "<td style='padding:3px 0;'>%2</td></tr>")
      .arg(keys, what);
}

QLabel* body_label(QWidget* parent) {
  auto* l = new QLabel(parent);
  l->setWordWrap(true);
  l->setTextFormat(Qt::RichText);
  l->setAlignment(Qt::AlignLeft | Qt::AlignTop);
  return l;
}

QFrame* panel(const QString& title, QLabel* body, QWidget* parent) {
  QFrame* card = card_frame(parent);
  auto* v = new QVBoxLayout(card);
  v->setContentsMargins(22, 18, 22, 18);
  v->setSpacing(8);
  v->addWidget(section_title(title, card));
  v->addWidget(body, 1);
  return card;
}

}  // namespace

QString device_in_words(const QString& dev) {
  const Result<hardware::DeviceSpec> parsed = hardware::parse_device_spec(dev.toStdString());
  if (!parsed.ok()) return dev.toHtmlEscaped();
  const hardware::DeviceSpec& s = parsed.value();
  const QString arg = QString::fromStdString(s.argument).toHtmlEscaped();
  QString text;
  switch (s.kind) {
    case hardware::DeviceKind::kSimulated:
      return "the keyboard, mouse or 3D mouse (no hardware)";
    case hardware::DeviceKind::kPhantom:
      text = arg.isEmpty() ? "the default PHANToM arm" : QString("the PHANToM arm '%1'").arg(arg);
      text += ": move its stylus to move the instrument";
      break;
    case hardware::DeviceKind::kScripted:
      text = QString("a scripted motion (%1): hands off, watch it")
                 .arg(QFileInfo(QString::fromStdString(s.argument)).fileName().toHtmlEscaped());
      break;
    case hardware::DeviceKind::kReplay:
      text = QString("a recorded session (%1), played back")
                 .arg(QFileInfo(QString::fromStdString(s.argument)).fileName().toHtmlEscaped());
      break;
  }
  if (s.usb_gripper) {
    text += "; the USB gripper on its end opens and closes the jaws";
    if (!s.gripper.serial.empty()) {
      text += QString(" (serial %1)").arg(QString::fromStdString(s.gripper.serial).toHtmlEscaped());
    }
    if (!s.gripper.bus_path.empty()) {
      text +=
          QString(" (at bus %1)").arg(QString::fromStdString(s.gripper.bus_path).toHtmlEscaped());
    }
  }
  return text;
}

BriefingPage::BriefingPage(QWidget* parent) : QWidget(parent) {
  auto* v = new QVBoxLayout(this);
  v->setContentsMargins(40, 28, 40, 24);
  v->setSpacing(6);
  auto* head = new QHBoxLayout;
  title_ = page_title("", this);
  head->addWidget(title_, 1);
  v->addLayout(head);
  badge_ = difficulty_badge("", this);
  v->addWidget(badge_);
  description_ = page_subtitle("", this);
  v->addWidget(description_);
  v->addSpacing(14);

  auto* columns = new QHBoxLayout;
  columns->setSpacing(18);
  task_ = body_label(this);
  task_->setObjectName("briefing_task");
  columns->addWidget(panel("Your task", task_, this), 5);
  // The instruments and the controls share one panel that fills the column: as two panels
  // stacked, the instruments' one kept its height from before its text was set and cut off the
  // right hand's line (a wrapped label's height for its width does not reach a sibling panel).
  QFrame* side = card_frame(this);
  auto* sv = new QVBoxLayout(side);
  sv->setContentsMargins(22, 18, 22, 18);
  sv->setSpacing(8);
  sv->addWidget(section_title("Your instruments", side));
  instruments_ = body_label(side);
  instruments_->setObjectName("briefing_instruments");
  sv->addWidget(instruments_);
  sv->addSpacing(16);
  sv->addWidget(section_title("Controls", side));
  controls_ = body_label(side);
  controls_->setObjectName("briefing_controls");
  sv->addWidget(controls_);
  sv->addStretch(1);
  columns->addWidget(side, 6);
  v->addLayout(columns, 1);

  v->addSpacing(12);
  auto* buttons = new QHBoxLayout;
  auto* back_button = secondary_button("Back", this);
  back_button->setObjectName("briefing_back");
  buttons->addWidget(back_button);
  buttons->addStretch(1);
  QLabel* clock_hint = hint_label("The clock starts when you press Start.", this);
  clock_hint->setWordWrap(false);
  buttons->addWidget(clock_hint);
  buttons->addSpacing(12);
  start_ = primary_button("Start", this);
  start_->setObjectName("start");
  start_->setMinimumWidth(140);
  buttons->addWidget(start_);
  v->addLayout(buttons);

  connect(start_, &QPushButton::clicked, this, &BriefingPage::start_requested);
  connect(back_button, &QPushButton::clicked, this, &BriefingPage::back);
}

void BriefingPage::set_briefing(const CatalogEntry& s, const std::array<QString, 2>& devices) {
  title_->setText(QString::fromStdString(s.name));
  const QString difficulty = QString::fromStdString(s.difficulty);
  badge_->setText(difficulty_text(difficulty));
  // The badge's colour, as the chooser's.
  QLabel* fresh = difficulty_badge(difficulty);
  badge_->setStyleSheet(fresh->styleSheet());
  delete fresh;
  description_->setText(QString::fromStdString(s.description));

  QString task;
  if (s.task) {
    const std::vector<std::string> lines = task_in_words(*s.task);
    bool in_list = false;
    for (const std::string& line : lines) {
      const QString l = QString::fromStdString(line).toHtmlEscaped();
      if (l.startsWith("- ")) {
        if (!in_list) task += "<ul style='margin:2px 0 0 -18px;'>";
        in_list = true;
        task += "<li style='margin-bottom:3px;'>" + l.mid(2) + "</li>";
      } else {
        if (in_list) task += "</ul>";
        in_list = false;
        task += "<p style='margin:0 0 8px 0;'>" + l + "</p>";
      }
    }
    if (in_list) task += "</ul>";
  } else {
    task = "This scenario has no task: explore it freely.";
  }
  task_->setText(task);

  bool keyboard = false;
  QString instruments;
  for (int side = 0; side < 2; ++side) {
    const QString& dev = devices[static_cast<size_t>(side)];
    keyboard = keyboard || dev == "simulated";
    instruments += QString(
                       "<p style='margin:0 0 6px 0;'><b>%1 hand:</b> a grasper, driven by %2."
                       "</p>")
                       .arg(side == 0 ? "Left" : "Right", device_in_words(dev));
  }
  instruments_->setText(instruments);

  QString c = "<table>";
  if (keyboard) {
    c += row(key("T"), "switch between the left and right hand (the status bar says which)");
    c += row(key("J") + " " + key("L") + " " + key("I") + " " + key("K") + " " + key("U") + " " +
                 key("O"),
             "move the hand's handle 2 mm left / right, away / towards you, up / down (the tip "
             "moves the other way: the shaft pivots in its port); " +
                 key("H") + " takes it home");
    c += row(key("[") + " " + key("]"),
             "close / open the jaws (close them on the catheter to "
             "hold it)");
    c += row(key(",") + " " + key("."),
             "turn the instrument 5° about its shaft (the jaws' plane turns with it)");
    c += row(key("Shift"), "with any of these keys: a quarter of the step, to aim finely");
    c += row(key("Ctrl") + " + drag",
             "move the instrument in the view's plane; Ctrl + wheel along the view (with Shift a "
             "quarter as far); Ctrl + middle drag sideways turns it about its shaft; Ctrl + right "
             "drag up opens the jaws, down closes them");
    c += row("3D mouse",
             "moves the active instrument in three dimensions, a twist of its cap turns it; its "
             "buttons close and open the jaws");
  }
  c += row("Laparoscope", "left drag or the arrows pivot it, right drag or " + key("W") + "/" +
                              key("S") + " slide it in and out, middle drag or " + key("A") + "/" +
                              key("D") + " turn it, the wheel or " + key("+") + "/" + key("-") +
                              " zoom; " + key("C") + " the camera assistant, " + key("R") +
                              " resets it");
  c += row(key("P") + " or " + key("Esc"),
           "pause: no force, the clock stops; " + key("Space") + " resumes");
  c += row(key("Ctrl+R"), "restart this patient; " + key("Ctrl+E") + " ends the attempt");
  c += row(key("F11"), "full screen");
  c += "</table>";
  controls_->setText(c);
  start_->setFocus();
}

}  // namespace lap::app
