// Wavefront OBJ (+ MTL) -> Scene, through Debian's tinyobjloader (double precision build).
// One mesh shape per (OBJ object, material), with its texture coordinates (vt) and normals
// (vn) when every face has them, and vertex colours (`v x y z r g b`, the extension MeshLab and
// most scanners write) when every vertex has them: they multiply the material's colour, as
// glTF's COLOR_0 does (imported_vertex_color). MTL parameters map onto our materials:
//   Ke > 0 (no map_Ke)              -> light (radiance Ke)
//   d < 1 (no map_d) or illum 4/6/7/9 -> glass (transmission Kd or Tf, ior Ni)
//   illum 3/5 with black Kd         -> mirror (Ks)
//   otherwise                       -> plastic: Kd, specularity from Ks, roughness from Ns
// and its textures (docs/scene-format.md has the table): map_Kd the colour, map_Ks the
// specular colour, map_Ns the roughness, map_d cut-outs, bump/map_Bump a bump map, norm a
// normal map, map_Ke an emission; paths relative to the MTL's folder; -o, -s, -clamp,
// -imfchan, -bm and -colorspace honoured. A texture that is not there is a warning at its
// MTL line, and renders magenta.
// A standalone OBJ gets a camera framing its bounds (frame_model).
#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <istream>
#include <streambuf>
#include <unordered_map>
#include <utility>

#include "base/input_file.h"
#include "runtime/base/sampling.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/model_defaults.h"
#include "runtime/scene/obj_checks.h"
#include "runtime/scene/shapes.h"

