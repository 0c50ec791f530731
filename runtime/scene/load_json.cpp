// The native scene format (docs/scene-format.md): JSON read with positions, every field
// checked with its path and line, unknown fields warned about with the nearest known name.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "base/base64.h"
#include "base/json_positions.h"
#include "runtime/scene/pattern_json.h"
#include "runtime/scene/json_fields.h"
#include "base/nearest_name.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/material.h"
#include "runtime/scene/shapes.h"

namespace crex {
namespace {

using nlohmann::json;

const Range kRadiance{0, kMaxRadiance};

class SceneJsonLoader {
public:
    SceneJsonLoader(const PositionedJson& doc, const SourceFile& file, std::string base_dir, SceneSources& sources,
                    DiagnosticSink& sink)
        : doc_(doc), file_(file), base_dir_(std::move(base_dir)), sources_(sources), sink_(sink) {}

    std::optional<Scene> load() {
        size_t errors_before = sink_.error_count();
        if (!doc_.value.is_object()) {
            sink_.report("E302", doc_.span(""), fmt::format("a scene file must hold a JSON object, got {}", json_type_name(doc_.value)));
            return std::nullopt;
        }
        Scene scene;
        scene.source = file_.name();
        ObjectReader top(doc_, sink_, doc_.value, "");
        top.warn_unknown({"format", "version", "camera", "cameras", "units", "background", "medium", "images", "materials", "shapes",
                          "distant_lights", "back_faces_visible"});
        top.format_and_version("crex-scene");
        if (top.has("camera")) read_camera(top, scene.camera);
        read_array(top, "cameras", [&](ObjectReader& r) { read_named_camera(r, scene); });
        if (!top.has("camera") && !scene.cameras.empty()) scene.camera = scene.cameras.front().camera;
        if (top.has("units")) read_units(top, scene.units);
        read_array(top, "images", [&](ObjectReader& r) { read_image(r, scene); });
        top.vec3("background", scene.background, kRadiance);
        top.boolean("back_faces_visible", scene.back_faces_visible);
        if (top.has("medium")) read_medium(top, scene);
        read_array(top, "materials", [&](ObjectReader& r) { read_material(r, scene); });
        read_array(top, "shapes", [&](ObjectReader& r) { read_shape(r, scene); });
        read_array(top, "distant_lights", [&](ObjectReader& r) { read_distant_light(r, scene); });
        if (!top.has("shapes")) top.missing("shapes", "an array of shapes");
        if (sink_.error_count() != errors_before) return std::nullopt;
        validate_scene(scene, sink_, [&](size_t i) {
            if (i >= shape_index_.size()) return doc_.span(doc_.value.contains("camera") ? "/camera" : "");
            return doc_.span("/shapes/" + std::to_string(shape_index_[i]));
        });
        if (sink_.error_count() != errors_before) return std::nullopt;
        return scene;
    }

private:
    template <class F>
    void read_array(ObjectReader& parent, const std::string& key, F&& each) {
        if (!parent.has(key)) return;
        if (!parent.at(key).is_array()) {
            parent.wrong(key, "an array of objects");
            return;
        }
        for (size_t i = 0; i < parent.at(key).size(); ++i) {
            const json& e = parent.at(key)[i];
            std::string ptr = parent.pointer() + "/" + key + "/" + std::to_string(i);
            current_index_ = i;
            if (!e.is_object()) {
                sink_.report("E302", doc_.span(ptr), fmt::format("{}: expected an object, got {}", readable_json_path(ptr), json_type_name(e)));
                continue;
            }
            ObjectReader r(doc_, sink_, e, ptr);
            each(r);
        }
    }

    void read_camera(ObjectReader& top, Camera& cam) {
        if (!top.at("camera").is_object()) {
            top.wrong("camera", "an object");
            return;
        }
        ObjectReader r(doc_, sink_, top.at("camera"), "/camera");
        r.warn_unknown({"position", "direction", "look_at", "up", "vfov", "hfov", "view_distance", "projection", "fore_clip"});
        read_camera_fields(r, cam);
    }

    // One of the file's named cameras (`crex --camera NAME|INDEX` chooses among them).
    void read_named_camera(ObjectReader& r, Scene& scene) {
        r.warn_unknown({"name", "position", "direction", "look_at", "up", "vfov", "hfov", "view_distance", "projection",
                        "fore_clip"});
        NamedCamera c;
        r.string("name", c.name);
        read_camera_fields(r, c.camera);
        scene.cameras.push_back(c);
    }

