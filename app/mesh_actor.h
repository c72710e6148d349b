#pragma once
/// \file
/// Turns a haptics::TriangleMesh into a VTK actor (float buffers only here, for rendering).

#include <vtkActor.h>
#include <vtkSmartPointer.h>

#include "haptics/triangle_mesh.h"

namespace lap::app {

/// A lit, smooth-shaded actor of the mesh in the given RGB colour.
[[nodiscard]] vtkSmartPointer<vtkActor> make_mesh_actor(const haptics::TriangleMesh& mesh,
                                                        const double rgb[3]);

}  // namespace lap::app
