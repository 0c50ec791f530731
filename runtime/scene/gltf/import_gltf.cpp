// glTF 2.0 (.gltf, .glb) -> Scene (docs/scene-format.md, "glTF 2.0"): the default scene's
// node tree with its transforms, one mesh shape per (node, primitive), materials by the
// table of gltf_materials.h, KHR_lights_punctual point and spot lights as small spherical
// `light` emitters and directional ones as distant lights, perspective and orthographic
// cameras (the first is the camera; `--camera` chooses another), and
// tags for task maps from node names ("task3:cup", "distractor:tv") or node extras
// ({"task": 3}, {"distractor": true}), inherited by a node's children. glTF's units are
// metres and its up axis +y; crex keeps both (and says so in `crex scene-info`).
#include <fmt/format.h>

#include <algorithm>
#include <tuple>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <set>

#include "runtime/scene/gltf/gltf_document.h"
#include "runtime/scene/gltf/gltf_materials.h"
#include "runtime/scene/gltf/gltf_transform.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/material.h"
#include "runtime/scene/model_defaults.h"
#include "runtime/scene/shapes.h"

namespace crex {
namespace {

using gltf::Document;
using gltf::Mat4;
using gltf::local_transform;

// A directional light's disk: the sun's angular diameter (glTF's lights have no size).
constexpr double kSunAngleDeg = 0.53;

// A tag from a node: extras {"task": 0..3, "distractor": bool, "tag": name}, or a name
// "task3:cup" / "distractor:tv".
std::optional<Tag> node_tag(const tinygltf::Node& node) {
    std::optional<Tag> tag;
    const std::string& name = node.name;
    for (int task = 0; task <= 3; ++task)
        if (name.rfind(fmt::format("task{}:", task), 0) == 0) tag = Tag{name.substr(6), task, false};
    if (name.rfind("distractor:", 0) == 0) tag = Tag{name.substr(11), 0, true};
    const tinygltf::Value& x = node.extras;
    if (x.IsObject() && (x.Has("task") || x.Has("distractor"))) {
        if (!tag) tag = Tag{name, 0, false};
        if (x.Has("task") && x.Get("task").IsNumber()) tag->task = std::clamp(x.Get("task").GetNumberAsInt(), 0, 3);
        if (x.Has("distractor") && x.Get("distractor").IsBool()) tag->distractor = x.Get("distractor").Get<bool>();
        if (x.Has("tag") && x.Get("tag").IsString()) tag->name = x.Get("tag").Get<std::string>();
    }
    if (tag && tag->name.empty()) tag->name = "node";
    return tag;
}

// Extensions whose absence would change what the file means, which crex reads.
const std::set<std::string> kReadableRequired = {"KHR_texture_transform",        "KHR_materials_transmission",     "KHR_materials_ior",
                                                 "KHR_materials_emissive_strength", "KHR_lights_punctual",          "KHR_mesh_quantization",
                                                 "KHR_materials_pbrSpecularGlossiness", "KHR_materials_unlit"};

class GltfImporter {
public:
    GltfImporter(const Document& doc, const std::string& path, DiagnosticSink& sink) : doc_(doc), path_(path), sink_(sink) {}