    void read_units(ObjectReader& top, SceneUnits& units) {
        if (!top.at("units").is_object()) {
            top.wrong("units", "an object {\"metres_per_unit\": ..., \"up\": [x, y, z]}");
            return;
        }
        ObjectReader r(doc_, sink_, top.at("units"), "/units");
        r.warn_unknown({"metres_per_unit", "up"});
        r.number("metres_per_unit", units.metres_per_unit, kPositive);
        r.vec3("up", units.up);
    }

    // An image carried in the file: {"name": ..., "mime_type": ..., "data": base64}.
    void read_image(ObjectReader& r, Scene& scene) {
        r.warn_unknown({"name", "mime_type", "data"});
        EmbeddedImage image;
        std::string data;
        const bool named = r.string("name", image.name, true);
        if (!r.string("data", data, true) || !named) return;
        r.string("mime_type", image.mime_type);
        auto bytes = base64_decode(data);
        if (!bytes) {
            sink_.report("E303", r.span("data"), fmt::format("{}: expected the image's bytes in base64", r.path("data")));
            return;
        }
        image.bytes = std::move(*bytes);
        if (!image_names_.insert(image.name).second) {
            sink_.report("E305", r.span("name"), fmt::format("{}: an image named '{}' is already defined", r.path("name"), image.name));
            return;
        }
        scene.images.push_back(std::move(image));
    }

    void read_camera_fields(ObjectReader& r, Camera& cam) {
        std::string projection;
        if (r.string("projection", projection)) {
            auto p = projection_from_name(projection);
            if (!p)
                sink_.report("E303", r.span("projection"), fmt::format("{}: unknown projection '{}'; expected one of perspective, "
                                                                       "parallel, angular, hemispherical, stereographic, cylindrical",
                                                                       r.path("projection"), projection));
            else
                cam.projection = *p;
        }
        r.number("fore_clip", cam.fore_clip, kNonNegative);
        r.vec3("position", cam.position);
        Vec3 look_at;
        if (r.has("direction") && r.has("look_at"))
            sink_.report("E303", r.span("look_at"), "camera: give either 'direction' or 'look_at', not both");
        else if (r.vec3("look_at", look_at))
            cam.direction = look_at - cam.position;
        else
            r.vec3("direction", cam.direction);
        r.vec3("up", cam.up);
        // A field of view per projection: a fisheye reaches around, a parallel view's is a size.
        const Projection p = cam.projection;
        const double most = p == Projection::kParallel ? INFINITY
                            : p == Projection::kAngular || p == Projection::kStereographic ? 360 : 180;
        const bool closed = p == Projection::kAngular || p == Projection::kHemispherical;
        r.number("vfov", cam.vfov_deg, Range{0, p == Projection::kCylindrical ? 180 : most, true, !closed});
        r.number("hfov", cam.hfov_deg, Range{0, p == Projection::kCylindrical ? 360 : most, false, !(closed || p == Projection::kCylindrical)});
        r.number("view_distance", cam.view_distance, kPositive);
        if (!(length(cam.direction) > 0))
            sink_.report("E306", r.span(r.has("look_at") ? "look_at" : "direction"), "camera: the view direction has zero length");
        else if (!(length(cross(cam.direction, cam.up)) > 1e-9 * length(cam.direction) * length(cam.up)))
            sink_.report("E306", r.span("up"), "camera: 'up' is parallel to the view direction (or zero)");
    }

    void read_medium(ObjectReader& top, Scene& scene) {
        if (!top.at("medium").is_object()) {
            top.wrong("medium", "an object");
            return;
        }
        ObjectReader r(doc_, sink_, top.at("medium"), "/medium");
        r.warn_unknown({"extinction", "albedo", "eccentricity", "box"});
        Medium m;
        r.vec3("extinction", m.extinction, kNonNegative, true);
        r.vec3("albedo", m.albedo, kUnit);
        r.number("eccentricity", m.eccentricity, Range{-1, 1, true, true});
        if (r.has("box")) {
            const json& b = r.at("box");
            if (!b.is_array() || b.size() != 2 || !b[0].is_array() || b[0].size() != 3 || !b[1].is_array() || b[1].size() != 3) {
                r.wrong("box", "[[min x, y, z], [max x, y, z]]");
            } else {
                bool numbers = true;
                for (int k = 0; k < 2; ++k)
                    for (int c = 0; c < 3; ++c) numbers = numbers && b[k][c].is_number() && std::isfinite(b[k][c].get<double>());
                if (!numbers) {
                    r.wrong("box", "[[min x, y, z], [max x, y, z]] of finite numbers");
                } else {
                    m.bounded = true;
                    m.box_min = {b[0][0].get<double>(), b[0][1].get<double>(), b[0][2].get<double>()};
                    m.box_max = {b[1][0].get<double>(), b[1][1].get<double>(), b[1][2].get<double>()};
                    if (!(m.box_min.x < m.box_max.x && m.box_min.y < m.box_max.y && m.box_min.z < m.box_max.z))
                        sink_.report("E306", r.span("box"), "medium: the box's minimum must be below its maximum on every axis");
                }
            }
        }
        scene.medium = m;
    }

