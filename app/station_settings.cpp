#include "app/station_settings.h"

#include "app/render_quality.h"
#include "hardware/device_spec.h"

namespace lap::app {
namespace {

constexpr int kMaxTraineeChars = 64;

}  // namespace

// Named here rather than by QCoreApplication's names, so that every program and test of the
// project reads the same station: ~/.config/laptrainer/laptrainer.conf.
StationSettings::StationSettings() : settings_(QSettings::UserScope, "laptrainer", "laptrainer") {}

StationSettings::StationSettings(const QString& file) : settings_(file, QSettings::IniFormat) {}

QString StationSettings::last_trainee() const {
  return checked_trainee(settings_.value("trainee/last").toString());
}

void StationSettings::remember_trainee(const QString& trainee) {
  const QString t = checked_trainee(trainee);
  if (t.isEmpty()) return;
  QStringList recent = recent_trainees();
  recent.removeAll(t);
  recent.prepend(t);
  while (recent.size() > kRecentTrainees) recent.removeLast();
  settings_.setValue("trainee/last", t);
  settings_.setValue("trainee/recent", recent);
}

QStringList StationSettings::recent_trainees() const {
  QStringList out;
  for (const QString& s : settings_.value("trainee/recent").toStringList()) {
    const QString t = checked_trainee(s);
    if (!t.isEmpty() && !out.contains(t)) out << t;
    if (out.size() >= kRecentTrainees) break;
  }
  return out;
}

QString StationSettings::last_scenario() const {
  return settings_.value("scenario/last").toString();
}

void StationSettings::set_last_scenario(const QString& file) {
  settings_.setValue("scenario/last", file);
}

std::array<QString, 2> StationSettings::devices() const {
  std::array<QString, 2> out{"simulated", "simulated"};
  const char* keys[2] = {"devices/left", "devices/right"};
  for (size_t i = 0; i < 2; ++i) {
    const QString v = settings_.value(keys[i]).toString();
    if (!v.isEmpty() && hardware::parse_device_spec(v.toStdString()).ok()) out[i] = v;
  }
  return out;
}

void StationSettings::set_devices(const std::array<QString, 2>& devices) {
  settings_.setValue("devices/left", devices[0]);
  settings_.setValue("devices/right", devices[1]);
}

int StationSettings::dominant_hand() const {
  bool ok = false;
  const int hand = settings_.value("trainee/dominant_hand", 1).toInt(&ok);
  return ok && (hand == 0 || hand == 1) ? hand : 1;
}

void StationSettings::set_dominant_hand(int hand) {
  settings_.setValue("trainee/dominant_hand", hand == 0 ? 0 : 1);
}

QByteArray StationSettings::window_geometry() const {
  return settings_.value("window/geometry").toByteArray();
}

void StationSettings::set_window_geometry(const QByteArray& geometry) {
  settings_.setValue("window/geometry", geometry);
}

QString StationSettings::render_quality() const {
  // Read as the command line reads it; what does not parse is auto.
  return render_quality_name(
      parse_render_quality(settings_.value("view/render_quality", "auto").toString())
          .value_or(RenderQualityChoice::kAuto));
}

void StationSettings::set_render_quality(const QString& quality) {
  settings_.setValue("view/render_quality", quality);
}

bool StationSettings::full_screen() const {
  return settings_.value("window/full_screen", false).toBool();
}

void StationSettings::set_full_screen(bool on) { settings_.setValue("window/full_screen", on); }

QString checked_trainee(const QString& typed, QString* why) {
  const QString t = typed.trimmed();
  auto refuse = [&](const QString& reason) {
    if (why != nullptr) *why = reason;
    return QString();
  };
  if (t.isEmpty()) return refuse("Type your name or trainee ID.");
  if (t.size() > kMaxTraineeChars) {
    return refuse(QString("A name or ID of at most %1 characters, please.").arg(kMaxTraineeChars));
  }
  for (const QChar c : t) {
    if (c.category() == QChar::Other_Control || c.category() == QChar::Other_Format) {
      return refuse("Letters, digits, spaces and punctuation only, please.");
    }
  }
  if (why != nullptr) why->clear();
  return t;
}

}  // namespace lap::app