    std::optional<Scene> run() {
        const size_t errors = sink_.error_count();
        const auto& m = doc_.model;
        for (size_t i = 0; i < m.extensionsRequired.size(); ++i)
            if (!kReadableRequired.count(m.extensionsRequired[i]))
                sink_.report("E307", doc_.at(fmt::format("/extensionsRequired/{}", i)),
                             fmt::format("the file requires extension {}, which crex cannot read", m.extensionsRequired[i]));
        if (sink_.error_count() != errors) return std::nullopt;
        scene_.source = path_;
        scene_.units = {1.0, {0, 1, 0}};
        const std::string stem = std::filesystem::path(path_).stem().string();
        materials_ = gltf::convert_materials(doc_, stem, scene_.images, sink_);
        scene_.materials = materials_.materials;
        used_.assign(materials_.materials.size(), false);

        visited_.assign(m.nodes.size(), false);
        for (int r : gltf::scene_roots(m)) visit(r, Mat4{}, std::nullopt, 0, "/scenes");
        if (sink_.error_count() != errors) return std::nullopt;
        add_lights();
        // Only the materials some shape uses (and the lights'): the census counts used ones anyway.
        std::vector<Material> used;
        for (size_t i = 0; i < scene_.materials.size(); ++i)
            if (i >= used_.size() || used_[i]) used.push_back(scene_.materials[i]);
        scene_.materials = std::move(used);
        if (scene_.shapes.empty()) {
            sink_.report("E306", doc_.at(""), fmt::format("glTF '{}' has no triangles in its scene", path_));
            return std::nullopt;
        }
        if (!scene_.cameras.empty()) {
            scene_.camera = scene_.cameras.front().camera;
        } else {
            frame_model(scene_);  // no camera: one framing the bounds, as for a standalone OBJ
        }
        validate_scene(scene_, sink_, [&](size_t i) { return doc_.at(i < where_.size() ? where_[i] : std::string()); });
        if (sink_.error_count() != errors) return std::nullopt;
        return std::move(scene_);
    }

private:
    void visit(int index, const Mat4& parent, std::optional<Tag> tag, int depth, const std::string& from) {
        const auto& m = doc_.model;
        if (index < 0 || static_cast<size_t>(index) >= m.nodes.size()) {
            sink_.report("E303", doc_.at(from), fmt::format("node {} does not exist", index));
            return;
        }
        const std::string at = fmt::format("/nodes/{}", index);
        if (visited_[size_t(index)] || depth > 1000) {
            sink_.report("E303", doc_.at(at), fmt::format("node {} is reached twice: the node hierarchy must be a tree", index));
            return;
        }
        visited_[size_t(index)] = true;
        const tinygltf::Node& node = m.nodes[size_t(index)];
        const Mat4 world = parent * local_transform(node);
        if (auto own = node_tag(node)) tag = own;
        if (node.mesh >= 0) add_mesh(node, index, world, tag);
        if (node.camera >= 0) add_camera(node, index, world);
        if (auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end() && it->second.Has("light"))
            pending_lights_.push_back({it->second.Get("light").GetNumberAsInt(), world, at + "/extensions/KHR_lights_punctual", node.name});
        if (node.skin >= 0 && !warned_skin_) {
            warned_skin_ = true;
            sink_.report("W311", doc_.at(at + "/skin"), "skinning is not applied: meshes are rendered in their bind pose");
        }
        for (size_t c = 0; c < node.children.size(); ++c) visit(node.children[c], world, tag, depth + 1, fmt::format("{}/children/{}", at, c));
    }