    void read_material(ObjectReader& r, Scene& scene) {
        Material m;
        std::string type;
        r.string("name", m.name, true);
        if (r.string("type", type, true)) {
            auto t = material_type_from_name(type);
            if (!t) {
                sink_.report("E303", r.span("type"),
                             fmt::format("{}: unknown material type '{}'; expected one of void, plastic, metal, "
                                         "trans, glass, dielectric, mirror, light, glow, illum", r.path("type"), type));
                return;
            }
            m.type = *t;
        }
        r.warn_unknown({"name", "type", "color", "specularity", "roughness", "transmissivity", "transmitted_specular",
                        "ior", "glow_radius", "emission", "emission_sampled", "anisotropy", "spot", "outside", "alternate", "metallic", "opacity",
                        "alpha_mode", "alpha_cutoff", "specular_color", "normal_map", "bump_map", "thin", "patterns", "surface_functions", "directional_function", "redirections", "clips", "mixture"});
        bool emitter = m.type == MaterialType::kLight || m.type == MaterialType::kGlow || m.type == MaterialType::kIllum;
        MaterialTextures& tex = m.textures;
        // Reflectances above 1 create energy; radiances may be anything the image can hold.
        // Wherever a colour or a number goes, a texture reference (an object) may go instead.
        if (!texture_or(r, "color", tex.color)) r.vec3("color", m.color, emitter ? kRadiance : kUnit);
        if (!texture_or(r, "specularity", tex.specularity)) r.number("specularity", m.specularity, kUnit);
        if (!texture_or(r, "roughness", tex.roughness)) r.number("roughness", m.roughness, kUnit);
        if (!texture_or(r, "metallic", tex.metallic)) r.number("metallic", m.metallic, kUnit);
        if (!texture_or(r, "opacity", tex.opacity)) r.number("opacity", m.opacity, kUnit);
        r.number("transmissivity", m.transmissivity, kUnit);
        r.number("transmitted_specular", m.transmitted_specular, kUnit);
        r.number("ior", m.ior, kPositive);
        r.boolean("thin", m.thin_glass);  // glass: RADIANCE's pane, straight through
        r.number("glow_radius", m.glow_radius);  // negative: never lights the scene
        Vec3 e;
        if (!texture_or(r, "emission", tex.emission) && r.vec3("emission", e, kRadiance)) m.emission = e;
        r.boolean("emission_sampled", m.emission_sampled);
        if (r.has("anisotropy") && r.at("anisotropy").is_object()) {
            ObjectReader a(doc_, sink_, r.at("anisotropy"), r.pointer() + "/anisotropy");
            a.warn_unknown({"orientation", "roughness_v"});
            Anisotropy an;
            a.vec3("orientation", an.orientation, kAny, true);
            a.number("roughness_v", an.roughness_v, Range{0, 1, true, false}, true);
            if (!(length(an.orientation) > 0)) sink_.report("E306", a.span("orientation"), "anisotropy: the orientation vector is zero");
            m.anisotropy = an;
        } else if (r.has("anisotropy")) {
            r.wrong("anisotropy", "an object {\"orientation\": [x, y, z], \"roughness_v\": r}");
        }
        if (r.has("spot") && r.at("spot").is_object()) {
            ObjectReader a(doc_, sink_, r.at("spot"), r.pointer() + "/spot");
            a.warn_unknown({"angle", "direction"});
            Spot sp;
            a.number("angle", sp.angle_deg, Range{0, 360, true, false}, true);
            a.vec3("direction", sp.direction, kAny, true);
            if (!(length(sp.direction) > 0)) sink_.report("E306", a.span("direction"), "spot: the direction is zero");
            m.spot = sp;
        } else if (r.has("spot")) {
            r.wrong("spot", "an object {\"angle\": degrees, \"direction\": [x, y, z]}");
        }
        if (r.has("outside") && r.at("outside").is_object()) {
            ObjectReader a(doc_, sink_, r.at("outside"), r.pointer() + "/outside");
            a.warn_unknown({"color", "ior"});
            OutsideMedium o;
            a.vec3("color", o.color, kUnit);
            a.number("ior", o.ior, kPositive, true);
            m.outside = o;
        } else if (r.has("outside")) {
            r.wrong("outside", "an object {\"color\": [r, g, b], \"ior\": n}");
        }
        if (r.string("alternate", m.alternate) && !m.alternate.empty() && !material_names_.count(m.alternate))
            sink_.report("E305", r.span("alternate"), fmt::format("{}: no material named '{}' is defined before it", r.path("alternate"), m.alternate));
        texture_only(r, "specular_color", tex.specular_color);
        texture_only(r, "normal_map", tex.normal);
        texture_only(r, "bump_map", tex.bump);
        std::string mode;
        if (r.string("alpha_mode", mode)) {
            if (mode == "mask") m.alpha_mode = AlphaMode::kMask;
            else if (mode == "blend") m.alpha_mode = AlphaMode::kBlend;
            else sink_.report("E303", r.span("alpha_mode"), fmt::format("{}: expected \"mask\" or \"blend\", got \"{}\"", r.path("alpha_mode"), mode));
        }
        r.number("alpha_cutoff", m.alpha_cutoff, kUnit);
        if (r.has("patterns")) {
            // An emitter's patterns, as crex writes them for RADIANCE scenes (pattern_json.h).
            const nlohmann::json& a = r.at("patterns");
            std::string error;
            if (!a.is_array()) error = "expected an array of patterns";
            else if (!emitter && m.type != MaterialType::kPlastic && m.type != MaterialType::kMetal && m.type != MaterialType::kTrans &&
                     m.type != MaterialType::kMirror)
                error = "only a light, glow, illum, plastic, metal, trans or mirror takes patterns";
            for (size_t k = 0; error.empty() && k < a.size(); ++k) {
                FunctionPattern f;
                if (pattern_from_json(a[k], f, error)) m.patterns.push_back(std::move(f));
                else error = fmt::format("pattern {}: {}", k, error);
            }
            if (!error.empty()) sink_.report("E303", r.span("patterns"), fmt::format("{}: {}", r.path("patterns"), error));
        }
        if (r.has("surface_functions")) {
            SurfaceFunctions sf;
            std::string error;
            if (m.type != MaterialType::kTrans) error = "only a trans takes surface functions";
            else if (surface_functions_from_json(r.at("surface_functions"), sf, error)) m.surface_functions = std::move(sf);
            if (!error.empty()) sink_.report("E303", r.span("surface_functions"), fmt::format("{}: {}", r.path("surface_functions"), error));
        }
        if (r.has("directional_function")) {
            DirectionalFunction df;
            std::string error;
            if (m.type != MaterialType::kPlastic && m.type != MaterialType::kTrans) error = "only a plastic or trans takes a directional function";
            else if (directional_function_from_json(r.at("directional_function"), df, error)) m.directional = std::move(df);
            if (!error.empty())
                sink_.report("E303", r.span("directional_function"), fmt::format("{}: {}", r.path("directional_function"), error));
        }
        if (r.has("clips")) {
            // RADIANCE's antimatter: a void material naming the materials its solid removes.
            const nlohmann::json& c = r.at("clips");
            std::string error;
            if (m.type != MaterialType::kVoid) error = "only a void material clips";
            else if (!c.is_array() || c.empty()) error = "expected an array of material names";
            for (size_t k = 0; error.empty() && k < c.size(); ++k)
                if (!c[k].is_string() || !material_names_.count(c[k].get<std::string>()))
                    error = fmt::format("entry {} is not the name of a material defined before it", k);
            if (error.empty()) m.clips = c.get<std::vector<std::string>>();
            else sink_.report("E303", r.span("clips"), fmt::format("{}: {}", r.path("clips"), error));
        }
        if (r.has("redirections")) {
            std::vector<Redirection> rd;
            std::string error;
            if (m.type != MaterialType::kTrans) error = "only a trans takes redirections";
            else if (redirections_from_json(r.at("redirections"), rd, error)) m.redirections = std::move(rd);
            if (!error.empty()) sink_.report("E303", r.span("redirections"), fmt::format("{}: {}", r.path("redirections"), error));
        }
        if (r.has("mixture")) {
            // RADIANCE's mixfunc as crex writes it: {"background": material, "coefficient": pattern}.
            const nlohmann::json& x = r.at("mixture");
            Mixture mix;
            std::string error;
            if (!x.is_object() || !x.contains("background") || !x.at("background").is_string() || !x.contains("coefficient"))
                error = "expected {\"background\": material name, \"coefficient\": pattern}";
            else if (mix.background = x.at("background").get<std::string>(); !material_names_.count(mix.background))
                error = fmt::format("no material named '{}' is defined before it", mix.background);
            else if (pattern_from_json(x.at("coefficient"), mix.coefficient, error) && mix.coefficient.kind != FunctionPattern::Kind::kBrightFunc &&
                     mix.coefficient.kind != FunctionPattern::Kind::kBrightText)
                error = "the coefficient must be a brightfunc or a brighttext";
            if (error.empty()) m.mixture = std::move(mix);
            else sink_.report("E303", r.span("mixture"), fmt::format("{}: {}", r.path("mixture"), error));
        }
        if (emitter && tex.any())
            sink_.report("E307", r.span("type"), fmt::format("{}: a '{}' emitter takes constant values, not textures (give another "
                                                             "material an 'emission' texture instead)", r.path("type"), type));
        if (m.name.empty()) return;
        if (!material_names_.insert(m.name).second) {
            sink_.report("E305", r.span("name"), fmt::format("{}: a material named '{}' is already defined", r.path("name"), m.name));
            return;
        }
        scene.materials.push_back(m);
    }

