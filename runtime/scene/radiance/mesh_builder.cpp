// RADIANCE's `mesh` primitive: a compiled mesh (.rtm) placed by its transform, its triangles
// in the mesh's own materials, or all in the primitive's modifier when that is not void (as
// RADIANCE renders it).
#include <fmt/format.h>

#include <map>

#include "runtime/scene/radiance/compiled_mesh.h"
#include "runtime/scene/radiance/generators.h"
#include "runtime/scene/radiance/primitive_types.h"
#include "runtime/scene/radiance/scene_builder.h"

namespace crex::radiance {

void SceneBuilder::mesh(const Primitive& p, const std::optional<Tag>& tag) {
    if (p.strings.empty()) {
        report("E303", p.type.span, fmt::format("mesh '{}' needs its mesh file as a string argument", p.id.text), &p);
        return;
    }
    const Word& file = p.strings[0];
    const std::string path = find_named_file(file);
    auto cached = meshes_.find(path);
    if (cached == meshes_.end()) {
        auto m = std::make_shared<CompiledMesh>();
        std::string error;
        if (path.empty() || !read_compiled_mesh(path, *m, error)) {
            // Once per file, not once per copy an xform array makes of it.
            if (refused_places_.insert({file.span.file, file.span.begin}).second)
                report("E308", file.span, fmt::format("mesh '{}': cannot read the compiled mesh '{}': {}", p.id.text, file.text,
                                                      path.empty() ? "no such file" : error), &p)
                    .help = "it is looked for next to the file that names it, then in the RAYPATH directories";
            return;
        }
        cached = meshes_.emplace(path, std::move(m)).first;
    }
    const CompiledMesh& m = *cached->second;
    std::optional<Transform> xf = function_transform(p, 1);
    if (!xf) return;

    // The material of each of the mesh's materials (an alias followed to what it names), or
    // the primitive's modifier for all of them.
    std::vector<std::optional<std::string>> materials(m.materials.size() + 1);  // [0]: triangles without one
    if (p.modifier.text != "void") {
        DefPtr d = lookup(p.modifier, p, "the modifier");
        if (!d) return;
        auto name = material_of(d, p);
        if (!name) return;
        std::fill(materials.begin(), materials.end(), name);
    } else {
        materials[0] = "";  // void: invisible
        for (size_t k = 0; k < m.materials.size(); ++k) {
            size_t target = k;
            for (int hops = 0; m.materials[target].type == "alias" && m.materials[target].modifier >= 0 && hops < 64; ++hops)
                target = static_cast<size_t>(m.materials[target].modifier);
            const std::string key = path + "#" + std::to_string(target);
            auto known = mesh_materials_.find(key);
            if (known == mesh_materials_.end()) {
                const BinaryObject& o = m.materials[target];
                auto d = std::make_shared<Definition>();
                d->p = from_binary(o, "void", p);
                std::optional<std::string> name;
                const PrimitiveTypeInfo* info = find_primitive_type(o.type);
                if (!info || info->kind == PrimitiveKind::kSurface || info->kind == PrimitiveKind::kAlias) {
                    report("E308", file.span, fmt::format("mesh '{}': the mesh's material '{}' has the type '{}', which is {}", p.id.text,
                                                          o.name, o.type, info ? "not a material" : "not a RADIANCE type"), &p);
                } else if (o.modifier >= 0 || o.type == "alias") {
                    report("E307", file.span, fmt::format("mesh '{}': the mesh's material '{}' has a modifier of its own, which crex does "
                                                          "not read inside compiled meshes", p.id.text, o.name), &p);
                } else {
                    name = material_of(d, p);
                }
                known = mesh_materials_.emplace(key, name).first;
            }
            materials[k + 1] = known->second;
        }
    }

    // One shape per material, with the vertices it uses, moved by the transform.
    std::map<std::string, Shape> shapes;
    std::map<std::string, std::vector<int64_t>> remap;  // per shape: the mesh's vertex -> the shape's
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const std::optional<std::string>& name = materials[static_cast<size_t>(m.triangle_material[t] + 1)];
        if (!name || name->empty()) continue;  // reported, or invisible
        Shape& s = shapes[*name];
        std::vector<int64_t>& index = remap[*name];
        if (index.empty()) {
            index.assign(m.positions.size(), -1);
            s.type = ShapeType::kMesh;
            s.name = p.id.text;
            s.material = *name;
            s.tag = tag;
            s.file = path;
        }
        std::array<uint32_t, 3> tri;
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t v = m.triangles[t][k];
            if (index[v] < 0) {
                index[v] = static_cast<int64_t>(s.vertices.size());
                s.vertices.push_back(xf->point(m.positions[v]));
                if (m.has_normals) s.normals.push_back(normalize_or_zero(xf->vector(m.normals[v])));
                if (m.has_uvs) s.uvs.push_back(m.uvs[v]);
            }
            tri[k] = static_cast<uint32_t>(index[v]);
        }
        if (xf->mirrors()) std::swap(tri[1], tri[2]);  // keep the front side
        s.triangles.push_back(tri);
    }
    for (auto& [name, s] : shapes) {
        // A normal the mesh lacks (code 0) leaves the whole shape flat: crex takes normals for
        // every vertex or none.
        for (const Vec3& n : s.normals)
            if (n == Vec3{}) {
                s.normals.clear();
                break;
            }
        shape_spans_.push_back(p.type.span.merge(p.id.span));
        shape_modifiers_.push_back(p.modifier.text);
        shape_tag_explicit_.push_back(tag.has_value());
        scene_.shapes.push_back(std::move(s));
    }
}

