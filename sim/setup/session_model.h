#pragma once
/// \file
/// Everything about a session that is fixed once it is set up, in one immutable object built from
/// a scene, the caller's RuntimeSettings and the two devices' names and limits: the loops' timing,
/// the two tools at their ports (thesis §7.2, §7.5), each organ's force law and surface
/// properties (chapter 6) with its surface databases at rest, and the tissue models (catheter,
/// local deformation, modal shell, grasp settings: sim/setup/tissue_model.h).
///
/// The haptic and modelling threads read it through `const` (MuJoCo's mjModel to a session's
/// mjData): no type of theirs can change it, so they share it without a lock. A Session
/// (sim/runtime/session.h) keeps only state, buffers and threads; several sessions may run from
/// one model side by side.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "haptics/haptic_object.h"
#include "haptics/mesh_database.h"
#include "haptics/segment_database.h"
#include "sim/setup/organ_surface.h"
#include "sim/setup/rigid_body_models.h"
#include "sim/setup/runtime_settings.h"
#include "sim/setup/scene.h"
#include "sim/setup/task_model.h"
#include "sim/setup/tissue_model.h"
#include "sim/setup/tool_model.h"

namespace lap::sim {

/// The loops' periods and the session's length, from RuntimeSettings.
struct SessionTiming {
  double dt_s = 0.001;          ///< haptic period
  double model_dt_s = 0.005;    ///< modelling period: a whole number of haptic periods
  int64_t ticks_per_model = 5;  ///< haptic ticks per modelling step
  int64_t max_ticks = 0;        ///< the session's length in haptic ticks
  int64_t recorded_ticks = 0;   ///< device inputs kept (space reserved at set-up)
};

class SessionModel {
 public:
  /// devices[0] left, [1] right. Diagnostics name the scenario file and the field at fault.
  static Result<std::shared_ptr<const SessionModel>> build(
      const Scene& scene, const RuntimeSettings& settings,
      const std::array<DeviceDescription, 2>& devices);

  [[nodiscard]] const RuntimeSettings& settings() const { return settings_; }
  [[nodiscard]] const SessionTiming& timing() const { return timing_; }
  [[nodiscard]] const ToolModel& tool(size_t side) const { return tools_[side]; }
  [[nodiscard]] const TissueModel& tissue() const { return *tissue_; }
  [[nodiscard]] const std::shared_ptr<const TissueModel>& tissue_ptr() const { return tissue_; }
  /// The task engine's fixed part (the scenario's task, the duct's lumen and incision).
  [[nodiscard]] const TaskModel& task() const { return task_; }

  [[nodiscard]] int32_t organ_count() const { return static_cast<int32_t>(objects_.size()); }
  /// Each organ as the proxies see it, with its force law and surface properties set and no
  /// surface yet: a session copies these and points them at its own surfaces.
  [[nodiscard]] const std::vector<haptics::HapticObject>& objects() const { return objects_; }
  /// Each organ's database, segment database and force-shading normals at rest, which a
  /// session's surfaces start as copies of (shading: null where the organ is not shaded).
  [[nodiscard]] std::vector<const haptics::MeshDatabase*> rest_databases() const;
  [[nodiscard]] std::vector<const haptics::SegmentDatabase*> rest_segment_databases() const;
  [[nodiscard]] std::vector<const haptics::ShadingNormals*> rest_shading() const;
  /// What is worth telling before the session starts (the duct's modes rebuilt, a tool whose
  /// stiffness budget at the handle is over its device's limit).
  [[nodiscard]] const std::vector<std::string>& notes() const { return notes_; }
  /// The stiffness a contact with organ i renders at the tool, tick by tick: its force law's k,
  /// or its sticking friction spring where stiffer [N/m]. What the haptic loop's stiffness
  /// budget counts per contact (sim/runtime/trocar_tool.h).
  [[nodiscard]] double contact_stiffness_n_per_m(int32_t organ) const;
  /// The stiffness the hand feels pressing organ i at the tool's tip once the tissue has given
  /// way (quasi-static, before the lever): (1 − s) k for an organ that dents locally (s the
  /// surface's share, models/local_deformation.h), k in series with the duct's own wall at its
  /// middle (its modes' static compliance there, across the wall), k for a rigid organ [N/m].
  /// docs/tissue-parameters.md derives each scenario value.
  [[nodiscard]] double felt_stiffness_n_per_m(int32_t organ) const;
  /// The duct's wall stiffness across it at the middle of its top, from its modes [N/m]; 0
  /// without a duct.
  [[nodiscard]] double duct_wall_stiffness_n_per_m() const { return duct_wall_stiffness_n_per_m_; }
  [[nodiscard]] const std::string& scenario_file() const { return scenario_file_; }
  /// The digest of the scenario's bytes as they were loaded (Scenario::digest).
  [[nodiscard]] uint64_t scenario_digest() const { return scenario_digest_; }
  /// The scenario's expert benchmarks for the training metrics, if it has them.
  [[nodiscard]] const std::optional<ProficiencySpec>& proficiency() const { return proficiency_; }
  /// The free rigid bodies (`rigid` organs with `dynamics`, §6.4); the haptic loop moves them
  /// (sim/runtime/moving_bodies.h).
  [[nodiscard]] const std::vector<RigidBodyOfOrgan>& bodies() const { return bodies_; }
  /// Each organ's name, as the scenario gives it.
  [[nodiscard]] const std::vector<std::string>& organ_names() const { return organ_names_; }

 private:
  SessionModel() = default;
  Status build_timing();
  Status build_tools(const Scene& scene, const std::array<DeviceDescription, 2>& devices);
  Status build_tissue(const Scene& scene);
  void build_surfaces(const Scene& scene);
  void note_stiffness_budget(const Scene& scene);

  RuntimeSettings settings_;
  SessionTiming timing_;
  std::string scenario_file_;
  uint64_t scenario_digest_ = 0;
  std::optional<ProficiencySpec> proficiency_;
  std::array<ToolModel, 2> tools_;
  std::shared_ptr<const TissueModel> tissue_;
  TaskModel task_;
  std::vector<std::unique_ptr<const haptics::MeshDatabase>> databases_;
  std::vector<std::unique_ptr<const haptics::SegmentDatabase>> segment_databases_;
  std::vector<OrganSurface> surfaces_;  // each organ's shading, texture, friction
  std::vector<haptics::HapticObject> objects_;
  std::vector<std::string> notes_;
  std::vector<std::string> organ_names_;
  std::vector<RigidBodyOfOrgan> bodies_;
  double duct_wall_stiffness_n_per_m_ = 0.0;
};

}  // namespace lap::sim