    void add_mesh(const tinygltf::Node& node, int node_index, const Mat4& world, const std::optional<Tag>& tag) {
        const auto& m = doc_.model;
        if (static_cast<size_t>(node.mesh) >= m.meshes.size()) {
            sink_.report("E303", doc_.at(fmt::format("/nodes/{}/mesh", node_index)), fmt::format("mesh {} does not exist", node.mesh));
            return;
        }
        const tinygltf::Mesh& mesh = m.meshes[size_t(node.mesh)];
        const bool flip = world.det3() < 0;  // a mirroring transform turns the triangles' winding
        for (size_t k = 0; k < mesh.primitives.size(); ++k) {
            const tinygltf::Primitive& p = mesh.primitives[k];
            const std::string at = fmt::format("/meshes/{}/primitives/{}", node.mesh, k);
            const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
                sink_.report("W311", doc_.at(at + "/mode"), fmt::format("mesh '{}' primitive {}: mode {} ({}) is not rendered: crex renders "
                                                                        "triangles", mesh.name, k, mode, mode <= 0 ? "points" : "lines"));
                continue;
            }
            if (!p.targets.empty() && !warned_morph_) {
                warned_morph_ = true;
                sink_.report("W311", doc_.at(at + "/targets"), "morph targets are not applied: the base shape is rendered");
            }
            auto attribute = [&](const char* name) {
                auto it = p.attributes.find(name);
                return it == p.attributes.end() ? -1 : it->second;
            };
            const int position = attribute("POSITION");
            if (position < 0) {
                sink_.report("E304", doc_.at(at + "/attributes"), fmt::format("mesh '{}' primitive {}: no POSITION attribute", mesh.name, k));
                continue;
            }
            const size_t errors = sink_.error_count();
            const size_t material = p.material >= 0 && static_cast<size_t>(p.material) < materials_.materials.size() - 1
                                        ? size_t(p.material) : materials_.default_index;
            if (p.material >= 0 && material == materials_.default_index)
                sink_.report("E303", doc_.at(at + "/material"), fmt::format("material {} does not exist", p.material));
            const std::vector<double> pos = gltf::read_accessor(doc_, position, 3, at + "/attributes/POSITION", sink_);
            const int normal_accessor = attribute("NORMAL");
            std::vector<double> nrm = normal_accessor >= 0 ? gltf::read_accessor(doc_, normal_accessor, 3, at + "/attributes/NORMAL", sink_)
                                                           : std::vector<double>{};
            const int uv_accessor = attribute(materials_.tex_coord[material] == 1 ? "TEXCOORD_1" : "TEXCOORD_0");
            std::vector<double> uv = uv_accessor >= 0 ? gltf::read_accessor(doc_, uv_accessor, 2, at + "/attributes/TEXCOORD", sink_)
                                                      : std::vector<double>{};
            // COLOR_0 (linear RGB or RGBA) multiplies the base colour; its alpha is not used.
            const int color_accessor = attribute("COLOR_0");
            const int color_components = color_accessor >= 0 && static_cast<size_t>(color_accessor) < doc_.model.accessors.size() &&
                                                 doc_.model.accessors[size_t(color_accessor)].type == TINYGLTF_TYPE_VEC4
                                             ? 4 : 3;
            const std::vector<double> colors =
                color_accessor >= 0 ? gltf::read_accessor(doc_, color_accessor, color_components, at + "/attributes/COLOR_0", sink_)
                                    : std::vector<double>{};
            std::vector<uint32_t> idx;
            if (p.indices >= 0) idx = gltf::read_indices(doc_, p.indices, at + "/indices", sink_);
            if (sink_.error_count() != errors) continue;
            const size_t n = pos.size() / 3;
            if (p.indices < 0)
                for (size_t i = 0; i < n; ++i) idx.push_back(static_cast<uint32_t>(i));
            Shape s;
            s.type = ShapeType::kMesh;
            s.name = !node.name.empty() ? node.name : mesh.name;
            s.material = materials_.materials[material].name;
            s.tag = tag;
            s.vertices.reserve(n);
            for (size_t i = 0; i < n; ++i) {
                const Vec3 v = world.point({pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]});
                if (!is_finite(v)) {
                    sink_.report("E303", doc_.at(fmt::format("/accessors/{}", position)),
                                 fmt::format("mesh '{}': vertex {} has a non-finite coordinate", mesh.name, i));
                    break;
                }
                s.vertices.push_back(v);
            }
            if (s.vertices.size() != n) continue;
            // An attribute with another count than POSITION's (invalid glTF) is left out, said once per primitive.
            for (const auto& [name, values, components] : {std::tuple<const char*, const std::vector<double>*, size_t>{"NORMAL", &nrm, 3},
                                                           {materials_.tex_coord[material] == 1 ? "TEXCOORD_1" : "TEXCOORD_0", &uv, 2},
                                                           {"COLOR_0", &colors, size_t(color_components)}})
                if (!values->empty() && values->size() / components != n)
                    sink_.report("W311", doc_.at(at + "/attributes/" + name),
                                 fmt::format("mesh '{}' primitive {}: {} has {} elements for {} vertices: it is not used", mesh.name, k, name,
                                             values->size() / components, n));
            if (nrm.size() == pos.size())
                for (size_t i = 0; i < n; ++i) {
                    const Vec3 v = world.normal({nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]});
                    s.normals.push_back(is_finite(v) ? v : Vec3{});
                }
            // Normals that are zero (or were not finite) mean the file has none there: shade flat.
            for (const auto& v : s.normals)
                if (v == Vec3{}) {
                    s.normals.clear();
                    break;
                }
            if (uv.size() / 2 == n)
                for (size_t i = 0; i < n; ++i) s.uvs.push_back({std::isfinite(uv[2 * i]) ? uv[2 * i] : 0.0, std::isfinite(uv[2 * i + 1]) ? uv[2 * i + 1] : 0.0});
            if (colors.size() / size_t(color_components) == n)
                for (size_t i = 0; i < n; ++i) {
                    const double* c = &colors[size_t(color_components) * i];
                    s.colors.push_back(imported_vertex_color(c[0], c[1], c[2]));
                }
            // Triangles of the primitive's mode.
            auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
                if (a >= n || b >= n || c >= n) return false;
                if (flip) std::swap(b, c);
                s.triangles.push_back({a, b, c});
                return true;
            };
            bool in_range = true;
            if (mode == TINYGLTF_MODE_TRIANGLES) {
                for (size_t i = 0; i + 2 < idx.size(); i += 3) in_range = add(idx[i], idx[i + 1], idx[i + 2]) && in_range;
            } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                for (size_t i = 0; i + 2 < idx.size(); ++i)
                    in_range = (i % 2 == 0 ? add(idx[i], idx[i + 1], idx[i + 2]) : add(idx[i + 1], idx[i], idx[i + 2])) && in_range;
            } else {
                for (size_t i = 1; i + 1 < idx.size(); ++i) in_range = add(idx[0], idx[i], idx[i + 1]) && in_range;
            }
            if (!in_range) {
                sink_.report("E303", doc_.at(at + "/indices"), fmt::format("mesh '{}' primitive {}: an index is beyond its {} vertices", mesh.name, k, n));
                continue;
            }
            if (s.triangles.empty()) {
                sink_.report("W311", doc_.at(at), fmt::format("mesh '{}' primitive {}: no triangles", mesh.name, k));
                continue;
            }
            used_[material] = true;
            where_.push_back(at);
            scene_.shapes.push_back(std::move(s));
        }
    }

    void add_camera(const tinygltf::Node& node, int node_index, const Mat4& world) {
        const auto& m = doc_.model;
        const std::string at = fmt::format("/nodes/{}/camera", node_index);
        if (static_cast<size_t>(node.camera) >= m.cameras.size()) {
            sink_.report("E303", doc_.at(at), fmt::format("camera {} does not exist", node.camera));
            return;
        }
        const tinygltf::Camera& c = m.cameras[size_t(node.camera)];
        const bool orthographic = c.type == "orthographic";
        if (c.type != "perspective" && !orthographic) {
            sink_.report("W311", doc_.at(fmt::format("/cameras/{}", node.camera)),
                         fmt::format("camera '{}' is of type '{}', neither perspective nor orthographic; it is not used", c.name, c.type));
            return;
        }
        NamedCamera named;
        named.name = gltf::camera_name(c, node, scene_.cameras.size());
        named.camera.position = world.point({0, 0, 0});
        named.camera.direction = world.vector({0, 0, -1});
        named.camera.up = world.vector({0, 1, 0});
        // Perspective: the vertical field of view; orthographic: crex's parallel view, whose
        // "fields of view" are the view's height and width in scene units (twice ymag, xmag).
        const double vertical = orthographic ? 2 * c.orthographic.ymag : c.perspective.yfov * 180 / 3.14159265358979323846;
        const double horizontal = orthographic ? 2 * c.orthographic.xmag : 0;
        const bool usable = orthographic ? vertical > 0 && std::isfinite(vertical) && horizontal > 0 && std::isfinite(horizontal)
                                         : vertical > 0 && vertical < 180;
        if (!usable || !is_finite(named.camera.position) || !(length(cross(named.camera.direction, named.camera.up)) > 0)) {
            sink_.report("W311", doc_.at(fmt::format("/cameras/{}", node.camera)),
                         fmt::format("camera '{}': its field of view or placement cannot be used; it is not used", named.name));
            return;
        }
        named.camera.vfov_deg = vertical;
        if (orthographic) {
            named.camera.projection = Projection::kParallel;
            named.camera.hfov_deg = horizontal;
        }
        scene_.cameras.push_back(named);
    }

    // KHR_lights_punctual: point and spot lights become small spheres of `light` material
    // with the same intensity (radiance = intensity / (pi r^2)), sized by the scene; a spot
    // keeps its cone; a directional light becomes a distant light the size of the sun.
    void add_lights() {
        const auto& m = doc_.model;
        if (pending_lights_.empty()) return;
        Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
        for (const auto& s : scene_.shapes) expand_bounds(s, lo, hi);
        for (const auto& l : pending_lights_) lo = vmin(lo, l.world.point({})), hi = vmax(hi, l.world.point({}));
        const double extent = is_finite(hi - lo) ? length(hi - lo) : 1.0;
        const double nominal_radius = std::max(2.5e-3 * extent, 1e-6);
        const size_t surfaces = scene_.shapes.size();  // the scene's own, before the lights join it
        for (const auto& pending : pending_lights_) {
            if (pending.index < 0 || static_cast<size_t>(pending.index) >= m.lights.size()) {
                sink_.report("E303", doc_.at(pending.at), fmt::format("light {} does not exist", pending.index));
                continue;
            }
            const tinygltf::Light& light = m.lights[size_t(pending.index)];
            const std::string name = !light.name.empty() ? light.name : !pending.node.empty() ? pending.node : fmt::format("light{}", pending.index);
            if (light.type != "point" && light.type != "spot" && light.type != "directional") {
                sink_.report("W311", doc_.at(pending.at), fmt::format("light '{}' is of type '{}': it is not rendered", name, light.type));
                continue;
            }
            Vec3 colour{1, 1, 1};
            if (light.color.size() == 3) colour = vmax(Vec3{light.color[0], light.color[1], light.color[2]}, Vec3{});
            const double intensity = std::isfinite(light.intensity) ? std::max(light.intensity, 0.0) : 0.0;
            const Vec3 max_radiance{kMaxRadiance, kMaxRadiance, kMaxRadiance};
            Material mat;
            mat.name = fmt::format("{}/light:{}#{}", std::filesystem::path(path_).stem().string(), name, pending.index);
            mat.type = MaterialType::kLight;
            if (light.type == "directional") {
                // A distant `light` of the sun's size along the node's +z (it shines along -z),
                // its illuminance (lux) kept: radiance = intensity / the disk's solid angle.
                DistantLight d;
                d.name = "light:" + name;
                d.material = mat.name;
                d.direction = normalize_or_zero(pending.world.vector({0, 0, 1}));
                d.angle_deg = kSunAngleDeg;
                const double solid_angle = 2 * 3.14159265358979323846 * (1 - std::cos(kSunAngleDeg * 3.14159265358979323846 / 360));
                mat.color = vmin(colour * (intensity / solid_angle), max_radiance);
                if (d.direction == Vec3{}) {
                    sink_.report("W311", doc_.at(pending.at), fmt::format("directional light '{}': its node's transform has no direction; it is not rendered", name));
                    continue;
                }
                if (!scene_.find_material(mat.name)) scene_.materials.push_back(mat), used_.push_back(true);
                scene_.distant_lights.push_back(d);
                continue;
            }
            const double radius = bulb_radius(pending.world.point({}), nominal_radius, surfaces, name, pending.at);
            mat.color = vmin(colour * (intensity / (3.14159265358979323846 * radius * radius)), max_radiance);
            if (light.type == "spot") {
                // crex's spotlight: a hard cone at glTF's outer angle (a half angle; crex's is
                // the whole), along the node's -z, its focus at the bulb (no extra falloff).
                const double outer = std::isfinite(light.spot.outerConeAngle) ? std::clamp(light.spot.outerConeAngle, 0.0, 3.14159265358979323846 / 2) : 0.785398;
                Spot spot;
                spot.angle_deg = 2 * outer * 180 / 3.14159265358979323846;
                spot.direction = normalize_or_zero(pending.world.vector({0, 0, -1})) * (1e-6 * radius);
                if (spot.direction != Vec3{} && spot.angle_deg > 0) mat.spot = spot;
                if (light.spot.innerConeAngle < outer)
                    sink_.report("W311", doc_.at(pending.at), fmt::format("spot light '{}': its cone's soft edge (inner angle {:g}, outer {:g}) "
                                                                          "is rendered as a hard edge at the outer angle", name,
                                                                          light.spot.innerConeAngle, outer));
            }
            // Two nodes of one light share its material unless their bulbs differ in size.
            if (const Material* same = scene_.find_material(mat.name); same && same->color != mat.color)
                mat.name += fmt::format("@{}", scene_.shapes.size());
            if (!scene_.find_material(mat.name)) {
                scene_.materials.push_back(mat);
                used_.push_back(true);
            }
            Shape s;
            s.type = ShapeType::kSphere;
            s.name = "light:" + name;
            s.material = mat.name;
            s.center = pending.world.point({});
            s.radius = radius;
            where_.push_back(pending.at);
            scene_.shapes.push_back(s);
        }
    }

    /// The radius of the sphere standing in for a point light at `centre`: the scene-sized
    /// `nominal`, shrunk to half the light's distance from the nearest surface. A bulb larger
    /// than the room around it would poke through a lamp's pole or a wall and shine from the
    /// wrong side; the light's power is kept whatever its size. A light behind the surface it
    /// is nearest (inside a closed mesh) is warned about: it lights only what it sees there.
    double bulb_radius(const Vec3& centre, double nominal, size_t surfaces, const std::string& name, const std::string& at) {
        double nearest = INFINITY;
        size_t nearest_shape = surfaces;
        bool behind = false;
        for (size_t i = 0; i < surfaces; ++i) {
            const Shape& shape = scene_.shapes[i];
            Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
            expand_bounds(shape, lo, hi);
            const Vec3 outside = vmax(vmax(lo - centre, centre - hi), Vec3{});
            if (!(length(outside) < nearest)) continue;  // its box is farther than the nearest so far
            const SurfaceDistance d = distance_to_surface(shape, centre);
            if (d.distance < nearest) nearest = d.distance, nearest_shape = i, behind = d.behind;
        }
        const double radius = std::max(std::min(nominal, 0.5 * nearest), 1e-6 * nominal);
        if (nearest_shape < surfaces && behind)
            sink_.report("W311", doc_.at(at), fmt::format("light '{}' is {:.3g} behind a face of '{}' (inside it?): it lights only what it can see from there",
                                                          name, nearest, scene_.shapes[nearest_shape].name));
        else if (nearest_shape < surfaces && radius < 0.1 * nominal)  // irradiance grows as 1/d^2 up to the bulb
            sink_.report("W311", doc_.at(at), fmt::format("light '{}' is only {:.3g} from '{}': its bulb is shrunk to radius {:.3g} (a tenth of "
                                                          "{:.3g} or less), and the surface next to it is lit so brightly that its "
                                                          "bounces are fireflies; move the light away from it",
                                                          name, nearest, scene_.shapes[nearest_shape].name, radius, nominal));
        return radius;
    }

    struct PendingLight {
        int index;
        Mat4 world;
        std::string at, node;
    };
    const Document& doc_;
    std::string path_;
    DiagnosticSink& sink_;
    Scene scene_;
    gltf::ConvertedMaterials materials_;
    std::vector<bool> used_, visited_;
    std::vector<std::string> where_;  ///< per shape: its JSON pointer
    std::vector<PendingLight> pending_lights_;
    bool warned_skin_ = false, warned_morph_ = false;
};

}  // namespace

std::optional<Scene> import_gltf(const std::string& path, DiagnosticSink& sink, SceneSources& sources) {
    auto doc = gltf::read_document(path, sources, sink);
    if (!doc) return std::nullopt;
    return GltfImporter(*doc, path, sink).run();
}

}  // namespace crex
