#pragma once
/// \file
/// The scenario chooser: the patients (scenario_catalog.h) listed easiest first, each a card
/// with a thumbnail of its preview, its name and difficulty; beside the list the chosen one in
/// full — its preview picture, description and task. The trainee picks one (click, then
/// Continue; or double-click). A scenario file elsewhere can be opened too.

#include <QFrame>
#include <QLabel>
#include <QPushButton>
#include <QString>
#include <QVBoxLayout>
#include <QWidget>
#include <vector>

#include "app/scenario_catalog.h"

namespace lap::app {

class ScenarioPage : public QWidget {
  Q_OBJECT

 public:
  explicit ScenarioPage(QWidget* parent = nullptr);

  /// Shows these scenarios (in this order) and selects `selected` (a file) if it is among them.
  void set_scenarios(const std::vector<CatalogEntry>& entries, const QString& selected);
  /// Whom the page greets.
  void set_trainee(const QString& trainee);
  /// The card of the scenario file `file` becomes the selected one (false: not listed).
  bool select(const QString& file);
  [[nodiscard]] const CatalogEntry* selected() const;

 signals:
  /// The trainee chose this scenario.
  void chosen(const lap::app::CatalogEntry& entry);
  /// The trainee asked to open a scenario file that is not listed.
  void open_file_requested();

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  void choose();
  void show_detail(const CatalogEntry& e);

  QLabel* subtitle_ = nullptr;
  QVBoxLayout* list_ = nullptr;
  QWidget* list_host_ = nullptr;
  QLabel* preview_ = nullptr;
  QLabel* name_ = nullptr;
  QLabel* badge_ = nullptr;
  QLabel* description_ = nullptr;
  QLabel* task_ = nullptr;
  QPushButton* continue_ = nullptr;
  std::vector<CatalogEntry> entries_;
  std::vector<QFrame*> cards_;
  int selected_ = -1;
};

}  // namespace lap::app
