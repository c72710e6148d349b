#include "app/authoring/authoring_panel.h"

#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QSignalBlocker>
#include <QTextBlock>
#include <QVBoxLayout>
#include <cmath>
#include <utility>

#include "sim/authoring/scenario_editor.h"
#include "sim/setup/scenario_loader.h"

namespace lap::app {

namespace {

QDoubleSpinBox* spin_box(QWidget* parent, double max, int decimals, double step,
                         const QString& suffix) {
  auto* s = new QDoubleSpinBox(parent);
  s->setRange(0.0, max);
  s->setDecimals(decimals);
  s->setSingleStep(step);
  s->setSuffix(suffix);
  return s;
}

constexpr double kMaxStiffnessNPerM = 3000.0;

}  // namespace

AuthoringPanel::AuthoringPanel(Opener opener, SessionSource session, QWidget* parent)
    : QDockWidget("Authoring", parent), open_(std::move(opener)), session_(std::move(session)) {
  setObjectName("authoring_panel");
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);

  auto* file_row = new QHBoxLayout;
  file_label_ = new QLabel("No scenario opened", body);
  file_label_->setWordWrap(true);
  auto* open_button = new QPushButton("Open...", body);
  connect(open_button, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Open scenario", QFileInfo(file_).path(),
                                                   "Scenarios (*.yaml *.yml)");
    if (!f.isEmpty()) open(f);
  });
  file_row->addWidget(file_label_, 1);
  file_row->addWidget(open_button);
  layout->addLayout(file_row);

  layout->addWidget(new QLabel("<b>Problems</b>", body));
  problems_ = new QListWidget(body);
  problems_->setObjectName("problems");
  problems_->setWordWrap(true);
  problems_->setMaximumHeight(110);
  layout->addWidget(problems_);
  location_ = new QLabel(body);
  location_->setObjectName("location");
  layout->addWidget(location_);
  source_ = new QPlainTextEdit(body);
  source_->setReadOnly(true);
  source_->setLineWrapMode(QPlainTextEdit::NoWrap);
  source_->setFont(QFont("Monospace", 8));
  source_->setMaximumHeight(150);
  layout->addWidget(source_);
  connect(problems_, &QListWidget::currentItemChanged, this,
          [this](QListWidgetItem* item, QListWidgetItem*) {
            if (item != nullptr) show_line(item->data(Qt::UserRole).toInt());
          });

  layout->addWidget(
      new QLabel("<b>Organs</b> (feel each change with the tool on the organ)", body));
  organs_ = new QListWidget(body);
  organs_->setObjectName("organs");
  organs_->setMaximumHeight(90);
  layout->addWidget(organs_);
  connect(organs_, &QListWidget::currentRowChanged, this, &AuthoringPanel::select_organ);
  follow_touch_ = new QCheckBox("Select the organ the tools touch", body);
  follow_touch_->setChecked(true);
  layout->addWidget(follow_touch_);
  touch_timer_.setInterval(100);
  connect(&touch_timer_, &QTimer::timeout, this, &AuthoringPanel::follow_touched_organ);
  touch_timer_.start();

  auto* form = new QFormLayout;
  stiffness_ = spin_box(body, kMaxStiffnessNPerM, 1, 10.0, " N/m");
  stiffness_slider_ = new QSlider(Qt::Horizontal, body);
  stiffness_slider_->setRange(0, static_cast<int>(kMaxStiffnessNPerM));
  auto* stiffness_row = new QHBoxLayout;
  stiffness_row->addWidget(stiffness_slider_, 1);
  stiffness_row->addWidget(stiffness_);
  form->addRow("Stiffness", stiffness_row);
  damping_ = spin_box(body, 20.0, 3, 0.05, " N s/m");
  form->addRow("Damping", damping_);
  friction_static_ = spin_box(body, 2.0, 3, 0.05, "");
  form->addRow("Static friction", friction_static_);
  friction_dynamic_ = spin_box(body, 2.0, 3, 0.05, "");
  form->addRow("Dynamic friction", friction_dynamic_);
  shading_ = new QCheckBox("force shading (§6.1)", body);
  form->addRow("Shading", shading_);
  texture_mm_ = spin_box(body, 10.0, 4, 0.01, " mm");
  form->addRow("Texture height", texture_mm_);
  layout->addLayout(form);

  connect(stiffness_slider_, &QSlider::valueChanged, this,
          [this](int v) { stiffness_->setValue(v); });
  connect(stiffness_, &QDoubleSpinBox::valueChanged, this, [this](double v) {
    const QSignalBlocker block(stiffness_slider_);
    stiffness_slider_->setValue(static_cast<int>(std::lround(v)));
    widget_changed(kStiffness);
  });
  connect(damping_, &QDoubleSpinBox::valueChanged, this, [this] { widget_changed(kDamping); });
  connect(friction_static_, &QDoubleSpinBox::valueChanged, this,
          [this] { widget_changed(kFrictionStatic); });
  connect(friction_dynamic_, &QDoubleSpinBox::valueChanged, this,
          [this] { widget_changed(kFrictionDynamic); });
  connect(shading_, &QCheckBox::toggled, this, [this] { widget_changed(kShading); });
  connect(texture_mm_, &QDoubleSpinBox::valueChanged, this, [this] { widget_changed(kTexture); });

  save_button_ = new QPushButton("Save to scenario", body);
  save_button_->setToolTip(
      "Write the changed values into the scenario file; its comments and layout stay");
  connect(save_button_, &QPushButton::clicked, this, [this] { (void)save(); });
  status_ = new QLabel(body);
  status_->setWordWrap(true);
  status_->setMinimumHeight(2 * status_->fontMetrics().lineSpacing() + 4);  // two lines, wrapped
  layout->addWidget(save_button_);
  layout->addWidget(status_);
  layout->addStretch(1);
  setWidget(body);

  reload_timer_.setSingleShot(true);
  reload_timer_.setInterval(150);
  connect(&reload_timer_, &QTimer::timeout, this, &AuthoringPanel::reload);
  connect(&watcher_, &QFileSystemWatcher::fileChanged, this, &AuthoringPanel::file_changed);
  connect(&watcher_, &QFileSystemWatcher::directoryChanged, this, &AuthoringPanel::file_changed);
  retry_timer_.setInterval(20);
  connect(&retry_timer_, &QTimer::timeout, this, [this] {
    std::vector<int> again;
    std::swap(again, pending_);
    for (const int o : again) post(o);
    if (pending_.empty()) retry_timer_.stop();
  });
  select_organ(-1);
}

