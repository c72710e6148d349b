#include "app/pages/page_style.h"

#include <QApplication>
#include <QFont>
#include <QPalette>
#include <QStyle>
#include <QStyleFactory>

namespace lap::app {
namespace {

// The theme's colours: a dark slate background, raised panels a step lighter, text near white.
constexpr const char* kWindow = "#1b2128";
constexpr const char* kPanel = "#242c35";
constexpr const char* kPanelBorder = "#323c48";
constexpr const char* kText = "#e8edf2";
constexpr const char* kMuted = "#9aa7b4";

const QString& style_sheet() {
  static const QString sheet = QString(R"(
QWidget { color: %1; }
QMainWindow, QStackedWidget > QWidget { background: %2; }
QLabel[role="title"] { font-size: 24pt; font-weight: 600; }
QLabel[role="subtitle"] { font-size: 12pt; color: %3; }
QLabel[role="section"] { font-size: 13pt; font-weight: 600; }
QLabel[role="hint"] { color: %3; }
QFrame#card { background: %4; border: 1px solid %5; border-radius: 10px; }
QFrame#card[selected="true"] { border: 2px solid %6; background: #27343f; }
QFrame#card QLabel { background: transparent; }
QLabel#badge { border-radius: 9px; padding: 2px 10px; font-weight: 600; color: #10151a; }
QPushButton { background: #2f3a46; border: 1px solid #3d4a58; border-radius: 6px;
              padding: 8px 18px; min-height: 20px; }
QPushButton:hover { background: #374452; }
QPushButton:pressed { background: #2a333d; }
QPushButton:disabled { color: #6b7784; background: #262e37; }
QPushButton:checked { background: #3a4a5a; border-color: %6; }
QPushButton[role="primary"] { background: %6; border: 1px solid %6; color: #0d1418; font-weight: 600; }
QPushButton[role="primary"]:hover { background: #55b6e4; }
QPushButton[role="primary"]:disabled { background: #2d4b5c; color: #7f97a5; border-color: #2d4b5c; }
QLineEdit, QComboBox, QSpinBox { background: #141a20; border: 1px solid #3d4a58; border-radius: 5px;
              padding: 6px 8px; selection-background-color: %6; }
QLineEdit:focus, QComboBox:focus { border-color: %6; }
QListWidget, QTableWidget { background: #141a20; border: 1px solid %5; border-radius: 6px;
              alternate-background-color: #19212a; gridline-color: #2a333d; }
QListWidget::item { padding: 6px 8px; }
QListWidget::item:selected, QTableWidget::item:selected { background: #2b5d7a; color: %1; }
QHeaderView::section { background: %4; color: %3; border: none; border-bottom: 1px solid %5;
              padding: 6px 8px; font-weight: 600; }
QGroupBox { background: %4; border: 1px solid %5; border-radius: 10px; margin-top: 22px;
            padding: 14px 12px 12px 12px; font-weight: 600; }
QGroupBox::title { subcontrol-origin: margin; left: 12px; top: 2px; padding: 0 4px;
                   font-size: 12pt; }
QGroupBox QLabel, QGroupBox QCheckBox { font-weight: normal; }
QProgressBar { background: #141a20; border: 1px solid #3d4a58; border-radius: 5px; height: 14px;
               text-align: center; }
QProgressBar::chunk { background: %6; border-radius: 4px; }
QStatusBar { background: #151a20; color: %3; }
QStatusBar QLabel { color: %3; }
QMenuBar { background: #151a20; }
QMenuBar::item:selected { background: #2f3a46; }
QMenu { background: %4; border: 1px solid %5; }
QMenu::item:selected { background: #2b5d7a; }
QToolTip { background: %4; color: %1; border: 1px solid %5; }
QScrollArea { border: none; background: transparent; }
QScrollArea > QWidget > QWidget { background: transparent; }
)")
                                   .arg(kText, kWindow, kMuted, kPanel, kPanelBorder, kAccent);
  return sheet;
}

// The look is keyed on a property, so that the label's object name stays free for tests and
// accessibility.
QLabel* role_label(const QString& text, const char* role, QWidget* parent) {
  auto* l = new QLabel(text, parent);
  l->setProperty("role", role);
  l->setWordWrap(true);
  return l;
}

}  // namespace

void apply_application_style(QApplication& app) {
  app.setStyle(QStyleFactory::create("Fusion"));
  QPalette p;
  p.setColor(QPalette::Window, QColor(kWindow));
  p.setColor(QPalette::WindowText, QColor(kText));
  p.setColor(QPalette::Base, QColor("#141a20"));
  p.setColor(QPalette::AlternateBase, QColor("#19212a"));
  p.setColor(QPalette::Text, QColor(kText));
  p.setColor(QPalette::Button, QColor("#2f3a46"));
  p.setColor(QPalette::ButtonText, QColor(kText));
  p.setColor(QPalette::Highlight, QColor("#2b5d7a"));
  p.setColor(QPalette::HighlightedText, QColor(kText));
  p.setColor(QPalette::ToolTipBase, QColor(kPanel));
  p.setColor(QPalette::ToolTipText, QColor(kText));
  p.setColor(QPalette::PlaceholderText, QColor("#6b7784"));
  p.setColor(QPalette::Disabled, QPalette::Text, QColor("#6b7784"));
  p.setColor(QPalette::Disabled, QPalette::ButtonText, QColor("#6b7784"));
  app.setPalette(p);
  QFont font = app.font();
  font.setPointSizeF(10.5);
  app.setFont(font);
  app.setStyleSheet(style_sheet());
}

QLabel* page_title(const QString& text, QWidget* parent) {
  return role_label(text, "title", parent);
}

QLabel* page_subtitle(const QString& text, QWidget* parent) {
  return role_label(text, "subtitle", parent);
}

QLabel* section_title(const QString& text, QWidget* parent) {
  return role_label(text, "section", parent);
}

QLabel* hint_label(const QString& text, QWidget* parent) {
  return role_label(text, "hint", parent);
}

QPushButton* primary_button(const QString& text, QWidget* parent) {
  auto* b = new QPushButton(text, parent);
  b->setProperty("role", "primary");
  b->setDefault(true);
  b->setCursor(Qt::PointingHandCursor);
  return b;
}

QPushButton* secondary_button(const QString& text, QWidget* parent) {
  auto* b = new QPushButton(text, parent);
  b->setCursor(Qt::PointingHandCursor);
  return b;
}

QFrame* card_frame(QWidget* parent) {
  auto* f = new QFrame(parent);
  f->setObjectName("card");
  f->setProperty("selected", false);
  return f;
}

void set_card_selected(QFrame* card, bool selected) {
  card->setProperty("selected", selected);
  // A dynamic property does not restyle by itself.
  card->style()->unpolish(card);
  card->style()->polish(card);
}

QString difficulty_text(const QString& difficulty) {
  if (difficulty.isEmpty()) return "Not graded";
  return difficulty.left(1).toUpper() + difficulty.mid(1);
}

QLabel* difficulty_badge(const QString& difficulty, QWidget* parent) {
  auto* l = new QLabel(difficulty_text(difficulty), parent);
  l->setObjectName("badge");
  const char* colour = "#9aa7b4";
  if (difficulty == "introductory") colour = "#8fc6e8";
  if (difficulty == "easy") colour = kSuccess;
  if (difficulty == "moderate") colour = kWarning;
  if (difficulty == "hard") colour = kFailure;
  l->setStyleSheet(QString("background: %1;").arg(colour));
  l->setSizePolicy(QSizePolicy::Maximum, QSizePolicy::Fixed);
  return l;
}

}  // namespace lap::app
