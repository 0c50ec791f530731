/// \file compiled_mesh.h
/// RADIANCE's compiled meshes (`.rtm`, written by obj2mesh), read as RADIANCE's readmesh.c
/// lays them out: a text header (format Radiance_tmesh), the size of an object index, the
/// bounding cube and (u, v) limits, an octree (skipped: crex builds its own BVH), the
/// materials the mesh carries (RADIANCE's binary scene: a type table, then each object's
/// modifier index, name, strings and reals) and the patches of up to 256 vertices, each
/// with its local triangles and the triangles joining it to earlier patches. Positions are
/// 32-bit fractions of the cube, normals RADIANCE's 32-bit direction codes.
///
/// Also RADIANCE's octrees (`.oct`, written by oconv), which share the layout: a header
/// (format Radiance_octree), the object size, the cube, the scene files it was made from, the
/// object count, the octree (skipped) and, when it is frozen (`oconv -f`), the whole scene as
/// binary objects.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "runtime/base/vec3.h"

namespace crex::radiance {

/// One object of a binary RADIANCE scene (a mesh's materials; an octree's whole scene).
struct BinaryObject {
    std::string type, name;
    int modifier = -1;  ///< index of an earlier object, -1 for void
    std::vector<std::string> strings;
    std::vector<double> reals;
};

struct CompiledMesh {
    std::vector<BinaryObject> materials;
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  ///< per position; zero where the mesh has none
    std::vector<std::array<double, 2>> uvs;  ///< per position; (0, 0) where it has none
    bool has_normals = false, has_uvs = false;
    std::vector<std::array<uint32_t, 3>> triangles;
    std::vector<int> triangle_material;  ///< per triangle: an index into `materials`, -1 for none
};

/// Reads `path`; false with `error` (what is wrong, and the byte offset) when it is not a
/// compiled mesh crex can read or is damaged. At most `max_triangles` triangles.
bool read_compiled_mesh(const std::string& path, CompiledMesh& out, std::string& error, size_t max_triangles = size_t{1} << 26);

/// Reads the octree at `path`: its scene into `objects` when it is frozen, else the names of
/// the scene files it was made from into `files` (objects then stays empty). False with
/// `error` (what is wrong, and the byte offset) when it is not an octree or is damaged.
bool read_octree(const std::string& path, std::vector<BinaryObject>& objects, std::vector<std::string>& files, std::string& error);

}  // namespace crex::radiance
