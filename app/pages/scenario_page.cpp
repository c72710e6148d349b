#include "app/pages/scenario_page.h"

#include <QEvent>
#include <QHBoxLayout>
#include <QMouseEvent>
#include <QPixmap>
#include <QScrollArea>
#include <QVBoxLayout>
#include <cmath>

#include "app/pages/page_style.h"

namespace lap::app {
namespace {

constexpr int kThumbWidth = 160;
constexpr int kThumbHeight = 90;  // 16:9, as the previews are rendered
constexpr int kPreviewWidth = 576;
constexpr int kPreviewHeight = 324;

QString task_summary(const CatalogEntry& e) {
  if (!e.task) return "No task: explore the scene.";
  const sim::TaskSpec& t = *e.task;
  if (t.kind != "catheter-insertion") return "Free exploration, no time limit.";
  return QString(
             "Task: insert the catheter %1 mm into the duct and hold it there %2 s; "
             "%3 minutes at most.")
      .arg(t.insertion_depth_m * 1000.0, 0, 'g', 3)
      .arg(t.hold_s, 0, 'g', 3)
      .arg(std::round(t.time_limit_s / 60.0), 0, 'f', 0);
}

QPixmap preview_of(const CatalogEntry& e, int w, int h) {
  QPixmap pix;
  if (e.preview.empty() || !pix.load(QString::fromStdString(e.preview.string()))) return {};
  return pix.scaled(w, h, Qt::KeepAspectRatioByExpanding, Qt::SmoothTransformation)
      .copy(0, 0, w, h);
}

void set_picture(QLabel* l, const QPixmap& pix) {
  if (pix.isNull()) {
    l->setPixmap(QPixmap());
    l->setText("No preview");
    l->setStyleSheet("background: #141a20; color: #6b7784; border-radius: 6px;");
  } else {
    l->setText(QString());
    l->setStyleSheet(QString());
    l->setPixmap(pix);
  }
}

}  // namespace

ScenarioPage::ScenarioPage(QWidget* parent) : QWidget(parent) {
  auto* v = new QVBoxLayout(this);
  v->setContentsMargins(40, 28, 40, 24);
  v->setSpacing(6);
  v->addWidget(page_title("Choose a patient", this));
  subtitle_ = page_subtitle("", this);
  v->addWidget(subtitle_);
  v->addSpacing(14);

  auto* columns = new QHBoxLayout;
  columns->setSpacing(20);
  auto* scroll = new QScrollArea(this);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  scroll->setFixedWidth(470);
  list_host_ = new QWidget(scroll);
  list_ = new QVBoxLayout(list_host_);
  list_->setContentsMargins(0, 0, 10, 0);
  list_->setSpacing(12);
  list_->addStretch(1);
  scroll->setWidget(list_host_);
  columns->addWidget(scroll);

  QFrame* detail = card_frame(this);
  detail->setObjectName("card");
  auto* d = new QVBoxLayout(detail);
  d->setContentsMargins(22, 20, 22, 20);
  d->setSpacing(10);
  preview_ = new QLabel(detail);
  preview_->setObjectName("scenario_preview");
  preview_->setFixedSize(kPreviewWidth, kPreviewHeight);
  preview_->setAlignment(Qt::AlignCenter);
  d->addWidget(preview_, 0, Qt::AlignHCenter);
  name_ = new QLabel(detail);
  name_->setObjectName("scenario_name");
  name_->setWordWrap(true);
  name_->setStyleSheet("font-size: 14pt; font-weight: 600;");
  d->addWidget(name_);
  badge_ = difficulty_badge("", detail);
  d->addWidget(badge_);
  description_ = new QLabel(detail);
  description_->setObjectName("scenario_description");
  description_->setWordWrap(true);
  description_->setStyleSheet("color: #c4ced8;");
  d->addWidget(description_);
  task_ = hint_label("", detail);
  d->addWidget(task_);
  d->addStretch(1);
  columns->addWidget(detail, 1);
  v->addLayout(columns, 1);

  v->addSpacing(10);
  auto* buttons = new QHBoxLayout;
  auto* open = secondary_button("Open Scenario File...", this);
  open->setObjectName("open_scenario_file");
  buttons->addWidget(open);
  buttons->addStretch(1);
  continue_ = primary_button("Continue", this);
  continue_->setObjectName("choose_patient");
  continue_->setEnabled(false);
  buttons->addWidget(continue_);
  v->addLayout(buttons);

  connect(open, &QPushButton::clicked, this, &ScenarioPage::open_file_requested);
  connect(continue_, &QPushButton::clicked, this, &ScenarioPage::choose);
}

void ScenarioPage::set_trainee(const QString& trainee) {
  subtitle_->setText(QString("Signed in as %1. Pick the patient to practise on: the easiest come "
                             "first.")
                         .arg(trainee.toHtmlEscaped()));
}

void ScenarioPage::set_scenarios(const std::vector<CatalogEntry>& entries,
                                 const QString& selected) {
  // The old cards go now (not later): the new ones take their places in the list.
  for (QFrame* c : cards_) delete c;
  cards_.clear();
  entries_ = entries;
  selected_ = -1;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const CatalogEntry& e = entries_[i];
    QFrame* card = card_frame(list_host_);
    card->setProperty("stem", QString::fromStdString(e.stem));
    card->setAccessibleName(QString::fromStdString(e.name));
    card->setCursor(Qt::PointingHandCursor);
    card->installEventFilter(this);
    auto* h = new QHBoxLayout(card);
    h->setContentsMargins(10, 10, 12, 10);
    h->setSpacing(14);
    auto* thumb = new QLabel(card);
    thumb->setFixedSize(kThumbWidth, kThumbHeight);
    thumb->setAlignment(Qt::AlignCenter);
    set_picture(thumb, preview_of(e, kThumbWidth, kThumbHeight));
    h->addWidget(thumb, 0, Qt::AlignTop);
    auto* text = new QVBoxLayout;
    text->setSpacing(6);
    auto* name = new QLabel(QString::fromStdString(e.name), card);
    name->setWordWrap(true);
    name->setStyleSheet("font-weight: 600;");
    text->addWidget(name);
    // Aligned, so that the badge's own width (its size policy is Maximum) does not cap the
    // column's and leave the name wrapped a word a line.
    text->addWidget(difficulty_badge(QString::fromStdString(e.difficulty), card), 0, Qt::AlignLeft);
    if (!e.problems.empty()) {
      auto* problem = new QLabel("Does not load: see the details", card);
      problem->setStyleSheet(QString("color: %1;").arg(kFailure));
      text->addWidget(problem);
    }
    text->addStretch(1);
    h->addLayout(text, 1);
    list_->insertWidget(list_->count() - 1, card);  // before the stretch
    cards_.push_back(card);
  }
  if (!select(selected) && !entries_.empty()) {
    select(QString::fromStdString(entries_[0].file.string()));
  }
}

