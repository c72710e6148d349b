#pragma once
/// \file
/// The pages' common look: the application's palette and style sheet (a dark theme, as
/// operating-room displays are, with one accent colour), and the few building blocks every page
/// uses — its title and subtitle, primary and secondary buttons, a card frame, a difficulty
/// badge — so that the pages look like one product.

#include <QFrame>
#include <QLabel>
#include <QPushButton>
#include <QString>

class QApplication;
class QBoxLayout;

namespace lap::app {

/// Applies the palette, font and style sheet to the whole application.
void apply_application_style(QApplication& app);

/// A page's title (large) and its subtitle (muted), stacked.
[[nodiscard]] QLabel* page_title(const QString& text, QWidget* parent = nullptr);
[[nodiscard]] QLabel* page_subtitle(const QString& text, QWidget* parent = nullptr);
/// A section's heading inside a page.
[[nodiscard]] QLabel* section_title(const QString& text, QWidget* parent = nullptr);
/// Muted, smaller text (hints, units).
[[nodiscard]] QLabel* hint_label(const QString& text, QWidget* parent = nullptr);

/// The page's main action (accent colour) and the others.
[[nodiscard]] QPushButton* primary_button(const QString& text, QWidget* parent = nullptr);
[[nodiscard]] QPushButton* secondary_button(const QString& text, QWidget* parent = nullptr);

/// A raised panel with rounded corners; `selected` draws it outlined in the accent colour.
[[nodiscard]] QFrame* card_frame(QWidget* parent = nullptr);
void set_card_selected(QFrame* card, bool selected);

/// A small coloured pill: introductory, easy, moderate, hard, or "not graded".
[[nodiscard]] QLabel* difficulty_badge(const QString& difficulty, QWidget* parent = nullptr);
/// The difficulty as a trainee reads it ("Introductory", "Not graded").
[[nodiscard]] QString difficulty_text(const QString& difficulty);

/// The accent and the result colours (success, failure, warning), as style-sheet colours.
inline constexpr const char* kAccent = "#3ba4d8";
inline constexpr const char* kSuccess = "#3fb67b";
inline constexpr const char* kFailure = "#e0574f";
inline constexpr const char* kWarning = "#e3a93b";

}  // namespace lap::app
