/// \file gltf_camera_path.h
/// A glTF file's camera animation as a camera path (issue 36, docs/animation.md): the world
/// transform of a camera node, moved by the file's animation of that node or of a node above
/// it, sampled at the animation's key times and at 8 steps between each two with glTF's own
/// interpolation (LINEAR with rotations slerped, STEP, CUBICSPLINE's Hermite curve), and
/// written as the JSON path format with `"timing": "keys"`, a direction and up per key and the
/// camera's vertical field of view. camera_path_file.h then reads it as any path, so a glTF
/// camera moves between those samples as every path does.
#pragma once

#include <optional>
#include <string>

#include "base/diagnostic.h"
#include "runtime/scene/load_scene.h"

namespace crex {

/// The path of camera `camera` (its name or index among the file's cameras, as `--camera`
/// takes them; "": the first) of the glTF file `path`, as the JSON path text; nullopt after
/// saying why (located in the file): no such camera, no animation moving it, an animated
/// node with a matrix (glTF forbids it), unusable accessors.
std::optional<std::string> gltf_camera_path_json(const std::string& path, const std::string& camera, SceneSources& sources,
                                                 DiagnosticSink& sink);

/// Whether `path` names a glTF file (.gltf or .glb, any case).
bool is_gltf_path(const std::string& path);

}  // namespace crex
