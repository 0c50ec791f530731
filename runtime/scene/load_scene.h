/// \file load_scene.h
/// Loading scenes: `builtin:NAME`, native JSON (`.json`), RADIANCE (`.rad`), Wavefront OBJ
/// (`.obj` with its `.mtl`) and glTF 2.0 (`.gltf`, `.glb`). Errors are diagnostics with file, line, column and field (codes
/// E3xx/W3xx); a scene is returned only when there were no errors.
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "base/source.h"
#include "runtime/scene/scene.h"

namespace crex {

/// Keeps the source texts that diagnostics point into alive as long as the caller needs them.
struct SceneSources {
    std::vector<std::unique_ptr<SourceFile>> files;
    const SourceFile& add(std::string name, std::string text);
};

/// Why a scene could not be read at all (missing file, unknown extension): an I/O problem,
/// reported apart from diagnostics about the content.
struct SceneLoadFailure {
    std::string message;
};

/// Loads `spec` (a path or builtin:NAME). Returns nullopt on failure: either `failure` is set
/// (I/O) or `sink` has errors (content).
std::optional<Scene> load_scene(const std::string& spec, SceneSources& sources, DiagnosticSink& sink,
                                SceneLoadFailure& failure);

/// The loaders, on text already read. `base_dir` resolves relative paths (OBJ files).
std::optional<Scene> load_scene_json(const SourceFile& file, const std::string& base_dir, SceneSources& sources,
                                     DiagnosticSink& sink);
/// How a RADIANCE scene finds the files it names.
struct RadianceOptions {
    /// Searched after the naming file's own directory for files named without a directory
    /// (RADIANCE's RAYPATH; load_scene takes it from that environment variable).
    std::vector<std::string> library_dirs;
};
/// A RADIANCE scene (docs/scene-format.md): files its commands read are kept in `sources`.
/// `view_file` (optional): a RADIANCE view file for the camera.
std::optional<Scene> import_radiance(const SourceFile& file, const SourceFile* view_file, SceneSources& sources,
                                     const RadianceOptions& options, DiagnosticSink& sink);
std::optional<Scene> import_radiance(const SourceFile& file, SceneSources& sources, DiagnosticSink& sink);
/// A RADIANCE project file (`.rif`): its materials, scene and illum files, and its first view.
std::optional<Scene> import_radiance_project(const SourceFile& rif, SceneSources& sources, const RadianceOptions& options,
                                             DiagnosticSink& sink);
std::optional<Scene> import_obj(const std::string& path, DiagnosticSink& sink, SceneSources& sources);
std::optional<Scene> import_gltf(const std::string& path, DiagnosticSink& sink, SceneSources& sources);

/// `--camera NAME|INDEX`: makes the scene's named camera `spec` (a name, or an index from 0
/// in the order of Scene::cameras) its camera. Returns "" or why it cannot.
std::string select_camera(Scene& scene, const std::string& spec);

/// Built-in scenes: "cornell" (the default), "cornell_diffuse".
std::optional<Scene> builtin_scene(const std::string& name);
std::vector<std::string> builtin_scene_names();

/// The native JSON form of a scene (what load_scene_json reads back to an equal scene).
nlohmann::json scene_to_json(const Scene& scene);
/// The same, as text for people: objects indented, arrays of numbers on one line.
std::string scene_json_text(const Scene& scene);
/// What the scene is, wherever its files lie: its JSON text with every texture file named by
/// a hash of its bytes and its file name instead of its path (kept where it cannot be read).
/// The same scene in another checkout gives the same text; an edited image gives another.
std::string scene_identity_text(const Scene& scene);

/// Rays are float in coordinates centred on the scene (runtime/trace): beyond this many units
/// from that centre they lose all precision, and Embree aborted (exit 134) near 1.8e18.
inline constexpr double kMaxReach = 1e15;
/// A scene must span at least this many units: Embree intersects in float, multiplying lengths
/// together, and below it those products lose their precision. The Cornell box rendered alike
/// from 3.5e12 down to 3.5e-13 units across, 1 % darker at 3.5e-14, a third as bright at 3.5e-15.
inline constexpr double kMinSpan = 1e-12;

/// The box around every shape of a scene (lo > hi: no shapes).
struct SceneBox {
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
};
SceneBox scene_box(const Scene& scene);
/// What keeps `camera` from viewing the scene in `box` with float rays: a non-finite position,
/// direction or up, a direction that is zero or along up, or a place more than kMaxReach from
/// the box's centre; "" if nothing.
/// Every camera a run renders from is checked: the scene's, a --view's, --camera's, and
/// each frame's on a camera path.
std::string camera_problem(const Camera& camera, const SceneBox& box);

/// How many shapes and distant sources direct lighting samples (0: direct light is black);
/// with `textured_emission` false, the shapes whose emission is an image left out.
size_t sampled_light_count(const Scene& scene, bool textured_emission = true);

/// Checks that apply to every loader's result: finite camera, materials referenced by shapes
/// exist, geometry not degenerate (relative to the scene's size), at least one light (W302).
/// `locate(i)` gives the span of shape i for messages.
void validate_scene(const Scene& scene, DiagnosticSink& sink,
                    const std::function<SourceSpan(size_t shape)>& locate);

}  // namespace crex
