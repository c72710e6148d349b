#pragma once
/// \file
/// One touchable object as every proxy sees it for one tick (the point proxy of chapter 4, the
/// segment proxy of chapter 5 and the gripper built on it): its mesh database, its pose now and
/// at the last tick (§6.4), its force law and its surface properties (chapter 6). The object
/// owns nothing: it points at data set up elsewhere, which must outlive it.

#include <Eigen/Geometry>

#include "haptics/force_law.h"

namespace lap::haptics {

class MeshDatabase;
class SegmentDatabase;
class ShadingNormals;
class HeightField;
struct FrictionModel;

/// One object as the proxy sees it for one tick.
struct HapticObject {
  const MeshDatabase* mesh = nullptr;
  Eigen::Isometry3d pose_WO = Eigen::Isometry3d::Identity();       ///< object to world, now
  Eigen::Isometry3d prev_pose_WO = Eigen::Isometry3d::Identity();  ///< at the previous tick
  bool two_sided = false;  ///< contact from either side (thin, open surfaces)
  ForceLaw law;
  /// The ray-based extension of `mesh` (chapter 5); needed by the segment proxy only.
  const SegmentDatabase* segments = nullptr;
  /// Force shading (§6.1) for the point proxy; nullptr: flat polygons.
  const ShadingNormals* shading = nullptr;
  /// Haptic texture (§6.3); nullptr: none. §6.6: shading and texture both change the shape and
  /// are not combined: with both set the texture is rendered and shading ignored
  /// (surface_problem() reports the combination at setup).
  const HeightField* texture = nullptr;
  double texture_k = 1.5;  ///< K of eq. 6-4 (1 to 2 per the thesis; smaller for sharp textures)
  /// Stick-slip friction (§6.2); nullptr: frictionless.
  const FrictionModel* friction = nullptr;
};

/// Setup-time check of an object's surface properties: empty when usable, else what is wrong
/// (§6.6: shading together with a texture; an invalid friction model).
[[nodiscard]] const char* surface_problem(const HapticObject& object);

}  // namespace lap::haptics