    void read_distant_light(ObjectReader& r, Scene& scene) {
        r.warn_unknown({"name", "material", "direction", "angle", "sky"});
        DistantLight l;
        r.string("name", l.name);
        if (r.string("material", l.material, true) && !material_names_.count(l.material)) report_unknown_material(r, l.material);
        r.vec3("direction", l.direction, kAny, true);
        if (!(length(l.direction) > 0)) sink_.report("E306", r.span("direction"), fmt::format("{}: the direction is zero", r.path("direction")));
        r.number("angle", l.angle_deg, Range{0, 360, true, false}, true);
        if (r.has("sky") && r.at("sky").is_object()) {
            ObjectReader k(doc_, sink_, r.at("sky"), r.pointer() + "/sky");
            k.warn_unknown({"type", "zenith", "ground", "normalization", "sun"});
            SkyModel sky;
            std::string type;
            if (k.string("type", type, true)) {
                auto t = sky_type_from_name(type);
                if (!t)
                    sink_.report("E303", k.span("type"), fmt::format("{}: unknown sky type '{}'; expected clear, overcast, uniform or "
                                                                     "intermediate", k.path("type"), type));
                else
                    sky.type = *t;
            }
            k.number("zenith", sky.zenith, kNonNegative, true);
            k.number("ground", sky.ground, kNonNegative);
            k.number("normalization", sky.normalization, kPositive);
            k.vec3("sun", sky.sun);
            sky.sun = normalize_or_zero(sky.sun);
            if (sky.sun == Vec3{}) sink_.report("E306", k.span("sun"), "sky: the sun direction is zero");
            l.sky = sky;
        } else if (r.has("sky")) {
            r.wrong("sky", "an object");
        }
        scene.distant_lights.push_back(std::move(l));
    }

