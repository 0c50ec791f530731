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
                d->p.modifier = {"void", file.span};
                d->p.type = {o.type, file.span};
                d->p.id = {o.name, file.span};
                for (const std::string& s : o.strings) d->p.strings.push_back({s, file.span});
                d->p.reals = o.reals;
                d->p.real_spans.assign(o.reals.size(), file.span);
                d->p.span = file.span;
                d->p.via = p.via;
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

}  // namespace crex::radiance
