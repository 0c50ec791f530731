/// \file gltf_document.h
/// A glTF 2.0 file (.gltf with external or data-URI buffers and images, or .glb) as Debian's
/// tinygltf reads it, with what the importer needs around it:
///  - its JSON text read again with positions, so that every problem the importer finds
///    names the line and column of the construct in the file (a .glb's JSON chunk);
///  - images kept as files or encoded bytes (tinygltf decodes nothing: OpenImageIO reads them
///    when rendering);
///  - accessors read with every offset, stride and count checked against their buffers
///    (a broken file is a located error, never a read past the end).
/// Why tinygltf and not assimp: it keeps glTF's own structure (node tree, extensions and
/// extras as JSON, KHR_texture_transform per texture reference, the lights and cameras), where
/// assimp converts to its own scene model and drops or renames some of it; and its JSON
/// pointers line up with the file, so errors can be located.
#pragma once

#include <tiny_gltf.h>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "base/json_positions.h"
#include "base/source.h"
#include "runtime/scene/load_scene.h"

namespace crex::gltf {

struct Document {
    tinygltf::Model model;
    const SourceFile* file = nullptr;  ///< the JSON text (a .glb's JSON chunk) diagnostics point into
    PositionedJson json;               ///< positions of that text (empty if it is not plain JSON)
    std::string directory;             ///< where relative URIs start
    std::string name;                  ///< the file's name, for image names and messages
    /// Per glTF image: its file (external URI, resolved), or the embedded bytes' name.
    std::vector<std::string> image_files;
    std::vector<std::string> image_bytes;  ///< per glTF image: encoded bytes when embedded
    std::vector<std::string> image_mime;
    /// Per glTF image: why its embedded bytes cannot be had ("" when they can, or it has none).
    std::vector<std::string> image_problem;

    /// The span of the construct at JSON pointer `pointer` ("/meshes/2/primitives/0/mode"),
    /// or of the nearest enclosing one.
    SourceSpan at(const std::string& pointer) const;
};

/// Reads `path`; the JSON text diagnostics point into is kept in `sources`. Returns nullopt
/// after reporting why (E308: cannot read; E301: not glTF).
std::optional<Document> read_document(const std::string& path, SceneSources& sources, DiagnosticSink& sink);

/// The elements of accessor `index` as doubles, `components` per element (checked against
/// the accessor's type), normalised integers mapped to [0, 1] or [-1, 1], sparse values
/// applied. Empty with an error reported at `pointer` when the accessor is unusable.
std::vector<double> read_accessor(const Document& doc, int index, int components, const std::string& pointer, DiagnosticSink& sink);

/// A camera's name as `--camera` takes it: the camera's own name, else its node's, else
/// "camera" and its index among the scene's cameras.
std::string camera_name(const tinygltf::Camera& camera, const tinygltf::Node& node, size_t index);

/// The default scene's root nodes, or, without scenes, every node no other node has as a child.
std::vector<int> scene_roots(const tinygltf::Model& model);

/// Integer elements (indices) of accessor `index`; the same checks.
std::vector<uint32_t> read_indices(const Document& doc, int index, const std::string& pointer, DiagnosticSink& sink);

}  // namespace crex::gltf