void AuthoringPanel::follow_touched_organ() {
  if (!follow_touch_->isChecked() || tunings_.empty()) return;
  sim::Session* session = session_ ? session_() : nullptr;
  if (session == nullptr) return;
  const int touched = session->touched_organ();
  if (touched >= 0 && touched < organs_->count() && touched != organ_) {
    organs_->setCurrentRow(touched);
  }
}

void AuthoringPanel::open(const QString& file) {
  file_ = QFileInfo(file).absoluteFilePath();
  file_label_->setText(file_);
  watch();
  reload();
}

void AuthoringPanel::watch() {
  if (!watcher_.files().isEmpty()) watcher_.removePaths(watcher_.files());
  if (!watcher_.directories().isEmpty()) watcher_.removePaths(watcher_.directories());
  // The folder too: an editor that saves by writing a new file and renaming it over the old one
  // ends the file's watch, and the folder's change brings it back.
  watcher_.addPath(QFileInfo(file_).path());
  if (QFileInfo::exists(file_)) watcher_.addPath(file_);
}

void AuthoringPanel::file_changed() {
  if (!watcher_.files().contains(file_) && QFileInfo::exists(file_)) watcher_.addPath(file_);
  reload_timer_.start();
}

void AuthoringPanel::reload() {
  if (file_.isEmpty()) return;
  QFile f(file_);
  source_->setPlainText(f.open(QIODevice::ReadOnly) ? QString::fromUtf8(f.readAll()) : QString());
  tunings_.clear();
  organ_ = -1;
  {
    const QSignalBlocker block(organs_);
    organs_->clear();
  }
  Status opened = open_ ? open_(file_) : Status{};
  sim::ScenarioLoadResult scenario = sim::load_scenario(file_.toStdString());
  if (opened.ok() && !scenario.ok()) opened = scenario.diagnostics();
  if (!opened.ok()) {
    show_problems(opened.diagnostics());
    select_organ(-1);
    status_->setText("Not loaded: fix the problems above; the file reloads when it changes.");
    emit reloaded(false);
    return;
  }
  show_problems({});
  scenario_ = std::move(scenario).value();
  for (const sim::OrganSpec& o : scenario_.organs) {
    OrganTuning t;
    t.parameters.stiffness_n_per_m = o.material.stiffness_n_per_m;
    t.parameters.damping_n_s_per_m = o.material.damping_n_s_per_m;
    t.parameters.friction_static = o.material.friction_static;
    t.parameters.friction_dynamic = o.material.friction_dynamic;
    t.parameters.shading = o.material.shading.enabled;
    t.parameters.texture_scale = 1.0;
    t.texture_amplitude_m = o.material.texture.amplitude_m;
    tunings_.push_back(t);
    organs_->addItem(QString::fromStdString(o.name));
  }
  status_->setText(QString("Loaded %1 organs.").arg(scenario_.organs.size()));
  organs_->setCurrentRow(tunings_.empty() ? -1 : 0);
  emit reloaded(true);
}

void AuthoringPanel::show_problems(const std::vector<Diagnostic>& problems) {
  problems_->clear();
  for (const Diagnostic& d : problems) {
    auto* item = new QListWidgetItem(QString::fromStdString(d.to_string()), problems_);
    item->setData(Qt::UserRole, d.line);
    item->setToolTip(item->text());
  }
  location_->setText(problems.empty() ? "No problems." : "Click a problem to see its line.");
  source_->setExtraSelections({});
}