    // `key` holds a texture reference (an object): read it into `slot` and return true.
    bool texture_or(ObjectReader& r, const std::string& key, std::optional<TextureRef>& slot) {
        if (!r.has(key) || !r.at(key).is_object()) return false;
        slot = read_texture(r, key);
        return true;
    }

    // `key` may only hold a texture reference.
    void texture_only(ObjectReader& r, const std::string& key, std::optional<TextureRef>& slot) {
        if (!r.has(key)) return;
        if (!r.at(key).is_object()) {
            r.wrong(key, "a texture reference {\"file\": ...}");
            return;
        }
        slot = read_texture(r, key);
    }

    // A texture reference (docs/scene-format.md, "Textures").
    std::optional<TextureRef> read_texture(ObjectReader& parent, const std::string& key) {
        ObjectReader r(doc_, sink_, parent.at(key), parent.pointer() + "/" + key);
        r.warn_unknown({"file", "image", "color_space", "wrap", "scale", "power", "channel", "prefer_alpha", "uv_transform", "mapping", "planar"});
        TextureRef t;
        std::string file;
        if (r.has("file") == r.has("image")) {
            sink_.report("E304", doc_.span(r.pointer()), fmt::format("{}: give the texture's 'file' or the name of an embedded "
                                                                      "'image' (one of them)", readable_json_path(r.pointer())));
            return std::nullopt;
        }
        if (r.string("file", file)) {
            std::filesystem::path p(file);
            if (p.is_relative()) p = std::filesystem::path(base_dir_) / p;
            std::error_code ec;
            std::filesystem::path absolute = std::filesystem::absolute(p, ec);
            t.file = (ec ? p : absolute).lexically_normal().string();
            if (!std::filesystem::is_regular_file(t.file, ec))
                sink_.report("W310", r.span("file"), fmt::format("{}: cannot find the texture '{}': it renders magenta", r.path("file"), file));
        }
        if (r.string("image", t.image) && !image_names_.count(t.image))
            sink_.report("E305", r.span("image"), fmt::format("{}: no image named '{}' is defined in 'images'", r.path("image"), t.image));
        std::string name;
        if (r.string("color_space", name)) {
            if (auto c = texture_color_space_from_name(name)) t.color_space = *c;
            else sink_.report("E303", r.span("color_space"), fmt::format("{}: expected \"auto\", \"srgb\" or \"linear\", got \"{}\"", r.path("color_space"), name));
        }
        if (r.has("wrap")) read_wrap(r, t);
        if (r.string("filter", name)) {
            if (auto f = texture_filter_from_name(name)) t.filter = *f;
            else sink_.report("E303", r.span("filter"), fmt::format("{}: expected \"smooth\" or \"nearest\", got \"{}\"", r.path("filter"), name));
        }
        if (r.has("scale")) {
            double k;
            if (r.at("scale").is_number()) {
                if (r.number("scale", k, kNonNegative)) t.scale = {k, k, k};
            } else {
                r.vec3("scale", t.scale, kNonNegative);
            }
        }
        r.number("power", t.power, kPositive);
        r.integer("channel", t.channel, 0, 63);
        r.boolean("prefer_alpha", t.prefer_alpha);
        if (r.has("uv_transform")) read_uv_transform(r, t);
        if (r.string("mapping", name)) {
            if (auto m = texture_mapping_from_name(name)) t.mapping = *m;
            else sink_.report("E303", r.span("mapping"), fmt::format("{}: expected \"uv\" or \"planar\", got \"{}\"", r.path("mapping"), name));
        }
        if (r.has("planar")) {
            const json& p = r.at("planar");
            bool ok = p.is_array() && p.size() == 8;
            for (size_t i = 0; ok && i < 8; ++i) ok = p[i].is_number() && std::isfinite(p[i].get<double>());
            if (!ok) r.wrong("planar", "an array of 8 numbers [ux, uy, uz, u0, vx, vy, vz, v0]");
            else
                for (size_t i = 0; i < 8; ++i) t.planar[i] = p[i].get<double>();
        }
        return t;
    }