bool SceneBuilder::mesh_normals(const Definition& texture, const Primitive& user, const std::vector<Vec3>& vertices,
                               std::vector<Vec3>& normals) {
    const Primitive& t = texture.p;
    auto base = [](const std::string& f) { return f.substr(f.find_last_of('/') + 1); };
    if (t.type.text != "texfunc" || t.strings.size() < 4 || t.strings[0].text != "dx" || t.strings[1].text != "dy" ||
        t.strings[2].text != "dz" || base(t.strings[3].text) != "tmesh.cal" || t.reals.size() != 10)
        return false;
    normals.clear();
    if (vertices.size() != 3) {
        report("E307", user.type.span, fmt::format("{} '{}': tmesh.cal's normals ('{}') interpolate across triangles, not across {} "
                                                   "vertices", user.type.text, user.id.text, t.id.text, vertices.size()), &user);
        return true;
    }
    const double axis = t.reals[0];
    if (!(axis == 0 || axis == 1 || axis == 2)) {
        report("E303", t.real_spans[0], fmt::format("texfunc '{}': tmesh.cal's major axis must be 0, 1 or 2, got {:g}", t.id.text, axis), &t);
        return true;
    }
    std::optional<Transform> xf = function_transform(t, 4);
    if (!xf) return true;
    // A vertex in the function's own coordinates: the transform is a similarity (xform's).
    const Vec3 origin = xf->point({});
    const Vec3 axes[3] = {xf->vector({1, 0, 0}), xf->vector({0, 1, 0}), xf->vector({0, 0, 1})};
    const double s2 = xf->scale() * xf->scale();
    const int a = static_cast<int>(axis);
    for (const Vec3& v : vertices) {
        const double P[3] = {dot(axes[0], v - origin) / s2, dot(axes[1], v - origin) / s2, dot(axes[2], v - origin) / s2};
        // tmesh.cal: (bu, bv) the coordinates across the major axis, the normal M (bu, bv, 1).
        const double bu = P[(a + 1) % 3], bv = P[(a + 2) % 3];
        const double* m = &t.reals[1];
        const Vec3 n{bu * m[0] + bv * m[1] + m[2], bu * m[3] + bv * m[4] + m[5], bu * m[6] + bv * m[7] + m[8]};
        normals.push_back(normalize_or_zero(xf->vector(n)));
    }
    for (const Vec3& n : normals)
        if (n == Vec3{}) {  // a degenerate normal matrix: shaded flat, as RADIANCE cannot do better
            normals.clear();
            normals.resize(3, Vec3{});
            break;
        }
    return true;
}

}  // namespace crex::radiance
