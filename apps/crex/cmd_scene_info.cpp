// `crex scene-info SCENE`: what a scene holds and which component bins can ever have work.
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <map>
#include <memory>

#include "apps/crex/commands.h"
#include "base/exit_codes.h"
#include "base/render_json.h"
#include "base/render_text.h"
#include "runtime/base/atomic_file.h"
#include "runtime/scene/census.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/shapes.h"
#include "runtime/texture/surface_textures.h"

namespace crex::app {
namespace {

struct SceneInfoOptions {
    std::string scene = "builtin:cornell";
    std::string format = "text";
    std::string export_json;
    std::string camera;
};

struct Stats {
    std::map<std::string, size_t> shapes_by_type;
    size_t triangles = 0;
    size_t spheres = 0;
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
};

Stats scene_stats(const Scene& s) {
    Stats st;
    for (const auto& shape : s.shapes) {
        ++st.shapes_by_type[std::string(shape_type_name(shape.type))];
        if (shape.type == ShapeType::kSphere) ++st.spheres;
        st.triangles += triangle_count(shape);
        expand_bounds(shape, st.lo, st.hi);
    }
    return st;
}

std::string vec_text(const Vec3& v) { return fmt::format("({:g}, {:g}, {:g})", v.x, v.y, v.z); }

// The images the materials use, opened (headers only) through the texture backend.
std::vector<TextureImage> texture_images(const Scene& scene, std::vector<Diagnostic>& warnings) {
    bool any = false;
    for (const auto& m : scene.materials) any = any || m.textures.any();
    if (!any) return {};
    try {
        return SurfaceTextures(scene, texture_cache_bytes(kDefaultMaxMemory), warnings, TiledCopies::kFindOnly).stats().images;  // as a render at the default, making no copy
    } catch (const std::exception& e) {
        warnings.push_back(run_diagnostic("W310", "crex scene-info", e.what()));  // no image plugin, say
        return {};
    }
}

std::string textured_slots(const Material& m) {
    std::string out;
    m.textures.for_each([&](const char* slot, const TextureRef&) { out += (out.empty() ? "" : ", ") + std::string(slot); });
    return out;
}

void print_text(const Scene& scene, const Census& c, const Stats& st, const std::vector<TextureImage>& images) {
    std::string types;
    for (const auto& [t, n] : st.shapes_by_type) types += fmt::format("{}{} {}", types.empty() ? "" : ", ", n, t);
    std::cout << fmt::format("scene {}\n", scene.source);
    std::cout << fmt::format("  shapes     {} ({}) -> {} triangles + {} analytic spheres\n", scene.shapes.size(), types,
                             st.triangles, st.spheres);
    std::cout << fmt::format("  bounds     {} .. {}\n", vec_text(st.lo), vec_text(st.hi));
    const Camera& cam = scene.camera;
    const bool parallel = cam.projection == Projection::kParallel;
    std::cout << fmt::format("  camera     {} at {} looking {} up {}, {} {:g}{}{}\n", projection_name(cam.projection), vec_text(cam.position),
                             vec_text(cam.direction), vec_text(cam.up), parallel ? "height" : "vfov", cam.vfov_deg, parallel ? "" : " deg",
                             cam.hfov_deg > 0 ? fmt::format(", {} {:g}{}", parallel ? "width" : "hfov", cam.hfov_deg, parallel ? "" : " deg") : "");
    if (!scene.distant_lights.empty()) {
        std::string names;
        for (const auto& l : scene.distant_lights)
            names += fmt::format("{}{} ({:g} deg{})", names.empty() ? "" : ", ", l.name.empty() ? l.material : l.name, l.angle_deg,
                                 l.sky ? fmt::format(", {} sky", sky_type_name(l.sky->type)) : "");
        std::cout << fmt::format("  distant    {}\n", names);
    }
    for (size_t i = 0; i < scene.cameras.size(); ++i)
        std::cout << fmt::format("  camera {:<3} '{}' at {} looking {}\n", i, scene.cameras[i].name, vec_text(scene.cameras[i].camera.position),
                                 vec_text(scene.cameras[i].camera.direction));
    if (scene.units.metres_per_unit > 0 || scene.units.up != Vec3{})
        std::cout << fmt::format("  units      {}{}\n", scene.units.metres_per_unit > 0 ? fmt::format("{:g} m per unit", scene.units.metres_per_unit) : "",
                                 scene.units.up != Vec3{} ? fmt::format(", up {}", vec_text(scene.units.up)) : "");
    std::cout << fmt::format("  emitters   {} sampled (light, illum, glow with a radius, distant, textured emission), {} "
                             "unsampled (other glow or emission)\n", c.sampled_emitters, c.unsampled_emitters);
    if (c.has_medium)
        std::cout << (scene.medium->bounded ? fmt::format("  medium     homogeneous single-scatter, in the box {} .. {}\n", vec_text(scene.medium->box_min),
                                                          vec_text(scene.medium->box_max))
                                            : std::string("  medium     homogeneous single-scatter, everywhere\n"));
    if (!scene.back_faces_visible)
        std::cout << "  back faces hidden (RADIANCE -bv-): a ray meeting the back of a surface goes through it (not dielectrics, emitters, BRTDfunc, prisms)\n";
    if (!c.tags.empty()) {
        std::string tags;
        for (size_t i = 0; i < c.tags.size(); ++i)
            tags += fmt::format("{}{} ({} surface{})", tags.empty() ? "" : ", ", c.tags[i], c.tag_surfaces[i], c.tag_surfaces[i] == 1 ? "" : "s");
        std::cout << fmt::format("  tagged     {}\n", tags);
    }
    std::cout << "\nmaterials in use (component split):\n";
    for (const auto& m : c.materials) {
        std::string spawns = component_set_letters(m.spawns);
        const Material* mat = scene.find_material(m.name);
        const std::string slots = mat ? textured_slots(*mat) : "";
        std::cout << fmt::format("  {:<20} {:<10} spawns {:<8} ({} shape{}){}\n", m.name, material_type_name(m.type),
                                 spawns.empty() ? "nothing" : spawns, m.shapes, m.shapes == 1 ? "" : "s",
                                 slots.empty() ? "" : ", textured: " + slots);
    }
    if (!images.empty()) {
        uint64_t file = 0, memory = 0;
        std::cout << "\ntextures (memory: all texels with their MIP levels; the render's cache holds at most its share of --max-memory):\n";
        for (const auto& i : images) {
            if (!i.error.empty()) {
                std::cout << fmt::format("  {}  cannot be read: {} (renders magenta)\n", i.name, i.error);
                continue;
            }
            file += i.info.file_bytes, memory += i.memory_bytes();
            std::cout << "  " << image_text(i);
        }
        std::cout << fmt::format("  {} image{}: {:.1f} MiB on disk, {:.1f} MiB in memory\n", images.size(), images.size() == 1 ? "" : "s",
                                 file / double(1 << 20), memory / double(1 << 20));
    }
    std::cout << "\ncensus: which bins can ever receive rays\n";
    std::string cannot;
    for (const auto& row : kComponentTable) {
        bool yes = c.can_occur(row.component);
        std::string from;
        for (const auto& m : c.materials)
            if (m.spawns.test(static_cast<size_t>(row.component))) from += (from.empty() ? "" : ", ") + m.name;
        std::cout << fmt::format("  {} {:<32} {}\n", row.letter, row.name, yes ? "yes, from " + from : "no");
        if (!yes) cannot += (cannot.empty() ? "" : ", ") + std::string(1, row.letter);
    }
    if (!cannot.empty()) std::cout << fmt::format("  cannot occur: {} (crex steps on these are pruned)\n", cannot);
    std::string sources = "camera";
    for (const auto& row : kComponentTable)
        if (c.can_occur(row.component)) sources += fmt::format(", {}", row.letter);
    std::cout << fmt::format("\nspawn graph: {{{}}} -> {{{}}}\n", sources, component_set_letters(c.spawnable));
    std::cout << fmt::format("census hash: {}\n", census_hash_hex(c.hash));
}

int run_scene_info(const SceneInfoOptions& opt) {
    SceneSources sources;
    DiagnosticSink sink;
    SceneLoadFailure failure;
    auto scene = load_scene(opt.scene, sources, sink, failure);
    std::vector<Diagnostic> diagnostics = sink.sorted();
    if (opt.format == "text") std::cerr << render_text(diagnostics);
    if (!failure.message.empty()) {
        std::cerr << "crex scene-info: error: " << failure.message << "\n";
        return kExitFailure;
    }
    if (!scene) {
        if (opt.format == "json") {
            nlohmann::json out = {{"diagnostics", to_json(diagnostics)}, {"scene", nullptr}};
            std::cout << out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
        } else {
            std::cerr << fmt::format("{} error{}: the scene was not loaded\n", sink.error_count(),
                                     sink.error_count() == 1 ? "" : "s");
        }
        return kExitInputErrors;
    }
    if (!opt.camera.empty()) {
        if (std::string error = select_camera(*scene, opt.camera); !error.empty()) {
            std::cerr << "crex scene-info: error: " << error << "\n";
            return kExitUsage;
        }
    }
    if (!opt.export_json.empty()) {
        std::string error = write_file_atomically(opt.export_json, scene_json_text(*scene));
        if (!error.empty()) {
            std::cerr << fmt::format("crex scene-info: error: cannot write '{}': {}\n", opt.export_json, error);
            return kExitFailure;
        }
    }
    Census census = take_census(*scene);
    Stats st = scene_stats(*scene);
    std::vector<Diagnostic> texture_warnings;
    const std::vector<TextureImage> images = texture_images(*scene, texture_warnings);
    if (opt.format == "text") std::cerr << render_text(texture_warnings);
    if (opt.format == "json") {
        nlohmann::json out;
        out["diagnostics"] = to_json(diagnostics);
        out["scene"] = {{"source", scene->source}, {"shapes", scene->shapes.size()}, {"triangles", st.triangles},
                        {"spheres", st.spheres}, {"shapes_by_type", st.shapes_by_type},
                        {"back_faces_visible", scene->back_faces_visible}};
        out["census"] = to_json(census);
        out["textures"] = images_json(images);
        nlohmann::json cameras = nlohmann::json::array();
        for (const auto& c : scene->cameras) cameras.push_back(c.name);
        out["scene"]["cameras"] = cameras;
        if (scene->units.metres_per_unit > 0) out["scene"]["metres_per_unit"] = scene->units.metres_per_unit;
        if (scene->units.up != Vec3{}) out["scene"]["up"] = {scene->units.up.x, scene->units.up.y, scene->units.up.z};
        std::cout << out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    } else {
        print_text(*scene, census, st, images);
    }
    return kExitOk;
}

}  // namespace

Runner add_scene_info_command(CLI::App& app) {
    auto opt = std::make_shared<SceneInfoOptions>();
    CLI::App* cmd = app.add_subcommand("scene-info", "Show a scene's contents and its material census");
    cmd->add_option("scene", opt->scene, "A scene: file.json, file.rad, file.rif, file.obj, file.gltf, file.glb or builtin:NAME")
        ->capture_default_str();
    cmd->add_option("--format", opt->format, "text or json (on stdout)")->check(CLI::IsMember({"text", "json"}));
    cmd->add_option("--export-json", opt->export_json, "Also write the scene in crex's native JSON format to FILE");
    cmd->add_option("--camera", opt->camera, "The scene's camera NAME or INDEX (glTF files name theirs; the first is the default)");
    cmd->footer(R"(
The census lists, for each component bin (D G S T R M), whether any material in use can spawn
rays into it. Crex steps on bins that can never have work are pruned by the planner.

Examples:
  crex scene-info                                   the built-in Cornell box
  crex scene-info builtin:cornell_diffuse           only D can occur
  crex scene-info examples/scenes/cornell/scene.rad a RADIANCE scene (+ scene.vf for the view)
  crex scene-info --format json my_scene.json
  crex scene-info model.obj --export-json model.json   convert to the native format
  crex scene-info room.gltf                         meshes, cameras, lights, textures (files, sizes, memory)

Exit status: 0 ok or warnings only, 1 errors in the scene, 2 usage, 3 cannot read it.)");
    return [opt] { return run_scene_info(*opt); };
}

}  // namespace crex::app