    void read_wrap(ObjectReader& r, TextureRef& t) {
        const json& w = r.at("wrap");
        auto one = [&](const json& v, TextureWrap& out) {
            auto x = v.is_string() ? texture_wrap_from_name(v.get<std::string>()) : std::nullopt;
            if (x) out = *x;
            return x.has_value();
        };
        bool ok = w.is_string() ? one(w, t.wrap_s) && one(w, t.wrap_t)
                                : w.is_array() && w.size() == 2 && one(w[0], t.wrap_s) && one(w[1], t.wrap_t);
        if (!ok)
            sink_.report("E303", r.span("wrap"), fmt::format("{}: expected \"repeat\", \"clamp\", \"mirror\" or \"black\" (or two of "
                                                             "them, for s and t), got {}", r.path("wrap"), json_shown(w)));
    }

    // {"offset": [u, v], "rotation": radians, "scale": [u, v]} (glTF's KHR_texture_transform),
    // or {"matrix": [a, b, c, d, e, f]}: s = a u + b v + c, t = d u + e v + f.
    void read_uv_transform(ObjectReader& parent, TextureRef& t) {
        if (!parent.at("uv_transform").is_object()) {
            parent.wrong("uv_transform", "an object {\"offset\": [u, v], \"rotation\": radians, \"scale\": [u, v]}");
            return;
        }
        ObjectReader r(doc_, sink_, parent.at("uv_transform"), parent.pointer() + "/uv_transform");
        r.warn_unknown({"offset", "rotation", "scale", "matrix"});
        auto pair = [&](const std::string& key, std::array<double, 2>& out) {
            if (!r.has(key)) return;
            const json& v = r.at(key);
            if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number() || !std::isfinite(v[0].get<double>()) ||
                !std::isfinite(v[1].get<double>())) {
                r.wrong(key, "an array of 2 numbers");
                return;
            }
            out = {v[0].get<double>(), v[1].get<double>()};
        };
        if (r.has("matrix")) {
            const json& v = r.at("matrix");
            bool ok = v.is_array() && v.size() == 6;
            for (size_t i = 0; ok && i < 6; ++i) ok = v[i].is_number() && std::isfinite(v[i].get<double>());
            if (!ok) r.wrong("matrix", "an array of 6 numbers [a, b, c, d, e, f]");
            else
                for (size_t i = 0; i < 6; ++i) t.uv_transform[i] = v[i].get<double>();
            return;
        }
        std::array<double, 2> offset{0, 0}, scale{1, 1};
        double rotation = 0;
        pair("offset", offset);
        pair("scale", scale);
        r.number("rotation", rotation);
        t.uv_transform = uv_transform_of(offset[0], offset[1], rotation, scale[0], scale[1]);
    }

