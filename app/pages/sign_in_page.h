#pragma once
/// \file
/// Sign-in: the trainee types a name or ID (or picks one of those who trained on this station
/// before); their attempts are filed under it. The field starts with whoever signed in last.

#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QPushButton>
#include <QStringList>
#include <QWidget>

namespace lap::app {

class SignInPage : public QWidget {
  Q_OBJECT

 public:
  explicit SignInPage(QWidget* parent = nullptr);

  /// The trainees to offer (the session database's and this station's, most recent first).
  void set_known_trainees(const QStringList& trainees);
  /// Pre-fills the field.
  void set_trainee(const QString& trainee);
  /// Puts the cursor in the field (when the page is shown).
  void focus_field();

 signals:
  /// A name or ID was given and checked (station_settings.h, checked_trainee).
  void signed_in(const QString& trainee);

 private:
  void try_sign_in();

  QLineEdit* field_ = nullptr;
  QListWidget* known_ = nullptr;
  QLabel* known_title_ = nullptr;
  QLabel* problem_ = nullptr;
  QPushButton* sign_in_ = nullptr;
};

}  // namespace lap::app
