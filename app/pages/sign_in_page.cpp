#include "app/pages/sign_in_page.h"

#include <QCompleter>
#include <QHBoxLayout>
#include <QVBoxLayout>

#include "app/pages/page_style.h"
#include "app/station_settings.h"

namespace lap::app {

SignInPage::SignInPage(QWidget* parent) : QWidget(parent) {
  auto* outer = new QHBoxLayout(this);
  outer->addStretch(1);
  auto* card = card_frame(this);
  card->setMinimumWidth(520);
  card->setMaximumWidth(560);
  outer->addWidget(card, 0, Qt::AlignVCenter);
  outer->addStretch(1);

  auto* v = new QVBoxLayout(card);
  v->setContentsMargins(36, 32, 36, 32);
  v->setSpacing(10);
  v->addWidget(page_title("Sign in", card));
  v->addWidget(page_subtitle(
      "Your attempts are kept under your name or trainee ID, on this station.", card));
  v->addSpacing(12);
  auto* label = new QLabel("Name or trainee ID", card);
  v->addWidget(label);
  field_ = new QLineEdit(card);
  field_->setObjectName("trainee");
  field_->setPlaceholderText("e.g. Dr A. Rivera or R-2041");
  field_->setMaxLength(64);
  field_->setClearButtonEnabled(true);
  label->setBuddy(field_);
  v->addWidget(field_);
  problem_ = new QLabel(card);
  problem_->setObjectName("sign_in_problem");
  problem_->setStyleSheet(QString("color: %1;").arg(kFailure));
  problem_->hide();
  v->addWidget(problem_);

  v->addSpacing(8);
  known_title_ = section_title("Trainees on this station", card);
  v->addWidget(known_title_);
  known_ = new QListWidget(card);
  known_->setObjectName("known_trainees");
  known_->setMinimumHeight(150);
  known_->setAlternatingRowColors(true);
  v->addWidget(known_, 1);

  v->addSpacing(12);
  auto* buttons = new QHBoxLayout;
  buttons->addStretch(1);
  sign_in_ = primary_button("Sign in", card);
  sign_in_->setObjectName("sign_in");
  buttons->addWidget(sign_in_);
  v->addLayout(buttons);

  connect(sign_in_, &QPushButton::clicked, this, &SignInPage::try_sign_in);
  connect(field_, &QLineEdit::returnPressed, this, &SignInPage::try_sign_in);
  connect(field_, &QLineEdit::textChanged, this, [this] { problem_->hide(); });
  connect(known_, &QListWidget::itemClicked, this,
          [this](QListWidgetItem* item) { field_->setText(item->text()); });
  connect(known_, &QListWidget::itemActivated, this, [this](QListWidgetItem* item) {
    field_->setText(item->text());
    try_sign_in();
  });
  set_known_trainees({});
}

void SignInPage::set_known_trainees(const QStringList& trainees) {
  known_->clear();
  known_->addItems(trainees);
  known_title_->setVisible(!trainees.isEmpty());
  known_->setVisible(!trainees.isEmpty());
  auto* completer = new QCompleter(trainees, field_);
  completer->setCaseSensitivity(Qt::CaseInsensitive);
  completer->setFilterMode(Qt::MatchContains);
  field_->setCompleter(completer);
}

void SignInPage::set_trainee(const QString& trainee) {
  field_->setText(trainee);
  field_->selectAll();
}

void SignInPage::focus_field() { field_->setFocus(); }

void SignInPage::try_sign_in() {
  QString why;
  const QString trainee = checked_trainee(field_->text(), &why);
  if (trainee.isEmpty()) {
    problem_->setText(why);
    problem_->show();
    field_->setFocus();
    return;
  }
  emit signed_in(trainee);
}

}  // namespace lap::app
