#pragma once
/// \file
/// Device set-up: which device drives each hand's instrument — the keyboard and mouse (no
/// hardware), a PHANToM arm by its configured name, a scripted motion or a recorded session —
/// with or without the actuated USB gripper, chosen among those plugged in by serial number or
/// bus path; a live test of both (device_probe.h: position against the home position, grip,
/// buttons), read directly before any session. Gives each hand's DEV text
/// (hardware/device_spec.h), which the station remembers.

#include <QCheckBox>
#include <QComboBox>
#include <QElapsedTimer>
#include <QLabel>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QTimer>
#include <QWidget>
#include <array>
#include <filesystem>
#include <vector>

#include "app/device_probe.h"
#include "hardware/gripper_selection.h"
#include "sim/setup/scene.h"

namespace lap::app {

/// One hand's choice and its live readout (a part of DevicesPage).
class HandPanel : public QWidget {
  Q_OBJECT

 public:
  /// The device kinds, as the kind list orders them.
  enum Kind { kKeyboard = 0, kPhantom = 1, kScripted = 2, kReplay = 3 };

  HandPanel(int side, QWidget* parent = nullptr);
  /// Shows `spec` (DEV text); one that does not parse leaves the keyboard.
  void set_spec(const QString& spec);
  /// The DEV text of what is chosen now; empty with `problem` set when it is incomplete.
  [[nodiscard]] QString spec(QString* problem = nullptr) const;
  /// The grippers found on the bus, offered for this hand.
  void set_grippers(const std::vector<hardware::FoundGripper>& grippers);
  /// The live readout (or its absence: nullptr).
  void show_reading(const ProbeReading* reading, const Eigen::Vector3d& home_W);

 signals:
  void changed();

 private:
  void update_fields();

  int side_;
  QComboBox* kind_ = nullptr;
  QLabel* name_label_ = nullptr;
  QLineEdit* name_ = nullptr;
  QLabel* file_label_ = nullptr;
  QLineEdit* file_ = nullptr;
  QPushButton* browse_ = nullptr;
  QCheckBox* gripper_ = nullptr;
  QComboBox* gripper_choice_ = nullptr;
  QLabel* dev_ = nullptr;
  QLabel* position_ = nullptr;
  QProgressBar* grip_ = nullptr;
  std::array<QLabel*, 2> buttons_{};
  QLabel* status_ = nullptr;
};

class DevicesPage : public QWidget {
  Q_OBJECT

 public:
  explicit DevicesPage(QWidget* parent = nullptr);
  ~DevicesPage() override;
  DevicesPage(const DevicesPage&) = delete;
  DevicesPage& operator=(const DevicesPage&) = delete;
  DevicesPage(DevicesPage&&) = delete;
  DevicesPage& operator=(DevicesPage&&) = delete;

  /// The scene the devices are for (home positions) and its file (the expert's scripts beside
  /// it); the page keeps the pointer while shown.
  void set_scene(const sim::Scene* scene);
  /// Each hand's DEV text to start from.
  void set_specs(const std::array<QString, 2>& specs);
  void set_dominant_hand(int hand);
  [[nodiscard]] int dominant_hand() const;
  /// The hands' panels (left 0, right 1).
  [[nodiscard]] HandPanel* hand(int side) { return hands_[static_cast<size_t>(side)]; }
  /// Ends the live test (the devices closed): before a session opens them.
  void stop_test();
  [[nodiscard]] bool testing() const { return probe_.running(); }

 signals:
  /// Continue: both hands' DEV texts (checked) and the dominant hand.
  void accepted(const std::array<QString, 2>& specs, int dominant_hand);
  void back();

 protected:
  void keyPressEvent(QKeyEvent* event) override;
  void hideEvent(QHideEvent* event) override;

 private:
  void refresh_grippers();
  void toggle_test(bool on);
  void read_devices();
  void use_expert();
  void accept();
  [[nodiscard]] std::filesystem::path expert_script(int side) const;

  const sim::Scene* scene_ = nullptr;
  std::array<HandPanel*, 2> hands_{};
  QComboBox* dominant_ = nullptr;
  QLabel* grippers_found_ = nullptr;
  QLabel* problem_ = nullptr;
  QLabel* home_text_ = nullptr;
  QPushButton* test_ = nullptr;
  QPushButton* expert_ = nullptr;
  QTimer read_timer_;
  QElapsedTimer test_clock_;
  DeviceProbe probe_;
  int active_hand_ = 1;
};

}  // namespace lap::app