namespace crex {
namespace {

// Where an MTL's textures are found and its lines are (for locating missing ones).
struct MtlContext {
    std::string directory;              ///< the MTL's folder
    const SourceFile* file = nullptr;   ///< the MTL text, when it could be read
};

// The span of the first MTL line `keyword ... name` (for a texture that is not there).
SourceSpan texture_line(const MtlContext& mtl, const std::string& name) {
    if (!mtl.file) return {};
    for (uint32_t line = 1; line <= mtl.file->line_count(); ++line) {
        std::string_view t = mtl.file->line_text(line);
        if (t.find(name) != std::string_view::npos && t.find_first_not_of(" \t") != std::string_view::npos &&
            (t.find("map_") != std::string_view::npos || t.find("bump") != std::string_view::npos || t.find("norm") != std::string_view::npos)) {
            const uint32_t b = mtl.file->line_start(line);
            return {mtl.file, b, b + static_cast<uint32_t>(t.size())};
        }
    }
    return {mtl.file, 0, 0};
}

// What an MTL map gives: a colour (or a normal) reads its three channels from the first; a
// number reads the one -imfchan names.
enum class MtlMap { kColour, kScalar };

// An MTL texture statement (its name and options) as a texture reference: the path from the
// MTL's folder, OBJ's v flipped (t = 1 - v: OBJ's v runs up, images' t down), -o and -s as a
// uv transform, -clamp, -imfchan and -colorspace.
std::optional<TextureRef> mtl_texture(const std::string& name, const tinyobj::texture_option_t& opt, MtlMap map, const MtlContext& mtl,
                                      DiagnosticSink& sink) {
    if (name.empty()) return std::nullopt;
    TextureRef t;
    auto resolve = [&](const std::string& written) {
        std::filesystem::path p(written);
        if (p.is_relative()) p = std::filesystem::path(mtl.directory) / p;
        std::error_code ec;
        const auto absolute = std::filesystem::absolute(p, ec);
        return (ec ? p : absolute).lexically_normal().string();
    };
    t.file = resolve(name);
    std::error_code ec;
    // MTL files written on Windows name their maps with backslashes (".\wood.jpg"), which a
    // POSIX path keeps as part of the name: where that file is not there, the name read with
    // slashes is tried.
    if (!std::filesystem::is_regular_file(t.file, ec) && name.find('\\') != std::string::npos) {
        std::string slashed = name;
        std::replace(slashed.begin(), slashed.end(), '\\', '/');
        slashed = resolve(slashed);
        if (std::filesystem::is_regular_file(slashed, ec)) t.file = slashed;
    }
    if (!std::filesystem::is_regular_file(t.file, ec))
        sink.report("W310", texture_line(mtl, name), fmt::format("cannot find the texture '{}': it renders magenta", name));
    auto finite_or = [](double x, double fallback) { return std::isfinite(x) ? x : fallback; };
    const double su = finite_or(opt.scale[0], 1), sv = finite_or(opt.scale[1], 1);
    const double ou = finite_or(opt.origin_offset[0], 0), ov = finite_or(opt.origin_offset[1], 0);
    t.uv_transform = {su, 0, ou, 0, -sv, 1 - ov};
    if (opt.clamp) t.wrap_s = t.wrap_t = TextureWrap::kClamp;
    // -imfchan picks a scalar map's channel; tinyobjloader gives 'm' (matte) to every map not
    // a bump, whether written or not. Read as channel 3 it dropped every RGB map_Kd (W311) and
    // made an RGBA one grey with its alpha: 'm' is the alpha where the image has one, else its
    // first channel (a grey or RGB mask's value); 'l' (luminance) and 'z' read the first too.
    if (map == MtlMap::kScalar) {
        switch (opt.imfchan) {
        case 'g': t.channel = 1; break;
        case 'b': t.channel = 2; break;
        case 'm': t.prefer_alpha = true; break;
        default: break;
        }
    }
    if (opt.colorspace == "sRGB" || opt.colorspace == "srgb") t.color_space = TextureColorSpace::kSrgb;
    else if (opt.colorspace == "linear") t.color_space = TextureColorSpace::kLinear;
    return t;
}

Material convert_material(const tinyobj::material_t& m, const std::string& name, const MtlContext& mtl, DiagnosticSink& sink) {
    Material out;
    out.name = name;
    Vec3 kd{m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    Vec3 ks{m.specular[0], m.specular[1], m.specular[2]};
    Vec3 ke{m.emission[0], m.emission[1], m.emission[2]};
    auto clamp01 = [](Vec3 v) { return vmin(vmax(v, Vec3{0, 0, 0}), Vec3{1, 1, 1}); };
    const bool cut_out = !m.alpha_texname.empty();
    if (max_component(ke) > 0 && m.emissive_texname.empty()) {
        out.type = MaterialType::kLight;
        out.color = vmax(ke, Vec3{0, 0, 0});
        return out;  // an emitter: its textures do not apply
    }
    if ((m.dissolve < 1 && !cut_out) || m.illum == 4 || m.illum == 6 || m.illum == 7 || m.illum == 9) {
        out.type = MaterialType::kGlass;
        Vec3 tf{m.transmittance[0], m.transmittance[1], m.transmittance[2]};
        out.color = clamp01(max_component(tf) > 0 ? tf : Vec3{1, 1, 1});
        out.ior = m.ior > 0 ? m.ior : 1.5;
        if (!(m.ior > 0))
            sink.report("W311", mtl.file ? first_line_naming(*mtl.file, "newmtl", m.name, false) : SourceSpan{},
                        fmt::format("material '{}' is glass with Ni {:g}, which is not an index of refraction: it refracts as Ni 1.5",
                                    m.name, m.ior));
    } else if ((m.illum == 3 || m.illum == 5) && max_component(kd) <= 0 && m.diffuse_texname.empty()) {
        out.type = MaterialType::kMirror;
        out.color = clamp01(ks);
    } else {
        out.type = MaterialType::kPlastic;
        double d = max_component(kd), s = max_component(ks);
        out.specularity = d + s > 0 ? std::clamp(s / (d + s), 0.0, 1.0) : 0;
        // A specular map with Ks = 0 (some exporters write that): half of the light specular.
        if (!m.specular_texname.empty() && !(out.specularity > 0)) out.specularity = 0.5, ks = {1, 1, 1};
        out.color = clamp01(out.specularity < 1 ? kd / (1 - out.specularity) : kd);
        // Phong exponent -> roughness (the usual sqrt(2 / (Ns + 2)) mapping).
        out.roughness = out.specularity > 0 ? std::clamp(std::sqrt(2.0 / ((m.shininess > 0 ? double(m.shininess) : 0.0) + 2)), 0.0, 1.0) : 0;
    }
    MaterialTextures& tex = out.textures;
    // map_Kd multiplies Kd, so the diffuse lobe is Kd x texel; a Kd of 0 with a map (some
    // exporters write that) means the texture alone.
    if ((tex.color = mtl_texture(m.diffuse_texname, m.diffuse_texopt, MtlMap::kColour, mtl, sink)) && out.type == MaterialType::kPlastic)
        tex.color->scale = max_component(kd) > 0 ? out.color : Vec3{1, 1, 1} / (1 - std::min(out.specularity, 0.999));
    if ((tex.specular_color = mtl_texture(m.specular_texname, m.specular_texopt, MtlMap::kColour, mtl, sink)) && out.specularity > 0)
        tex.specular_color->scale = clamp01(ks / out.specularity);
    // map_Ns scales Ns: roughness = sqrt(2 / Ns) ~ (Ns texel / 2)^(-1/2).
    if ((tex.roughness = mtl_texture(m.specular_highlight_texname, m.specular_highlight_texopt, MtlMap::kScalar, mtl, sink))) {
        const double ns = m.shininess > 0 ? m.shininess : 1000;
        tex.roughness->scale = Vec3{1, 1, 1} * (ns / 2), tex.roughness->power = -0.5;
        tex.roughness->color_space = TextureColorSpace::kLinear;
    }
    if ((tex.opacity = mtl_texture(m.alpha_texname, m.alpha_texopt, MtlMap::kScalar, mtl, sink))) {
        tex.opacity->scale = Vec3{1, 1, 1} * std::clamp<double>(m.dissolve, 0, 1);
        tex.opacity->color_space = TextureColorSpace::kLinear;
    }
    // bump: height = texel x -bm x 1 cm (MTL heights have no unit; scenes are in metres by convention).
    if ((tex.bump = mtl_texture(m.bump_texname, m.bump_texopt, MtlMap::kScalar, mtl, sink))) {
        tex.bump->scale = Vec3{1, 1, 1} * (0.01 * (std::isfinite(m.bump_texopt.bump_multiplier) ? m.bump_texopt.bump_multiplier : 1.0));
        tex.bump->color_space = TextureColorSpace::kLinear;
    }
    if ((tex.normal = mtl_texture(m.normal_texname, m.normal_texopt, MtlMap::kColour, mtl, sink))) tex.normal->color_space = TextureColorSpace::kLinear;
    if ((tex.emission = mtl_texture(m.emissive_texname, m.emissive_texopt, MtlMap::kColour, mtl, sink)))
        tex.emission->scale = max_component(ke) > 0 ? vmax(ke, Vec3{}) : Vec3{1, 1, 1};
    if (out.type != MaterialType::kPlastic) {  // glass and mirrors: their colour and cut-outs only
        tex.specular_color.reset(), tex.roughness.reset();
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

// Where each object or group is named: the first `o NAME` or `g NAME` line of each name
// (tinyobjloader names a shape so), for locating what a mesh's check finds. One pass over
// the file, whatever the number of meshes.
std::map<std::string, SourceSpan, std::less<>> group_lines(const SourceFile& file) {
    std::map<std::string, SourceSpan, std::less<>> out;
    for (uint32_t line = 1; line <= file.line_count(); ++line) {
        const std::string_view t = file.line_text(line);
        std::optional<std::string_view> name = keyword_rest(t, "o");
        if (!name) name = keyword_rest(t, "g");
        if (!name) continue;
        const uint32_t b = file.line_start(line);
        out.try_emplace(std::string(*name), SourceSpan{&file, b, b + static_cast<uint32_t>(t.size())});
    }
    return out;
}

// Material names with blanks in them (LightWave and 3ds Max write them): tinyobjloader's
// `newmtl` keeps the whole name, its `usemtl` only the first word, so such a material was never
// found and its faces fell back to the default. Both are given the name trimmed, its blanks
// made kNameBlank, and the blanks are put back once the file is read. Lines keep their number.
constexpr char kNameBlank = '\x1f';

// The text with the names after `keyword` joined, or nullopt when none needs it (then the text
// is read as it is, not copied: a scanned mesh's OBJ is 100 MB). One pass, appending.
std::optional<std::string> joined_material_names(std::string_view text, std::string_view keyword) {
    std::optional<std::string> out;
    for (size_t line = 0; line < text.size();) {
        const size_t end = std::min(text.find('\n', line), text.size()), next = std::min(end + 1, text.size());
        const std::string_view t = text.substr(line, end - line);
        const size_t at = t.find_first_not_of(" \t"), k = at + keyword.size();
        std::string joined;
        if (at != std::string_view::npos && t.substr(at, keyword.size()) == keyword && k < t.size() && (t[k] == ' ' || t[k] == '\t')) {
            const size_t b = std::min(t.find_first_not_of(" \t", k), t.size());
            size_t e = t.size();
            while (e > b && (t[e - 1] == ' ' || t[e - 1] == '\t' || t[e - 1] == '\r')) --e;
            const std::string_view name = t.substr(b, e - b);
            // The leading blanks go too (tinyobjloader's newmtl would keep them): "usemtl  a" names "a".
            if (b > k + 1 || name.find_first_of(" \t") != std::string_view::npos) {
                joined = std::string(t.substr(0, k + 1)) + std::string(name);
                std::replace_if(joined.begin() + static_cast<std::ptrdiff_t>(k + 1), joined.end(), [](char c) { return c == ' ' || c == '\t'; },
                                kNameBlank);
                if (!out) out.emplace().reserve(text.size()), out->append(text.substr(0, line));
            }
        }
        if (out) out->append(joined.empty() ? t : std::string_view(joined)), out->append(text.substr(end, next - end));
        line = next;
    }
    return out;
}

// An input stream over text held elsewhere (no copy).
class TextStream final : public std::streambuf {
public:
    explicit TextStream(std::string_view text) {
        char* p = const_cast<char*>(text.data());  // read only: the get area is never written
        setg(p, p, p + text.size());
    }
};

std::string with_blanks(std::string name) {
    std::replace(name.begin(), name.end(), kNameBlank, ' ');
    return name;
}

// The MTL files tinyobjloader asks for, from the texts read and checked already (by the path
// `mtllib` names, relative to the OBJ's folder), their material names joined. A name crex's
// reading of `mtllib` did not make (tinyobjloader reads "my\ mats.mtl" as one file with a
// blank) is read here the same way: bounded, a regular file, its values checked into `sink`.
class MtlTexts final : public tinyobj::MaterialReader {
public:
    MtlTexts(std::string dir, SceneSources& sources, DiagnosticSink& sink) : dir_(std::move(dir)), sources_(sources), sink_(sink) {}
    void add(const std::string& path, const SourceFile& text) { texts_[path] = &text; }
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials, std::map<std::string, int>* names,
                    std::string* warn, std::string* err) override {
        const std::string path = (std::filesystem::path(dir_) / name).string();
        auto it = texts_.find(path);
        if (it == texts_.end()) {
            std::string error;
            std::error_code ec;
            auto text = std::filesystem::exists(path, ec) ? read_input_file(path, error, kMaxDataInputBytes) : std::nullopt;
            if (!text) {
                if (warn) *warn += fmt::format("Material file [ {} ] not found in a path : {}{}\n", name, dir_, error.empty() ? "" : " (" + error + ")");
                return false;
            }
            const SourceFile& file = sources_.add(path, std::move(*text));
            check_mtl_text(file, sink_);
            it = texts_.emplace(path, &file).first;
        }
        const std::optional<std::string> joined = joined_material_names(it->second->text(), "newmtl");
        TextStream buffer(joined ? std::string_view(*joined) : std::string_view(it->second->text()));
        std::istream in(&buffer);
        tinyobj::LoadMtl(names, materials, &in, warn, err);
        return true;
    }

private:
    std::string dir_;
    SceneSources& sources_;
    DiagnosticSink& sink_;
    std::map<std::string, const SourceFile*> texts_;
};

// A face corner's three indices, mixed.
struct CornerHash {
    size_t operator()(const std::array<int, 3>& c) const {
        const uint64_t first_two = static_cast<uint64_t>(static_cast<uint32_t>(c[0])) << 32 | static_cast<uint32_t>(c[1]);
        return static_cast<size_t>(hash_combine(first_two, static_cast<uint32_t>(c[2])));
    }
};

}  // namespace

std::optional<Scene> import_obj(const std::string& path, DiagnosticSink& sink, SceneSources& sources) {
    std::string error;
    auto text = read_input_file(path, error, kMaxDataInputBytes);  // a regular file, bounded
    const SourceFile& file = sources.add(path, text ? std::move(*text) : std::string());
    if (!text) {
        sink.report("E308", {&file, 0, 0}, error);
        return std::nullopt;
    }
    // UTF-16 (a byte-order mark): tinyobjloader reads no line of it, and "no triangles" hid why.
    if (const std::string_view t = file.text(); t.size() >= 2 && (t.substr(0, 2) == "\xFE\xFF" || t.substr(0, 2) == "\xFF\xFE")) {
        sink.report("E308", {&file, 0, 0}, fmt::format("cannot read OBJ '{}': it is UTF-16 text; crex reads OBJ in ASCII or UTF-8", path))
            .help = "save it as UTF-8 (iconv -f UTF-16 -t UTF-8)";
        return std::nullopt;
    }
    // Its text and its MTL files' values first (obj_checks.h): tinyobjloader reads them silently.
    const size_t errors_first = sink.error_count();
    check_obj_text(file, sink);
    // The first MTL's folder is where its textures are looked for; its text locates them.
    MtlContext mtl_context{std::filesystem::path(path).parent_path().string(), nullptr};
    MtlTexts mtl_texts(std::filesystem::path(path).parent_path().string(), sources, sink);
    bool first_library = true;
    for (const auto& lib : material_libraries(file, std::filesystem::path(path).parent_path().string())) {
        if (first_library) mtl_context.directory = std::filesystem::path(lib.path).parent_path().string();
        const bool first = std::exchange(first_library, false);
        std::error_code ec;
        if (!std::filesystem::exists(lib.path, ec)) continue;  // tinyobjloader warns (W301)
        auto mtl = read_input_file(lib.path, error, kMaxDataInputBytes);
        if (!mtl) {
            sink.report("E308", lib.named_at, error);
            continue;
        }
        const SourceFile& mtl_file = sources.add(lib.path, std::move(*mtl));
        if (first) mtl_context.file = &mtl_file;
        mtl_texts.add(lib.path, mtl_file);
        check_mtl_text(mtl_file, sink);
    }
    if (sink.error_count() != errors_first) return std::nullopt;
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> obj_shapes;
    std::vector<tinyobj::material_t> obj_materials;
    std::string obj_warnings, obj_errors;
    const std::optional<std::string> joined = joined_material_names(file.text(), "usemtl");
    TextStream obj_buffer(joined ? std::string_view(*joined) : std::string_view(file.text()));
    std::istream obj_text(&obj_buffer);
    // Triangulated; vertex colours only when every `v` line has them (no white fill).
    const bool ok = tinyobj::LoadObj(&attrib, &obj_shapes, &obj_materials, &obj_warnings, &obj_errors, &obj_text, &mtl_texts, true, false);
    report_obj_messages(with_blanks(obj_warnings), file, "W301", sink);
    if (!ok) {
        if (obj_errors.find_first_not_of(" \n") == std::string::npos)
            sink.report("E308", {&file, 0, 0}, fmt::format("cannot read OBJ '{}': malformed file", path));
        report_obj_messages(with_blanks(obj_errors), file, "E308", sink);
        return std::nullopt;
    }
    if (sink.error_count() != errors_first) return std::nullopt;  // an MTL read while reading it had bad values
    for (auto& m : obj_materials) m.name = with_blanks(m.name);
    size_t errors_before = sink.error_count();
    std::vector<Vec3> positions;
    positions.reserve(attrib.vertices.size() / 3);
    for (size_t i = 0; i + 2 < attrib.vertices.size(); i += 3) {
        Vec3 v{attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]};
        if (!is_finite(v)) sink.report("E303", nth_line(file, "v ", i / 3), fmt::format("vertex {} has a non-finite coordinate", i / 3 + 1));
        positions.push_back(v);
    }
    if (sink.error_count() != errors_before) return std::nullopt;

    // tinyobjloader keeps colours only when every vertex line has three after its position.
    const bool colored = !attrib.colors.empty() && attrib.colors.size() == attrib.vertices.size();

    Scene scene;
    scene.source = path;
    std::string stem = std::filesystem::path(path).stem().string();
    std::vector<std::string> material_names;
    const MtlContext& mtl = mtl_context;
    for (const auto& m : obj_materials) {
        std::string name = stem + "/" + m.name;
        material_names.push_back(name);
        scene.materials.push_back(convert_material(m, name, mtl, sink));
    }
    std::string fallback = stem + "/default";
    bool fallback_used = false;

    // A face corner (material, position, texture coordinate, normal) -> its mesh's vertex: the
    // first corner met at each position in `first_use` (stamped with its shape), any other in
    // a hash map. An ordered map of every corner was a fifth of loading a 2M-triangle OBJ.
    struct FirstUse {
        uint32_t shape = 0;  // 1 + the shape's index; 0: none yet
        int material = 0, uv = 0, normal = 0;
        uint32_t vertex = 0;
    };
    std::vector<FirstUse> first_use(positions.size());
    uint32_t shape_stamp = 0;
    for (const auto& shape : obj_shapes) {
        ++shape_stamp;
        std::map<int, Shape> by_material;  // material id -> mesh
        std::map<int, std::unordered_map<std::array<int, 3>, uint32_t, CornerHash>> remap;  // the corners after the first at a position
        std::map<int, bool> all_uvs, all_normals;  // does every corner of the mesh have them?
        size_t offset = 0;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            size_t n = shape.mesh.num_face_vertices[f];
            int mid = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
            if (mid >= static_cast<int>(material_names.size())) mid = -1;
            Shape& mesh = by_material[mid];
            all_uvs.try_emplace(mid, true), all_normals.try_emplace(mid, true);
            if (n == 3) {
                std::array<uint32_t, 3> tri{};
                bool valid = true;
                for (size_t k = 0; k < 3; ++k) {
                    const tinyobj::index_t& index = shape.mesh.indices[offset + k];
                    const int vi = index.vertex_index;
                    if (vi < 0 || static_cast<size_t>(vi) >= positions.size()) {
                        valid = false;
                        break;
                    }
                    const int ti = index.texcoord_index >= 0 && 2 * size_t(index.texcoord_index) + 1 < attrib.texcoords.size() ? index.texcoord_index : -1;
                    const int ni = index.normal_index >= 0 && 3 * size_t(index.normal_index) + 2 < attrib.normals.size() ? index.normal_index : -1;
                    all_uvs[mid] = all_uvs[mid] && ti >= 0;
                    all_normals[mid] = all_normals[mid] && ni >= 0;
                    const uint32_t next = static_cast<uint32_t>(mesh.vertices.size());
                    FirstUse& use = first_use[static_cast<size_t>(vi)];
                    bool fresh = false;
                    if (use.shape != shape_stamp) {
                        use = {shape_stamp, mid, ti, ni, next};
                        fresh = true;
                    }
                    uint32_t vertex = use.vertex;
                    if (!fresh && (use.material != mid || use.uv != ti || use.normal != ni)) {
                        const auto [it, added] = remap[mid].try_emplace({vi, ti, ni}, next);
                        fresh = added, vertex = it->second;
                    }
                    if (fresh) {
                        mesh.vertices.push_back(positions[static_cast<size_t>(vi)]);
                        const size_t t = static_cast<size_t>(std::max(ti, 0)), nn = static_cast<size_t>(std::max(ni, 0));
                        mesh.uvs.push_back(ti >= 0 ? std::array<double, 2>{attrib.texcoords[2 * t], attrib.texcoords[2 * t + 1]} : std::array<double, 2>{0, 0});
                        mesh.normals.push_back(ni >= 0 ? Vec3{attrib.normals[3 * nn], attrib.normals[3 * nn + 1], attrib.normals[3 * nn + 2]} : Vec3{});
                        if (colored) {
                            const size_t c = 3 * static_cast<size_t>(vi);
                            mesh.colors.push_back(imported_vertex_color(attrib.colors[c], attrib.colors[c + 1], attrib.colors[c + 2]));
                        }
                    }
                    tri[k] = vertex;
                }
                if (valid) mesh.triangles.push_back(tri);
            }
            offset += n;
        }
        for (auto& [mid, mesh] : by_material) {
            if (mesh.triangles.empty()) continue;
            // Texture coordinates and normals only when every corner has them (and they are usable).
            bool uvs_ok = all_uvs[mid], normals_ok = all_normals[mid];
            for (const auto& uv : mesh.uvs) uvs_ok = uvs_ok && std::isfinite(uv[0]) && std::isfinite(uv[1]);
            for (const auto& nv : mesh.normals) normals_ok = normals_ok && is_finite(nv) && length(nv) > 0;
            if (!uvs_ok) mesh.uvs.clear();
            if (!normals_ok) mesh.normals.clear();
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
    frame_model(scene);
    std::optional<std::map<std::string, SourceSpan, std::less<>>> groups;  // made when a mesh is said
    validate_scene(scene, sink, [&](size_t i) {
        if (i >= scene.shapes.size()) return SourceSpan{&file, 0, 0};
        if (!groups) groups = group_lines(file);
        const auto it = groups->find(scene.shapes[i].name);
        return it != groups->end() ? it->second : SourceSpan{&file, 0, 0};
    });
    if (sink.error_count() != errors_before) return std::nullopt;
    return scene;
}

}  // namespace crex
