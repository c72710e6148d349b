#pragma once
/// \file
/// The limits a mesh file (OBJ, STL, PLY, OFF, glTF/GLB) must keep: mesh files come from
/// outside (downloads, exports, a colleague's scan), so the loader refuses, with a clear
/// message, anything that would take an unreasonable time or memory before reading it. Each
/// limit is generous: the project's real organ meshes are below 1 % of it.

#include <cstdint>

namespace lap::sim {

/// Largest mesh file [bytes]: a 10 M-triangle binary STL is 500 MB; the real organ scans are a
/// few MB.
inline constexpr uint64_t kMaxMeshFileBytes = 512ULL * 1024 * 1024;
/// Most vertices and triangles in one mesh: a haptic organ surface needs 10^4–10^5 triangles;
/// 10 M is already far beyond what the proxies' databases are built for.
inline constexpr int64_t kMaxMeshVertices = 10'000'000;
inline constexpr int64_t kMaxMeshTriangles = 10'000'000;

/// glTF: most buffers and images one file may name (real exports have a handful).
inline constexpr int64_t kMaxGltfBuffers = 1024;
inline constexpr int64_t kMaxGltfImages = 1024;
/// glTF: largest buffer, external or embedded [bytes] (the file size limit, for the same reason).
inline constexpr uint64_t kMaxGltfBufferBytes = kMaxMeshFileBytes;
/// glTF: longest `data:` URI [characters]: 64 MiB of base64 is 48 MiB of data; larger data
/// belongs in a .bin file beside the .gltf (or in a .glb).
inline constexpr uint64_t kMaxGltfDataUriChars = 64ULL * 1024 * 1024;

}  // namespace lap::sim