    void read_shape(ObjectReader& r, Scene& scene) {
        Shape s;
        std::string type;
        if (!r.string("type", type, true)) return;
        auto t = shape_type_from_name(type);
        if (!t) {
            sink_.report("E303", r.span("type"), fmt::format("{}: unknown shape type '{}'; expected one of sphere, polygon, "
                                                              "mesh, box, ring, cone, cylinder", r.path("type"), type));
            return;
        }
        s.type = *t;
        r.string("name", s.name);
        if (r.string("material", s.material, s.type != ShapeType::kMesh || !r.has("file")) &&
            !material_names_.count(s.material))
            report_unknown_material(r, s.material);
        if (r.has("tag")) read_tag(r, s);
        switch (s.type) {
        case ShapeType::kSphere:
            r.warn_unknown({"type", "name", "material", "tag", "center", "radius", "inward"});
            r.boolean("inward", s.inward);
            r.vec3("center", s.center, kAny, true);
            r.number("radius", s.radius, kPositive, true);
            break;
        case ShapeType::kPolygon:
            r.warn_unknown({"type", "name", "material", "tag", "vertices"});
            r.vec3_list("vertices", s.vertices, true);
            break;
        case ShapeType::kBox:
            r.warn_unknown({"type", "name", "material", "tag", "min", "max"});
            r.vec3("min", s.min, kAny, true);
            r.vec3("max", s.max, kAny, true);
            break;
        case ShapeType::kRing:
            r.warn_unknown({"type", "name", "material", "tag", "center", "normal", "inner_radius", "outer_radius"});
            r.vec3("center", s.center, kAny, true);
            r.vec3("normal", s.normal, kAny, true);
            r.number("inner_radius", s.r0, kNonNegative);
            r.number("outer_radius", s.r1, kPositive, true);
            break;
        case ShapeType::kCone:
            r.warn_unknown({"type", "name", "material", "tag", "p0", "p1", "r0", "r1", "inward"});
            r.boolean("inward", s.inward);
            r.vec3("p0", s.p0, kAny, true);
            r.vec3("p1", s.p1, kAny, true);
            r.number("r0", s.r0, kNonNegative, true);
            r.number("r1", s.r1, kNonNegative, true);
            break;
        case ShapeType::kCylinder:
            r.warn_unknown({"type", "name", "material", "tag", "p0", "p1", "radius", "inward"});
            r.boolean("inward", s.inward);
            r.vec3("p0", s.p0, kAny, true);
            r.vec3("p1", s.p1, kAny, true);
            r.number("radius", s.radius, kPositive, true);
            break;
        case ShapeType::kMesh:
            r.warn_unknown({"type", "name", "material", "tag", "vertices", "triangles", "uvs", "normals", "colors", "file"});
            if (r.has("file")) {
                read_obj_mesh(r, s, scene);
                return;
            }
            r.vec3_list("vertices", s.vertices, true);
            read_triangles(r, s);
            read_uvs(r, s);
            if (r.vec3_list("normals", s.normals, false) && s.normals.size() != s.vertices.size())
                sink_.report("E303", r.span("normals"), fmt::format("{}: {} normals for {} vertices (give one per vertex)",
                                                                    r.path("normals"), s.normals.size(), s.vertices.size()));
            if (r.vec3_list("colors", s.colors, false)) {
                if (s.colors.size() != s.vertices.size())
                    sink_.report("E303", r.span("colors"), fmt::format("{}: {} vertex colours for {} vertices (give one per vertex)",
                                                                       r.path("colors"), s.colors.size(), s.vertices.size()));
                for (const Vec3& c : s.colors)
                    if (c.x < 0 || c.y < 0 || c.z < 0) {
                        sink_.report("E303", r.span("colors"), fmt::format("{}: a vertex colour is negative", r.path("colors")));
                        break;
                    }
            }
            break;
        }
        shape_index_.push_back(current_index_);
        scene.shapes.push_back(std::move(s));
    }

    void report_unknown_material(ObjectReader& r, const std::string& name) {
        Diagnostic& d = sink_.report("E305", r.span("material"),
                                     fmt::format("{}: no material named '{}' is defined", r.path("material"), name));
        d.help = did_you_mean(name, std::vector<std::string>(material_names_.begin(), material_names_.end()));
    }

    void read_tag(ObjectReader& r, Shape& s) {
        if (!r.at("tag").is_object()) {
            r.wrong("tag", "an object {\"name\": ..., \"task\": 0..3, \"distractor\": false}");
            return;
        }
        ObjectReader t(doc_, sink_, r.at("tag"), r.pointer() + "/tag");
        t.warn_unknown({"name", "task", "distractor"});
        Tag tag;
        t.string("name", tag.name, true);
        t.integer("task", tag.task, 0, 3);
        t.boolean("distractor", tag.distractor);
        s.tag = tag;
    }

