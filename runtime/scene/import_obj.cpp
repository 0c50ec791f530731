// Wavefront OBJ (+ MTL) -> Scene, through Debian's tinyobjloader (double precision build).
// One mesh shape per (OBJ object, material). MTL parameters map onto our materials:
//   Ke > 0                          -> light (radiance Ke)
//   d < 1 or illum 4/6/7/9          -> glass (transmission Kd or Tf, ior Ni)
//   illum 3/5 with black Kd         -> mirror (Ks)
//   otherwise                       -> plastic: Kd, specularity from Ks, roughness from Ns
// A standalone OBJ gets a camera framing its bounds from +z.
#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "base/input_file.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/obj_checks.h"
#include "runtime/scene/shapes.h"

namespace crex {
namespace {

Material convert_material(const tinyobj::material_t& m, const std::string& name) {
    Material out;
    out.name = name;
    Vec3 kd{m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    Vec3 ks{m.specular[0], m.specular[1], m.specular[2]};
    Vec3 ke{m.emission[0], m.emission[1], m.emission[2]};
    auto clamp01 = [](Vec3 v) { return vmin(vmax(v, Vec3{0, 0, 0}), Vec3{1, 1, 1}); };
    if (max_component(ke) > 0) {
        out.type = MaterialType::kLight;
        out.color = vmax(ke, Vec3{0, 0, 0});
    } else if (m.dissolve < 1 || m.illum == 4 || m.illum == 6 || m.illum == 7 || m.illum == 9) {
        out.type = MaterialType::kGlass;
        Vec3 tf{m.transmittance[0], m.transmittance[1], m.transmittance[2]};
        out.color = clamp01(max_component(tf) > 0 ? tf : Vec3{1, 1, 1});
        out.ior = m.ior > 0 ? m.ior : 1.5;
    } else if ((m.illum == 3 || m.illum == 5) && max_component(kd) <= 0) {
        out.type = MaterialType::kMirror;
        out.color = clamp01(ks);
    } else {
        out.type = MaterialType::kPlastic;
        double d = max_component(kd), s = max_component(ks);
        out.specularity = d + s > 0 ? std::clamp(s / (d + s), 0.0, 1.0) : 0;
        out.color = clamp01(out.specularity < 1 ? kd / (1 - out.specularity) : kd);
        // Phong exponent -> roughness (the usual sqrt(2 / (Ns + 2)) mapping).
        out.roughness = out.specularity > 0 ? std::clamp(std::sqrt(2.0 / (std::max<double>(m.shininess, 0) + 2)), 0.0, 1.0) : 0;
    }
    return out;
}

// Span of the n-th (0-based) line of `file` starting with `prefix`, for locating bad vertices.
SourceSpan nth_line(const SourceFile& file, const std::string& prefix, size_t n) {
    for (uint32_t line = 1; line <= file.line_count(); ++line) {
        std::string_view t = file.line_text(line);
        if (t.rfind(prefix, 0) == 0 && n-- == 0) {
            uint32_t b = file.line_start(line);
            return {&file, b, b + static_cast<uint32_t>(t.size())};
        }
    }
    return {&file, 0, 0};
}

}  // namespace

std::optional<Scene> import_obj(const std::string& path, DiagnosticSink& sink, SceneSources& sources) {
    std::string error;
    auto text = read_input_file(path, error, kMaxDataInputBytes);  // a regular file, bounded
    const SourceFile& file = sources.add(path, text ? std::move(*text) : std::string());
    if (!text) {
        sink.report("E308", {&file, 0, 0}, error);
        return std::nullopt;
    }
    // Its text and its MTL files' values first (obj_checks.h): tinyobjloader reads them silently.
    const size_t errors_first = sink.error_count();
    check_obj_text(file, sink);
    for (const auto& lib : material_libraries(file, std::filesystem::path(path).parent_path().string())) {
        std::error_code ec;
        if (!std::filesystem::exists(lib.path, ec)) continue;  // tinyobjloader warns (W301)
        auto mtl = read_input_file(lib.path, error, kMaxDataInputBytes);
        if (!mtl) {
            sink.report("E308", lib.named_at, error);
            continue;
        }
        check_mtl_text(sources.add(lib.path, std::move(*mtl)), sink);
    }
    if (sink.error_count() != errors_first) return std::nullopt;
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = std::filesystem::path(path).parent_path().string();
    tinyobj::ObjReader reader;
    const bool ok = reader.ParseFromFile(path, config);
    report_obj_messages(reader.Warning(), file, "W301", sink);
    if (!ok) {
        if (reader.Error().find_first_not_of(" \n") == std::string::npos)
            sink.report("E308", {&file, 0, 0}, fmt::format("cannot read OBJ '{}': malformed file", path));
        report_obj_messages(reader.Error(), file, "E308", sink);
        return std::nullopt;
    }
    const auto& attrib = reader.GetAttrib();
    size_t errors_before = sink.error_count();
    std::vector<Vec3> positions;
    for (size_t i = 0; i + 2 < attrib.vertices.size(); i += 3) {
        Vec3 v{attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]};
        if (!is_finite(v)) sink.report("E303", nth_line(file, "v ", i / 3), fmt::format("vertex {} has a non-finite coordinate", i / 3 + 1));
        positions.push_back(v);
    }
    if (sink.error_count() != errors_before) return std::nullopt;