void ScenarioPage::show_detail(const CatalogEntry& e) {
  set_picture(preview_, preview_of(e, kPreviewWidth, kPreviewHeight));
  name_->setText(QString::fromStdString(e.name));
  const QString difficulty = QString::fromStdString(e.difficulty);
  QLabel* fresh = difficulty_badge(difficulty);
  badge_->setText(fresh->text());
  badge_->setStyleSheet(fresh->styleSheet());
  delete fresh;
  if (e.problems.empty()) {
    description_->setText(QString::fromStdString(e.description));
    description_->setStyleSheet("color: #c4ced8;");
    task_->setText(task_summary(e));
  } else {
    description_->setText("This scenario does not load:\n" +
                          QString::fromStdString(e.problems).left(600));
    description_->setStyleSheet(QString("color: %1;").arg(kFailure));
    task_->clear();
  }
}

bool ScenarioPage::select(const QString& file) {
  for (size_t i = 0; i < entries_.size(); ++i) {
    if (QString::fromStdString(entries_[i].file.string()) != file) continue;
    selected_ = static_cast<int>(i);
    for (size_t k = 0; k < cards_.size(); ++k) set_card_selected(cards_[k], k == i);
    continue_->setEnabled(entries_[i].problems.empty());
    show_detail(entries_[i]);
    return true;
  }
  return false;
}

const CatalogEntry* ScenarioPage::selected() const {
  return selected_ < 0 ? nullptr : &entries_[static_cast<size_t>(selected_)];
}

bool ScenarioPage::eventFilter(QObject* watched, QEvent* event) {
  if (event->type() != QEvent::MouseButtonPress && event->type() != QEvent::MouseButtonDblClick) {
    return QWidget::eventFilter(watched, event);
  }
  for (size_t i = 0; i < cards_.size(); ++i) {
    if (cards_[i] != watched) continue;
    select(QString::fromStdString(entries_[i].file.string()));
    if (event->type() == QEvent::MouseButtonDblClick) choose();
    return true;
  }
  return QWidget::eventFilter(watched, event);
}

void ScenarioPage::choose() {
  const CatalogEntry* e = selected();
  if (e == nullptr || !e->problems.empty()) return;
  emit chosen(*e);
}

}  // namespace lap::app
