#include "app/pages/devices_page.h"

#include <QFileDialog>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QVBoxLayout>
#include <cmath>
#include <optional>

#include "app/pages/page_style.h"
#include "app/tool_keys.h"
#include "hardware/device_spec.h"
#include "hardware/libusb_transport.h"

namespace lap::app {
namespace {

constexpr double kMaxGripRad = 1.0;  // the simulated jaws' widest opening
constexpr int kReadPeriodMs = 33;    // 30 readings a second: smooth to the eye

QString gripper_suffix(const hardware::GripperSelector& g) {
  if (!g.serial.empty()) return ":" + QString::fromStdString(g.serial);
  if (!g.bus_path.empty()) return "@" + QString::fromStdString(g.bus_path);
  return {};
}

QLabel* light(const QString& text, QWidget* parent) {
  auto* l = new QLabel(text, parent);
  l->setAlignment(Qt::AlignCenter);
  l->setMinimumWidth(72);
  l->setStyleSheet("border: 1px solid #3d4a58; border-radius: 9px; padding: 2px 8px;");
  return l;
}

void set_light(QLabel* l, bool on) {
  l->setProperty("on", on);  // for whoever reads the screen without its colours (tests)
  l->setStyleSheet(
      on ? QString("border: 1px solid %1; border-radius: 9px; padding: 2px 8px; "
                   "background: %1; color: #0d1418; font-weight: 600;")
               .arg(kAccent)
         : QString("border: 1px solid #3d4a58; border-radius: 9px; padding: 2px 8px;"));
}

}  // namespace

HandPanel::HandPanel(int side, QWidget* parent) : QWidget(parent), side_(side) {
  const QString hand = side == 0 ? "left" : "right";
  auto* box = new QGroupBox(side == 0 ? "Left hand" : "Right hand", this);
  auto* outer = new QVBoxLayout(this);
  outer->setContentsMargins(0, 0, 0, 0);
  outer->addWidget(box);
  auto* form = new QFormLayout(box);
  form->setLabelAlignment(Qt::AlignRight | Qt::AlignVCenter);
  form->setHorizontalSpacing(12);
  form->setVerticalSpacing(10);

  kind_ = new QComboBox(box);
  kind_->setObjectName(hand + "_kind");
  kind_->addItem("Keyboard and mouse (no hardware)");
  kind_->addItem("PHANToM arm");
  kind_->addItem("Scripted motion (keyframe CSV)");
  kind_->addItem("Recorded session (.lapdev)");
  form->addRow("Device", kind_);

  name_ = new QLineEdit(box);
  name_->setObjectName(hand + "_phantom_name");
  name_->setPlaceholderText("the default arm");
  name_->setToolTip(
      "The arm's name as configured in Touch Setup (OpenHaptics): two arms are told apart "
      "by their names. Empty: the default arm.");
  name_label_ = new QLabel("Arm's name", box);
  form->addRow(name_label_, name_);

  auto* file_row = new QHBoxLayout;
  file_ = new QLineEdit(box);
  file_->setObjectName(hand + "_file");
  file_->setPlaceholderText("path to the file");
  browse_ = secondary_button("Browse...", box);
  browse_->setObjectName(hand + "_browse");
  file_row->addWidget(file_, 1);
  file_row->addWidget(browse_);
  file_label_ = new QLabel("File", box);
  form->addRow(file_label_, file_row);

  auto* gripper_row = new QHBoxLayout;
  gripper_ = new QCheckBox("Actuated USB gripper", box);
  gripper_->setObjectName(hand + "_gripper");
  gripper_->setToolTip(
      "The gripper on the arm's end opens and closes the jaws and renders the "
      "squeeze. With two plugged in, choose which by its serial number or by "
      "where it is plugged (bus and ports).");
  gripper_choice_ = new QComboBox(box);
  gripper_choice_->setObjectName(hand + "_gripper_choice");
  gripper_row->addWidget(gripper_);
  gripper_row->addWidget(gripper_choice_, 1);
  form->addRow("Gripper", gripper_row);

  dev_ = new QLabel(box);
  dev_->setObjectName(hand + "_dev");
  dev_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  dev_->setStyleSheet("font-family: 'DejaVu Sans Mono'; color: #9aa7b4;");
  dev_->setWordWrap(true);
  form->addRow("As DEV", dev_);

  auto* separator = new QFrame(box);
  separator->setFrameShape(QFrame::HLine);
  separator->setStyleSheet("color: #323c48;");
  form->addRow(separator);

  position_ = new QLabel("-", box);
  position_->setObjectName(hand + "_position");
  position_->setStyleSheet("font-family: 'DejaVu Sans Mono';");
  form->addRow("From home", position_);
  grip_ = new QProgressBar(box);
  grip_->setObjectName(hand + "_grip");
  grip_->setRange(0, 1000);
  grip_->setFormat("-");
  form->addRow("Jaws open", grip_);
  auto* button_row = new QHBoxLayout;
  buttons_[0] = light("Button 1", box);
  buttons_[1] = light("Button 2", box);
  buttons_[0]->setObjectName(hand + "_button1");
  buttons_[1]->setObjectName(hand + "_button2");
  button_row->addWidget(buttons_[0]);
  button_row->addWidget(buttons_[1]);
  button_row->addStretch(1);
  form->addRow("Buttons", button_row);
  status_ = new QLabel("Not being tested", box);
  status_->setObjectName(hand + "_status");
  status_->setWordWrap(true);
  form->addRow("Status", status_);

  connect(kind_, &QComboBox::currentIndexChanged, this, [this] {
    update_fields();
    emit changed();
  });
  for (QLineEdit* e : {name_, file_}) {
    connect(e, &QLineEdit::textChanged, this, [this] {
      update_fields();
      emit changed();
    });
  }
  connect(gripper_, &QCheckBox::toggled, this, [this] {
    update_fields();
    emit changed();
  });
  connect(gripper_choice_, &QComboBox::currentIndexChanged, this, [this] {
    update_fields();
    emit changed();
  });
  connect(browse_, &QPushButton::clicked, this, [this] {
    const bool script = kind_->currentIndex() == kScripted;
    const QString f = QFileDialog::getOpenFileName(
        this, script ? "Scripted motion" : "Recorded session", file_->text(),
        script ? "Keyframe scripts (*.csv)" : "Recorded device inputs (*.lapdev)");
    if (!f.isEmpty()) file_->setText(f);
  });
  set_grippers({});
  update_fields();
}

void HandPanel::set_spec(const QString& text) {
  const Result<hardware::DeviceSpec> parsed = hardware::parse_device_spec(text.toStdString());
  hardware::DeviceSpec spec;
  if (parsed.ok()) spec = parsed.value();
  const QString arg = QString::fromStdString(spec.argument);
  switch (spec.kind) {
    case hardware::DeviceKind::kSimulated:
      kind_->setCurrentIndex(kKeyboard);
      break;
    case hardware::DeviceKind::kPhantom:
      kind_->setCurrentIndex(kPhantom);
      name_->setText(arg);
      break;
    case hardware::DeviceKind::kScripted:
      kind_->setCurrentIndex(kScripted);
      file_->setText(arg);
      break;
    case hardware::DeviceKind::kReplay:
      kind_->setCurrentIndex(kReplay);
      file_->setText(arg);
      break;
  }
  gripper_->setChecked(spec.usb_gripper);
  const QString suffix = gripper_suffix(spec.gripper);
  int found = gripper_choice_->findData(suffix);
  if (found < 0) {
    // A gripper remembered but not plugged in now: offered all the same, marked so.
    gripper_choice_->addItem(QString("%1 (not found now)").arg(suffix.mid(1)), suffix);
    found = gripper_choice_->count() - 1;
  }
  gripper_choice_->setCurrentIndex(found);
  update_fields();
}

QString HandPanel::spec(QString* problem) const {
  QString text;
  switch (kind_->currentIndex()) {
    case kPhantom:
      text = name_->text().trimmed().isEmpty() ? "phantom" : "phantom:" + name_->text().trimmed();
      break;
    case kScripted:
    case kReplay:
      if (file_->text().trimmed().isEmpty()) {
        if (problem != nullptr) {
          *problem =
              QString("%1 hand: choose the file to play.").arg(side_ == 0 ? "Left" : "Right");
        }
        return {};
      }
      text =
          (kind_->currentIndex() == kScripted ? "scripted:" : "replay:") + file_->text().trimmed();
      break;
    default:
      text = "simulated";
  }
  if (kind_->currentIndex() != kKeyboard && gripper_->isChecked()) {
    text += "+gripper" + gripper_choice_->currentData().toString();
  }
  const Result<hardware::DeviceSpec> parsed = hardware::parse_device_spec(text.toStdString());
  if (!parsed.ok()) {
    if (problem != nullptr) {
      *problem = QString("%1 hand: %2")
                     .arg(side_ == 0 ? "Left" : "Right", QString::fromStdString(parsed.message()));
    }
    return {};
  }
  if (problem != nullptr) problem->clear();
  return text;
}

void HandPanel::set_grippers(const std::vector<hardware::FoundGripper>& grippers) {
  const QString current = gripper_choice_->currentData().toString();
  gripper_choice_->blockSignals(true);
  gripper_choice_->clear();
  gripper_choice_->addItem("the only one plugged in", QString());
  for (const hardware::FoundGripper& g : grippers) {
    // By serial where it can be read; by where it is plugged otherwise.
    const QString suffix = g.serial.empty() ? "@" + QString::fromStdString(g.bus_path)
                                            : ":" + QString::fromStdString(g.serial);
    gripper_choice_->addItem(
        QString("serial %1 at bus %2")
            .arg(g.serial.empty() ? "(unreadable)" : QString::fromStdString(g.serial),
                 QString::fromStdString(g.bus_path)),
        suffix);
  }
  const int keep = gripper_choice_->findData(current);
  gripper_choice_->setCurrentIndex(keep < 0 ? 0 : keep);
  gripper_choice_->blockSignals(false);
  update_fields();
}

void HandPanel::update_fields() {
  const int k = kind_->currentIndex();
  name_label_->setVisible(k == kPhantom);
  name_->setVisible(k == kPhantom);
  const bool file = k == kScripted || k == kReplay;
  file_label_->setVisible(file);
  file_->setVisible(file);
  browse_->setVisible(file);
  gripper_->setEnabled(k != kKeyboard);
  gripper_choice_->setEnabled(k != kKeyboard && gripper_->isChecked());
  QString problem;
  const QString text = spec(&problem);
  dev_->setText(text.isEmpty() ? problem : text);
}

void HandPanel::show_reading(const ProbeReading* r, const Eigen::Vector3d& home_W) {
  (void)home_W;
  if (r == nullptr) {
    position_->setText("-");
    grip_->setValue(0);
    grip_->setFormat("-");
    set_light(buttons_[0], false);
    set_light(buttons_[1], false);
    status_->setText("Not being tested");
    status_->setStyleSheet("");
    return;
  }
  if (!r->open) {
    position_->setText("-");
    status_->setText(QString::fromStdString(r->problem));
    status_->setStyleSheet(QString("color: %1;").arg(kFailure));
    return;
  }
  const Eigen::Vector3d mm = r->from_home_m * 1000.0;
  position_->setText(QString("x %1  y %2  z %3 mm  (%4 mm away)")
                         .arg(mm.x(), 6, 'f', 1)
                         .arg(mm.y(), 6, 'f', 1)
                         .arg(mm.z(), 6, 'f', 1)
                         .arg(mm.norm(), 0, 'f', 1));
  const double grip = std::clamp(r->sample.gripper_angle_rad / kMaxGripRad, 0.0, 1.0);
  grip_->setValue(static_cast<int>(std::lround(grip * 1000.0)));
  grip_->setFormat(QString("%1°").arg(r->sample.gripper_angle_rad * 180.0 / M_PI, 0, 'f', 0));
  set_light(buttons_[0], (r->sample.buttons & 1U) != 0);
  set_light(buttons_[1], (r->sample.buttons & 2U) != 0);
  switch (r->status) {
    case hardware::DeviceStatus::kOk:
      status_->setText("Working: move it and watch the figures change.");
      status_->setStyleSheet(QString("color: %1;").arg(kSuccess));
      break;
    case hardware::DeviceStatus::kFinished:
      status_->setText("Played to its end.");
      status_->setStyleSheet("");
      break;
    default:
      status_->setText(QString("Not working: %1")
                           .arg(r->problem.empty() ? QString::fromStdString(std::string(
                                                         hardware::to_string(r->status)))
                                                   : QString::fromStdString(r->problem)));
      status_->setStyleSheet(QString("color: %1;").arg(kFailure));
  }
}

DevicesPage::DevicesPage(QWidget* parent) : QWidget(parent) {
  setFocusPolicy(Qt::StrongFocus);
  auto* v = new QVBoxLayout(this);
  v->setContentsMargins(40, 28, 40, 24);
  v->setSpacing(6);
  v->addWidget(page_title("Set up the instruments", this));
  v->addWidget(page_subtitle(
      "Choose what drives each hand's instrument, then test both before you start.", this));
  v->addSpacing(10);

  auto* hands = new QHBoxLayout;
  hands->setSpacing(18);
  for (int side = 0; side < 2; ++side) {
    hands_[static_cast<size_t>(side)] = new HandPanel(side, this);
    hands->addWidget(hands_[static_cast<size_t>(side)], 1);
    connect(hands_[static_cast<size_t>(side)], &HandPanel::changed, this, [this] {
      problem_->hide();
      if (probe_.running()) toggle_test(false);
    });
  }
  v->addLayout(hands);

  auto* options = new QHBoxLayout;
  options->addWidget(new QLabel("You operate with your", this));
  dominant_ = new QComboBox(this);
  dominant_->setObjectName("dominant_hand");
  dominant_->addItem("left hand");
  dominant_->addItem("right hand");
  options->addWidget(dominant_);
  options->addSpacing(24);
  grippers_found_ = hint_label("", this);
  options->addWidget(grippers_found_, 1);
  auto* refresh = secondary_button("Look for Grippers", this);
  refresh->setObjectName("refresh_grippers");
  options->addWidget(refresh);
  v->addSpacing(8);
  v->addLayout(options);

  v->addSpacing(6);
  home_text_ = hint_label(
      "Home position: each instrument starts in view, 10 cm or more into its port, pointing at "
      "the duct, its jaws half open. Hold a PHANToM's stylus in the middle of its workspace before "
      "you start: that "
      "is where the instrument starts. While testing, the keyboard moves the keyboard-driven "
      "hands: T switches hand, J/L, I/K, U/O move it, [ and ] close and open the jaws (a quarter "
      "as far with Shift), H goes home.",
      this);
  v->addWidget(home_text_);
  problem_ = new QLabel(this);
  problem_->setObjectName("devices_problem");
  problem_->setWordWrap(true);
  problem_->setStyleSheet(QString("color: %1;").arg(kFailure));
  problem_->hide();
  v->addWidget(problem_);
  v->addStretch(1);

  auto* buttons = new QHBoxLayout;
  auto* back_button = secondary_button("Back", this);
  back_button->setObjectName("devices_back");
  buttons->addWidget(back_button);
  buttons->addStretch(1);
  expert_ = secondary_button("Watch the Expert", this);
  expert_->setObjectName("use_expert");
  expert_->setToolTip("Both hands play the expert's demonstration of this patient");
  buttons->addWidget(expert_);
  test_ = secondary_button("Test Devices", this);
  test_->setObjectName("test_devices");
  test_->setCheckable(true);
  buttons->addWidget(test_);
  auto* next = primary_button("Continue", this);
  next->setObjectName("devices_continue");
  buttons->addWidget(next);
  v->addLayout(buttons);

  read_timer_.setInterval(kReadPeriodMs);
  connect(&read_timer_, &QTimer::timeout, this, &DevicesPage::read_devices);
  connect(test_, &QPushButton::toggled, this, &DevicesPage::toggle_test);
  connect(refresh, &QPushButton::clicked, this, &DevicesPage::refresh_grippers);
  connect(expert_, &QPushButton::clicked, this, &DevicesPage::use_expert);
  connect(next, &QPushButton::clicked, this, &DevicesPage::accept);
  connect(back_button, &QPushButton::clicked, this, [this] {
    stop_test();
    emit back();
  });
  refresh_grippers();
}

DevicesPage::~DevicesPage() { probe_.stop(); }

void DevicesPage::set_scene(const sim::Scene* scene) {
  stop_test();
  scene_ = scene;
  expert_->setEnabled(!expert_script(0).empty() && !expert_script(1).empty());
}

void DevicesPage::set_specs(const std::array<QString, 2>& specs) {
  for (size_t i = 0; i < 2; ++i) hands_[i]->set_spec(specs[i]);
}

void DevicesPage::set_dominant_hand(int hand) { dominant_->setCurrentIndex(hand == 0 ? 0 : 1); }

int DevicesPage::dominant_hand() const { return dominant_->currentIndex(); }

std::filesystem::path DevicesPage::expert_script(int side) const {
  if (scene_ == nullptr) return {};
  const std::filesystem::path& file = scene_->scenario.file;
  const std::filesystem::path script = file.parent_path() / "scripts" / file.stem() /
                                       (side == 0 ? "expert_left.csv" : "expert_right.csv");
  std::error_code ec;
  return std::filesystem::is_regular_file(script, ec) ? script : std::filesystem::path();
}

void DevicesPage::use_expert() {
  for (int side = 0; side < 2; ++side) {
    const std::filesystem::path script = expert_script(side);
    if (script.empty()) return;
    hands_[static_cast<size_t>(side)]->set_spec("scripted:" +
                                                QString::fromStdString(script.string()));
  }
}

void DevicesPage::refresh_grippers() {
  const Result<std::vector<hardware::FoundGripper>> found = hardware::LibusbTransport::list();
  std::vector<hardware::FoundGripper> grippers;
  if (found.ok()) {
    grippers = found.value();
    grippers_found_->setText(
        grippers.empty() ? "No actuated gripper is plugged in."
                         : QString("%1 actuated gripper(s) plugged in.").arg(grippers.size()));
  } else {
    grippers_found_->setText(
        QString("Cannot look for grippers: %1").arg(QString::fromStdString(found.message())));
  }
  for (HandPanel* h : hands_) h->set_grippers(grippers);
}

void DevicesPage::toggle_test(bool on) {
  if (test_->isChecked() != on) {
    test_->setChecked(on);  // comes back here
    return;
  }
  if (!on) {
    read_timer_.stop();
    probe_.stop();
    for (HandPanel* h : hands_) h->show_reading(nullptr, Eigen::Vector3d::Zero());
    test_->setText("Test Devices");
    return;
  }
  std::array<hardware::DeviceSpec, 2> specs;
  for (size_t i = 0; i < 2; ++i) {
    QString problem;
    const QString text = hands_[i]->spec(&problem);
    if (text.isEmpty() || scene_ == nullptr) {
      problem_->setText(scene_ == nullptr ? "Choose a patient first." : problem);
      problem_->show();
      test_->setChecked(false);
      return;
    }
    specs[i] = hardware::parse_device_spec(text.toStdString()).value();
  }
  probe_.start(*scene_, specs);
  test_clock_.start();
  read_timer_.start();
  test_->setText("Stop Testing");
  setFocus();
  read_devices();
}

void DevicesPage::read_devices() {
  if (!probe_.running()) return;
  const std::array<ProbeReading, 2> r =
      probe_.read(static_cast<double>(test_clock_.nsecsElapsed()) * 1e-9);
  for (size_t i = 0; i < 2; ++i) hands_[i]->show_reading(&r[i], probe_.home(static_cast<int>(i)));
}

void DevicesPage::stop_test() { toggle_test(false); }

void DevicesPage::hideEvent(QHideEvent* event) {
  stop_test();
  QWidget::hideEvent(event);
}

void DevicesPage::keyPressEvent(QKeyEvent* e) {
  if (!probe_.running()) {
    QWidget::keyPressEvent(e);
    return;
  }
  switch (e->key()) {
    case Qt::Key_T:
      active_hand_ = 1 - active_hand_;
      return;
    case Qt::Key_H:
      probe_.go_home(active_hand_);
      return;
    default:
      break;
  }
  if (const std::optional<hardware::ToolKey> key =
          tool_key(e->key(), static_cast<int>(e->modifiers()))) {
    probe_.nudge(active_hand_,
                 hardware::key_nudge(*key, fine_step(static_cast<int>(e->modifiers()))));
    return;
  }
  QWidget::keyPressEvent(e);
}

void DevicesPage::accept() {
  std::array<QString, 2> specs;
  for (size_t i = 0; i < 2; ++i) {
    QString problem;
    specs[i] = hands_[i]->spec(&problem);
    if (specs[i].isEmpty()) {
      problem_->setText(problem);
      problem_->show();
      return;
    }
  }
  stop_test();
  emit accepted(specs, dominant_hand());
}

}  // namespace lap::app