    Scene scene;
    scene.source = path;
    std::string stem = std::filesystem::path(path).stem().string();
    std::vector<std::string> material_names;
    for (const auto& m : reader.GetMaterials()) {
        std::string name = stem + "/" + m.name;
        material_names.push_back(name);
        scene.materials.push_back(convert_material(m, name));
    }
    std::string fallback = stem + "/default";
    bool fallback_used = false;

    for (const auto& shape : reader.GetShapes()) {
        std::map<int, Shape> by_material;  // material id -> mesh
        std::map<int, std::map<int, uint32_t>> remap;
        size_t offset = 0;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            size_t n = shape.mesh.num_face_vertices[f];
            int mid = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
            if (mid >= static_cast<int>(material_names.size())) mid = -1;
            Shape& mesh = by_material[mid];
            auto& ids = remap[mid];
            if (n == 3) {
                std::array<uint32_t, 3> tri{};
                bool valid = true;
                for (size_t k = 0; k < 3; ++k) {
                    int vi = shape.mesh.indices[offset + k].vertex_index;
                    if (vi < 0 || static_cast<size_t>(vi) >= positions.size()) {
                        valid = false;
                        break;
                    }
                    auto [it, fresh] = ids.try_emplace(vi, static_cast<uint32_t>(mesh.vertices.size()));
                    if (fresh) mesh.vertices.push_back(positions[static_cast<size_t>(vi)]);
                    tri[k] = it->second;
                }
                if (valid) mesh.triangles.push_back(tri);
            }
            offset += n;
        }
        for (auto& [mid, mesh] : by_material) {
            if (mesh.triangles.empty()) continue;
            mesh.type = ShapeType::kMesh;
            mesh.name = shape.name;
            mesh.material = mid >= 0 ? material_names[static_cast<size_t>(mid)] : fallback;
            fallback_used = fallback_used || mid < 0;
            scene.shapes.push_back(std::move(mesh));
        }
    }
    if (fallback_used) {
        Material m;
        m.name = fallback;
        scene.materials.push_back(m);
    }
    if (scene.shapes.empty()) {
        sink.report("E306", {&file, 0, 0}, fmt::format("OBJ '{}' has no triangles", path));
        return std::nullopt;
    }
    // Frame the bounds from +z, far enough for a 45-degree vertical field of view.
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const auto& s : scene.shapes) expand_bounds(s, lo, hi);
    Vec3 centre = (lo + hi) * 0.5;
    double radius = 0.5 * length(hi - lo);
    scene.camera.position = centre + Vec3{0, 0, radius * 2.5 + 1e-9};
    scene.camera.direction = {0, 0, -1};
    validate_scene(scene, sink, [&](size_t) { return SourceSpan{&file, 0, 0}; });
    if (sink.error_count() != errors_before) return std::nullopt;
    return scene;
}

}  // namespace crex
