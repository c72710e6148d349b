#pragma once
/// \file
/// The briefing before an attempt: the patient, the task in words (its phases and what ends it
/// in failure, from the scenario's thresholds), each hand's instrument and how to work it with
/// the device chosen, and the Start button.

#include <QLabel>
#include <QPushButton>
#include <QString>
#include <QWidget>
#include <array>

#include "app/scenario_catalog.h"

class QVBoxLayout;

namespace lap::app {

class BriefingPage : public QWidget {
  Q_OBJECT

 public:
  explicit BriefingPage(QWidget* parent = nullptr);

  /// What to brief: the patient and each hand's DEV text.
  void set_briefing(const CatalogEntry& scenario, const std::array<QString, 2>& devices);

 signals:
  void start_requested();
  void back();

 private:
  QLabel* title_ = nullptr;
  QLabel* badge_ = nullptr;
  QLabel* description_ = nullptr;
  QLabel* task_ = nullptr;
  QLabel* instruments_ = nullptr;
  QLabel* controls_ = nullptr;
  QPushButton* start_ = nullptr;
};

/// How a hand's device is worked, in words (its DEV text: hardware/device_spec.h).
[[nodiscard]] QString device_in_words(const QString& dev);

}  // namespace lap::app