void AuthoringPanel::show_line(int line) {
  location_->setText(QString("%1:%2").arg(file_).arg(line));
  if (line <= 0) return;
  const QTextBlock block = source_->document()->findBlockByNumber(line - 1);
  if (!block.isValid()) return;
  QTextCursor cursor(block);
  source_->setTextCursor(cursor);
  source_->centerCursor();
  QTextEdit::ExtraSelection mark;
  mark.cursor = cursor;
  mark.format.setBackground(QColor(255, 220, 120));
  mark.format.setProperty(QTextFormat::FullWidthSelection, true);
  source_->setExtraSelections({mark});
}

void AuthoringPanel::select_organ(int organ) {
  organ_ = organ >= 0 && organ < static_cast<int>(tunings_.size()) ? organ : -1;
  const bool have = organ_ >= 0;
  for (QWidget* w :
       std::initializer_list<QWidget*>{stiffness_, stiffness_slider_, damping_, friction_static_,
                                       friction_dynamic_, shading_, texture_mm_, save_button_}) {
    w->setEnabled(have);
  }
  if (!have) return;
  updating_ = true;
  const sim::SurfaceParameters& p = tunings_[static_cast<size_t>(organ_)].parameters;
  const sim::MaterialSpec& m = scenario_.organs[static_cast<size_t>(organ_)].material;
  stiffness_->setValue(p.stiffness_n_per_m);
  damping_->setValue(p.damping_n_s_per_m);
  friction_static_->setValue(p.friction_static);
  friction_dynamic_->setValue(p.friction_dynamic);
  shading_->setChecked(p.shading);
  const bool textured = m.texture.kind != sim::TextureSpec::Kind::kNone;
  texture_mm_->setEnabled(textured);
  texture_mm_->setToolTip(textured ? "The texture's height (its amplitude_m)"
                                   : "The organ has no texture: add one in the scenario");
  texture_mm_->setValue(textured ? tunings_[static_cast<size_t>(organ_)].texture_amplitude_m * 1e3
                                 : 0.0);
  sim::Session* session = session_ ? session_() : nullptr;
  const bool can_shade =
      session != nullptr && organ_ < session->organ_count() && session->surface_can_shade(organ_);
  shading_->setEnabled(can_shade || p.shading);
  shading_->setToolTip(can_shade ? "Switch force shading on and off"
                                 : "No shading normals in this session: set shading: enabled: "
                                   "true in the scenario and reload");
  updating_ = false;
}

void AuthoringPanel::widget_changed(Field field) {
  if (updating_ || organ_ < 0) return;
  OrganTuning& t = tunings_[static_cast<size_t>(organ_)];
  const sim::MaterialSpec& m = scenario_.organs[static_cast<size_t>(organ_)].material;
  t.parameters.stiffness_n_per_m = stiffness_->value();
  t.parameters.damping_n_s_per_m = damping_->value();
  t.parameters.friction_static = friction_static_->value();
  t.parameters.friction_dynamic = friction_dynamic_->value();
  t.parameters.shading = shading_->isChecked();
  if (m.texture.amplitude_m > 0.0) {
    t.texture_amplitude_m = texture_mm_->value() / 1e3;
    t.parameters.texture_scale = t.texture_amplitude_m / m.texture.amplitude_m;
  }
  t.changed |= field;
  status_->setText(
      QString("%1: changed, not saved.")
          .arg(QString::fromStdString(scenario_.organs[static_cast<size_t>(organ_)].name)));
  post(organ_);
}

void AuthoringPanel::post(int organ) {
  sim::Session* session = session_ ? session_() : nullptr;
  if (session == nullptr || organ >= session->organ_count()) return;
  if (!session->tune_surface(organ, tunings_[static_cast<size_t>(organ)].parameters)) {
    pending_.push_back(organ);
    retry_timer_.start();
  }
}

Status AuthoringPanel::save() {
  std::vector<sim::MaterialEdit> edits;
  for (size_t o = 0; o < tunings_.size(); ++o) {
    const OrganTuning& t = tunings_[o];
    const sim::OrganSpec& spec = scenario_.organs[o];
    const sim::SurfaceParameters& p = t.parameters;
    auto add = [&](Field f, const char* field, std::variant<double, bool> v) {
      if ((t.changed & f) != 0) edits.push_back({spec.name, field, v});
    };
    add(kStiffness, "stiffness_n_per_m", p.stiffness_n_per_m);
    add(kDamping, "damping_n_s_per_m", p.damping_n_s_per_m);
    add(kFrictionStatic, "friction_static", p.friction_static);
    add(kFrictionDynamic, "friction_dynamic", p.friction_dynamic);
    add(kShading, "shading.enabled", p.shading);
    add(kTexture, "texture.amplitude_m", t.texture_amplitude_m);
  }
  if (edits.empty()) {
    status_->setText("Nothing changed: nothing to save.");
    return {};
  }
  const Status saved = sim::save_scenario_materials(file_.toStdString(), edits);
  if (!saved.ok()) {
    show_problems(saved.diagnostics());
    status_->setText("Not saved: see the problems above.");
    return saved;
  }
  for (OrganTuning& t : tunings_) t.changed = 0;
  status_->setText(QString("Saved %1 value(s) to %2.").arg(edits.size()).arg(file_));
  return {};
}

}  // namespace lap::app