    void read_triangles(ObjectReader& r, Shape& s) {
        if (!r.has("triangles")) {
            r.missing("triangles", "an array of [i, j, k] vertex indices");
            return;
        }
        const json& tris = r.at("triangles");
        if (!tris.is_array()) {
            r.wrong("triangles", "an array of [i, j, k] vertex indices");
            return;
        }
        for (size_t i = 0; i < tris.size(); ++i) {
            const json& t = tris[i];
            std::string ptr = r.pointer() + "/triangles/" + std::to_string(i);
            bool ok = t.is_array() && t.size() == 3;
            for (size_t k = 0; ok && k < 3; ++k) ok = t[k].is_number_unsigned();
            if (!ok) {
                sink_.report("E302", doc_.span(ptr), fmt::format("{}: expected [i, j, k] with vertex indices >= 0, got {}",
                                                                  readable_json_path(ptr), json_shown(t)));
                return;
            }
            std::array<uint32_t, 3> tri{};
            for (size_t k = 0; k < 3; ++k) {
                uint64_t idx = t[k].get<uint64_t>();
                if (idx >= s.vertices.size()) {
                    sink_.report("E303", doc_.span(ptr + "/" + std::to_string(k)),
                                 fmt::format("{}[{}]: vertex index {} out of range (the mesh has {} vertices)",
                                             readable_json_path(ptr), k, idx, s.vertices.size()));
                    return;
                }
                tri[k] = static_cast<uint32_t>(idx);
            }
            s.triangles.push_back(tri);
        }
    }

    // "uvs": one [u, v] per vertex.
    void read_uvs(ObjectReader& r, Shape& s) {
        if (!r.has("uvs")) return;
        const json& uvs = r.at("uvs");
        if (!uvs.is_array()) {
            r.wrong("uvs", "an array of [u, v], one per vertex");
            return;
        }
        for (size_t i = 0; i < uvs.size(); ++i) {
            const json& e = uvs[i];
            std::string ptr = r.pointer() + "/uvs/" + std::to_string(i);
            if (!e.is_array() || e.size() != 2 || !e[0].is_number() || !e[1].is_number() || !std::isfinite(e[0].get<double>()) ||
                !std::isfinite(e[1].get<double>())) {
                sink_.report("E302", doc_.span(ptr), fmt::format("{}: expected [u, v] (finite numbers), got {}", readable_json_path(ptr), json_shown(e)));
                s.uvs.clear();
                return;
            }
            s.uvs.push_back({e[0].get<double>(), e[1].get<double>()});
        }
        if (s.uvs.size() != s.vertices.size())
            sink_.report("E303", r.span("uvs"), fmt::format("{}: {} texture coordinates for {} vertices (give one per vertex)",
                                                            r.path("uvs"), s.uvs.size(), s.vertices.size()));
    }

    void read_obj_mesh(ObjectReader& r, Shape& s, Scene& scene) {
        std::string rel;
        if (!r.string("file", rel)) return;
        std::filesystem::path p = std::filesystem::path(base_dir_) / rel;
        DiagnosticSink obj_sink;
        auto obj = import_obj(p.string(), obj_sink, sources_);
        // Whether anything lights the scene is this file's question, asked of the whole scene:
        // the OBJ's own "no light" (W302) would be wrong when the file around it has the sky.
        for (const auto& d : obj_sink.diagnostics())
            if (d.code != "W302") sink_.add(d);
        if (!obj) {
            Diagnostic& d = sink_.report("E308", r.span("file"), fmt::format("{}: cannot load the mesh '{}'", r.path("file"), rel));
            if (obj_sink.diagnostics().empty()) d.help = "check that the file exists and is a Wavefront OBJ";
            return;
        }
        // One shape per OBJ material; an explicit "material" overrides the MTL ones.
        for (auto& m : obj->materials) {
            if (!s.material.empty()) break;
            if (material_names_.insert(m.name).second) scene.materials.push_back(m);
        }
        for (auto& part : obj->shapes) {
            part.file = rel;
            part.tag = s.tag;
            if (!s.name.empty()) part.name = s.name;
            if (!s.material.empty()) part.material = s.material;
            shape_index_.push_back(current_index_);
            scene.shapes.push_back(std::move(part));
        }
    }

    const PositionedJson& doc_;
    const SourceFile& file_;
    std::string base_dir_;
    SceneSources& sources_;
    DiagnosticSink& sink_;
    std::set<std::string> material_names_;
    std::set<std::string> image_names_;
    std::vector<size_t> shape_index_;  // scene shape -> index in the file's "shapes"
    size_t current_index_ = 0;
};

}  // namespace

std::optional<Scene> load_scene_json(const SourceFile& file, const std::string& base_dir, SceneSources& sources,
                                     DiagnosticSink& sink) {
    PositionedJson doc;
    if (!parse_json_with_positions(file, doc, sink, "E301")) return std::nullopt;
    return SceneJsonLoader(doc, file, base_dir, sources, sink).load();
}

}  // namespace crex
