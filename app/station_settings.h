#pragma once
/// \file
/// What a training station remembers between sessions (QSettings, the desktop's own place for
/// them: ~/.config/laptrainer/laptrainer.conf): who signed in last and who trained here before,
/// the patient chosen last, each hand's device, the window's geometry and whether it was full
/// screen. Every value read back is checked: a setting edited by hand or left by another version
/// that does not parse is ignored (the default used), never trusted.

#include <QByteArray>
#include <QSettings>
#include <QString>
#include <QStringList>
#include <array>

namespace lap::app {

class StationSettings {
 public:
  /// The application's settings (QCoreApplication's organisation and application names).
  StationSettings();
  /// Another store (tests: a file of their own).
  explicit StationSettings(const QString& file);

  /// The trainee who signed in last ("" before anyone has).
  [[nodiscard]] QString last_trainee() const;
  /// Remembers `trainee` as the last one and first of the recent ones.
  void remember_trainee(const QString& trainee);
  /// Trainees who signed in on this station, the most recent first (at most kRecentTrainees).
  [[nodiscard]] QStringList recent_trainees() const;
  static constexpr int kRecentTrainees = 20;

  /// The scenario file chosen last ("" before any).
  [[nodiscard]] QString last_scenario() const;
  void set_last_scenario(const QString& file);

  /// Each hand's device as DEV text (hardware/device_spec.h; 0 left, 1 right); "simulated" when
  /// none was saved or the saved one does not parse.
  [[nodiscard]] std::array<QString, 2> devices() const;
  void set_devices(const std::array<QString, 2>& devices);

  /// The hand the trainee operates with (0 left, 1 right: the dominant-hand metrics).
  [[nodiscard]] int dominant_hand() const;
  void set_dominant_hand(int hand);

  /// How the operative field is drawn: "auto", "full" or "fast" (render_quality.h); "auto"
  /// when none was saved or the saved one is not one of these.
  [[nodiscard]] QString render_quality() const;
  void set_render_quality(const QString& quality);

  [[nodiscard]] QByteArray window_geometry() const;
  void set_window_geometry(const QByteArray& geometry);
  [[nodiscard]] bool full_screen() const;
  void set_full_screen(bool on);

  /// Writes what was set to disk now (QSettings also does it on its own, later).
  void sync() { settings_.sync(); }

 private:
  mutable QSettings settings_;
};

/// A trainee's name or ID as typed, checked: trimmed, 1 to 64 characters, no control
/// characters. Empty when it is not acceptable (`why` says what was expected).
[[nodiscard]] QString checked_trainee(const QString& typed, QString* why = nullptr);

}  // namespace lap::app
