#pragma once
/// \file
/// The instruments' 3D shapes (thesis §7.6, Figure 7-14: "the tool-body and two grippers … that
/// rotate about a hinge point"), built once per tool as plain meshes in the tool's own frames;
/// instrument_actors places them each frame. Geometry only (Eigen): no VTK here.
///
/// Frames. The body's frame has its origin at the hinge and +y along the shaft towards the
/// handle. A jaw's frame has its origin at the hinge, the jaw along −y to its tip and its back
/// (the outside, away from the other jaw) towards +x; z = x × y is the hinge pin's axis. The
/// flat gripping face lies in the plane x = 0, so two closed jaws (each a half of the shaft's
/// section) make up the shaft's round section.

#include <string>

#include "haptics/triangle_mesh.h"

namespace lap::app {

/// The instrument kinds a scenario's tool may name (ToolSpec::kind).
enum class InstrumentKind { kGrasper, kDissector, kClipApplier, kScissors, kProbe };
/// "grasper", "dissector", "clip-applier", "scissors", "probe" or "ray-probe" (both drawn as a
/// probe: a rod with a rounded tip, no jaws); anything else is a grasper.
[[nodiscard]] InstrumentKind instrument_kind(const std::string& name);

/// The metal tip (the clevis holding the hinge pin) is this long from the hinge up the shaft
/// [m] (estimate: a 5 mm instrument's tip assembly).
constexpr double kClevisLengthM = 0.012;

/// The insulated shaft: a cylinder of `radius_m` from the clevis to `length_m` up +y, with
/// outward normals.
/// A probe's rod starts at its tip instead (`from_m` 0).
[[nodiscard]] haptics::TriangleMesh make_shaft(double radius_m, double length_m,
                                               double from_m = kClevisLengthM);
/// The clevis: a steel cylinder of the shaft's radius from just past the hinge (covering the
/// jaws' roots) to kClevisLengthM, closed at its front.
[[nodiscard]] haptics::TriangleMesh make_clevis(double radius_m);
/// A probe's rounded tip: a sphere of `radius_m` about the origin (the probe's tip, where its
/// proxy holds it), outward normals.
[[nodiscard]] haptics::TriangleMesh make_probe_tip(double radius_m);
/// One jaw of `kind`, `length_m` from the hinge to its tip, in the jaw's frame; `side` +1 or −1
/// for jaw 0 or jaw 1 (a curved jaw curves the same way in the world for both, so its curve's
/// sign in the jaw's frame follows the side). Within the shaft's radius across, at most
/// `radius_m` from the jaw's line.
[[nodiscard]] haptics::TriangleMesh make_jaw(InstrumentKind kind, double length_m, double radius_m,
                                             int side);

}  // namespace lap::app
