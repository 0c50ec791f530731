// RADIANCE's patterns on emitters -> crex's FunctionPattern (scene.h): which patterns, their
// function files, data and pictures found and checked where they are written, so that a
// render never meets a name it cannot evaluate.
#include <fmt/format.h>

#include <filesystem>
#include <set>

#include "base/input_file.h"
#include "runtime/scene/material.h"
#include "runtime/scene/text_pattern.h"

#include "runtime/scene/radiance/calc.h"
#include "runtime/scene/radiance/data_file.h"
#include "runtime/scene/radiance/generators.h"
#include "runtime/scene/radiance/library_files.h"
#include "runtime/scene/radiance/scene_builder.h"

namespace crex::radiance {
namespace {

// What a pattern's expressions may read of the ray (RADIANCE's rayinit.cal), beside their
// real arguments (A1.., AC) and what their file defines.
const std::set<std::string>& ray_variables() {
    static const std::set<std::string> v{"Dx", "Dy", "Dz", "Nx", "Ny", "Nz", "Px", "Py", "Pz", "T", "Ts", "Rdot", "S", "Tx", "Ty",
                                         "Tz", "Ix", "Iy", "Iz", "Jx", "Jy", "Jz", "Kx", "Ky", "Kz", "NxP", "NyP", "NzP", "RdotP",
                                         "CrP", "CgP", "CbP", "Lu", "Lv", "Lx_crex", "Ly_crex", "Lz_crex",
                                         "DxA", "DyA", "DzA"};
    return v;
}

bool is_argument_name(const std::string& n) {
    if (n == "AC") return true;
    return n.size() >= 2 && n[0] == 'A' && n.find_first_not_of("0123456789", 1) == std::string::npos;
}

// A function or data file, bounded (never /dev/zero or a FIFO).
std::string read_text(const std::string& path, bool& ok) {
    std::string error;
    std::optional<std::string> text = read_input_file(path, error, kMaxDataInputBytes);
    ok = text.has_value();
    return text ? std::move(*text) : std::string();
}

}  // namespace

bool SceneBuilder::is_emitter_pattern(const std::string& type) {
    return type == "brightfunc" || type == "colorfunc" || type == "brightdata" || type == "colordata" || type == "colorpict" ||
           type == "brighttext" || type == "colortext";
}

bool SceneBuilder::text_of(const Primitive& p, size_t font_at, FunctionPattern& out) {
    // The font file, then a text file, or '.' and the words of one line.
    const std::string& t = p.type.text;
    if (p.strings.size() < font_at + 2) {
        report("E303", p.type.span, fmt::format("{} '{}' needs a font file and a text file (or '.' and the text) as string arguments",
                                                t, p.id.text), &p);
        return false;
    }
    auto read = [&](const Word& w, const char* what, std::string& text) {
        const std::string path = find_named_file(w);
        bool ok = false;
        if (!path.empty()) text = read_text(path, ok);
        if (!ok)
            report("E308", w.span, fmt::format("{} '{}': cannot read the {} '{}'", t, p.id.text, what, w.text), &p).help =
                "it is looked for next to the file that names it, then in the RAYPATH directories (RADIANCE's library, where its "
                "fonts are)";
        return ok;
    };
    const Word& font = p.strings[font_at];
    if (!read(font, "font file", out.font)) return false;
    Font parsed;
    std::string error;
    if (!parse_font(out.font, parsed, error)) {
        report("E302", font.span, fmt::format("{} '{}': the font file '{}', {}", t, p.id.text, font.text, error), &p);
        return false;
    }
    out.text.clear();
    if (p.strings.size() > font_at + 2) {
        std::string line;
        for (size_t i = font_at + 2; i < p.strings.size(); ++i) line += (line.empty() ? "" : " ") + p.strings[i].text;
        out.text.push_back(std::move(line));
    } else {
        std::string text;
        if (!read(p.strings[font_at + 1], "text file", text)) return false;
        size_t begin = 0;
        while (begin < text.size()) {
            size_t end = text.find('\n', begin);
            if (end == std::string::npos) end = text.size();
            out.text.push_back(text.substr(begin, end - begin));
            begin = end + 1;
        }
    }
    return true;
}

std::string SceneBuilder::find_named_file(const Word& name) const {
    const std::string dir = name.span.file ? std::filesystem::path(name.span.file->name()).parent_path().string() : "";
    return find_file(name.text, dir, library_dirs_);
}

std::optional<std::string> SceneBuilder::function_file_text(const Word& file, const Primitive& p) {
    if (file.text == ".") return std::string();
    const std::string path = find_named_file(file);
    bool ok = false;
    std::string text = path.empty() ? std::string() : read_text(path, ok);
    if (!ok) {
        if (auto builtin = builtin_function_file(file.text)) return *builtin;
        report("E308", file.span, fmt::format("cannot read the function file '{}'", file.text), &p).help =
            "it is looked for next to the file that names it, then in the RAYPATH directories";
        return std::nullopt;
    }
    return text;
}

std::optional<FunctionPattern> SceneBuilder::pattern_of(const Definition& d) {
    const Primitive& p = d.p;
    const std::string& t = p.type.text;
    using K = FunctionPattern::Kind;
    FunctionPattern out;
    out.name = p.id.text;
    if (t == "brighttext" || t == "colortext") {
        // Reals: the origin, right and down vectors, the inside and outside colours, [spacing].
        out.kind = t == "brighttext" ? K::kBrightText : K::kColorText;
        const size_t n = t == "brighttext" ? 11 : 15;
        if (p.reals.size() != n && p.reals.size() != n + 1) {
            report("E303", p.reals_span(), fmt::format("{} '{}' takes {} or {} real arguments (origin, right, down, the colours inside "
                                                       "and outside the letters, [spacing]), got {}", t, p.id.text, n, n + 1, p.reals.size()), &p);
            return std::nullopt;
        }
        out.args = p.reals;
        if (!text_of(p, 0, out)) return std::nullopt;
        return out;
    }
    out.kind = t == "brightfunc" ? K::kBrightFunc : t == "colorfunc" ? K::kColorFunc : t == "brightdata" ? K::kBrightData
             : t == "colordata" ? K::kColorData : K::kColorPict;
    // Where each kind keeps its functions, data or picture, file and coordinates.
    const size_t functions = out.kind == K::kBrightFunc || out.kind == K::kBrightData ? 1 : 3;
    const size_t data_files = out.kind == K::kBrightData ? 1 : out.kind == K::kColorData ? 3 : 0;
    const size_t pictures = out.kind == K::kColorPict ? 1 : 0;
    const size_t file_at = functions + data_files + pictures;
    const size_t fixed = file_at + 1;
    if (p.strings.size() < fixed) {
        report("E303", p.type.span, fmt::format("{} '{}' needs at least {} string arguments, got {}", t, p.id.text, fixed, p.strings.size()), &p);
        return std::nullopt;
    }
    for (size_t i = 0; i < functions; ++i) out.functions.push_back(p.strings[i].text);
    out.args = p.reals;

    for (size_t i = 0; i < data_files; ++i) {
        const Word& w = p.strings[functions + i];
        const std::string path = find_named_file(w);
        bool ok = false;
        const std::string text = path.empty() ? std::string() : read_text(path, ok);
        if (!ok) {
            report("E308", w.span, fmt::format("{} '{}': cannot read the data file '{}'", t, p.id.text, w.text), &p);
            return std::nullopt;
        }
        DataTable table;
        DataFileError e;
        if (!parse_data_file(text, table, e)) {
            report("E301", w.span, fmt::format("{} '{}': the data file '{}' is malformed at line {}, column {}: {}", t, p.id.text, w.text,
                                               e.line, e.column, e.message), &p);
            return std::nullopt;
        }
        if (!out.tables.empty() && table.axes.size() != out.tables.front().axes.size()) {
            report("E303", w.span, fmt::format("{} '{}': the data file '{}' has {} dimensions, the first has {}", t, p.id.text, w.text,
                                               table.axes.size(), out.tables.front().axes.size()), &p);
            return std::nullopt;
        }
        out.tables.push_back(std::move(table));
    }
    if (pictures) {
        const Word& w = p.strings[functions];
        out.picture = find_named_file(w);
        if (out.picture.empty()) {
            report("E308", w.span, fmt::format("{} '{}': cannot find the picture '{}'", t, p.id.text, w.text), &p).help =
                "it is looked for next to the file that names it, then in the RAYPATH directories";
            return std::nullopt;
        }
        out.picture = std::filesystem::absolute(out.picture).lexically_normal().string();
    }
    // The coordinates: one per data dimension, two for a picture, none for a function.
    const size_t coordinates = data_files ? out.tables.front().axes.size() : pictures ? 2 : 0;
    if (p.strings.size() < fixed + coordinates) {
        report("E303", p.type.span, fmt::format("{} '{}' needs {} coordinate expressions after its function file, got {}", t, p.id.text,
                                                coordinates, p.strings.size() - fixed), &p);
        return std::nullopt;
    }
    for (size_t i = 0; i < coordinates; ++i) {
        const Word& w = p.strings[fixed + i];
        if (is_transform_option(w.text)) {
            report("E303", w.span, fmt::format("{} '{}' needs {} coordinate expressions after its function file, got {}", t, p.id.text,
                                               coordinates, i), &p);
            return std::nullopt;
        }
        out.coordinates.push_back(w.text);
    }

    std::vector<size_t> expressions, names;
    for (size_t i = 0; i < functions; ++i) (data_files || pictures ? names : expressions).push_back(i);
    for (size_t i = 0; i < coordinates; ++i) expressions.push_back(fixed + i);
    if (!complete_functions(p, out, file_at, expressions, names, fixed + coordinates)) return std::nullopt;
    return out;
}

bool SceneBuilder::complete_functions(const Primitive& p, FunctionPattern& out, size_t file_at, const std::vector<size_t>& expressions,
                                      const std::vector<size_t>& names, size_t transform_at) {
    const std::string& t = p.type.text;
    using K = FunctionPattern::Kind;
    std::optional<std::string> definitions = function_file_text(p.strings[file_at], p);
    if (!definitions) return false;
    calc::Program program;
    calc::Error e;
    if (!program.define(*definitions, e)) {
        report("E302", p.strings[file_at].span, fmt::format("function file '{}': {}", p.strings[file_at].text, e.message), &p);
        return false;
    }
    out.definitions = std::move(*definitions);
    // Every expression parses, and names nothing the ray, the arguments or the file lack.
    auto check = [&](const Word& w, bool function_name) {
        calc::Error pe;
        if (function_name) {
            const size_t n = out.kind == K::kBrightData ? 1 : 3;
            if (program.takes(w.text, 1) || program.takes(w.text, n) || (out.kind != K::kBrightData && program.has_variable(w.text)))
                return true;
            report("E307", w.span, fmt::format("{} '{}': '{}' is not a function of {} of this file or RADIANCE's library", t,
                                               p.id.text, w.text, n == 1 ? "one argument" : "one or three arguments"), &p);
            return false;
        }
        auto expr = program.parse(w.text, pe);
        if (!expr) {
            report("E302", w.span, fmt::format("{} '{}': {}", t, p.id.text, pe.message), &p);
            return false;
        }
        for (const std::string& f : program.unknown_functions(*expr)) {
            report("E307", w.span, fmt::format("{} '{}': '{}' calls the function '{}', which neither its file nor crex's library "
                                               "defines", t, p.id.text, w.text, f), &p);
            return false;
        }
        for (const std::string& n : program.free_names(*expr))
            if (!ray_variables().count(n) && !is_argument_name(n)) {
                report("E307", w.span, fmt::format("{} '{}': '{}' uses '{}', which neither its file nor the ray defines", t, p.id.text,
                                                   w.text, n), &p);
                return false;
            }
        return true;
    };
    for (size_t i : names)
        if (!check(p.strings[i], true)) return false;
    for (size_t i : expressions)
        if (!check(p.strings[i], false)) return false;

    // The transform that placed the pattern, inverted: world -> pattern coordinates.
    std::optional<Transform> xf = function_transform(p, transform_at);
    if (!xf) return false;
    const double s = std::fabs(xf->scale());
    if (!(s > 0) || !std::isfinite(s)) {
        report("E303", p.strings.back().span, fmt::format("{} '{}': its transform scales by {:g}", t, p.id.text, xf->scale()), &p);
        return false;
    }
    const Vec3 origin = xf->point({0, 0, 0});
    const Vec3 axes[3] = {xf->vector({1, 0, 0}), xf->vector({0, 1, 0}), xf->vector({0, 0, 1})};
    for (int k = 0; k < 3; ++k) {
        const Vec3 row = axes[k] / (s * s);
        out.to_pattern[static_cast<size_t>(4 * k)] = row.x;
        out.to_pattern[static_cast<size_t>(4 * k + 1)] = row.y;
        out.to_pattern[static_cast<size_t>(4 * k + 2)] = row.z;
        out.to_pattern[static_cast<size_t>(4 * k + 3)] = -dot(origin, row);
    }
    out.scale = 1 / s;
    return true;
}

bool SceneBuilder::patterns_of(const Definition& d, const Primitive& user, std::vector<FunctionPattern>& out) {
    // The chain of modifiers below the material, nearest first; each must be a pattern crex
    // evaluates.
    for (const Definition* m = d.modifier.get(); m; m = m->modifier.get()) {
        if (!is_emitter_pattern(m->p.type.text)) {
            refuse(d, d.p.modifier.span, user, fmt::format("{} '{}' is modified by the {} '{}': crex evaluates the patterns "
                                        "brightfunc, colorfunc, brightdata, colordata and colorpict only",
                                        d.p.type.text, d.p.id.text, m->p.type.text, m->p.id.text));
            return false;
        }
        std::optional<FunctionPattern> f = pattern_of(*m);
        if (!f) return false;
        out.push_back(std::move(*f));
    }
    return true;
}

std::optional<Material> SceneBuilder::brtd_function(const Definition& d, const Primitive& user) {
    // 10 strings: specular reflectance r g b, specular transmittance r g b, the
    // directional-diffuse functions r g b, the function file; then its transform. 9+ reals:
    // diffuse reflectance of the front, of the back, diffuse transmittance (then A10.. for
    // the expressions).
    const Primitive& p = d.p;
    if (p.strings.size() < 10 || p.reals.size() < 9) {
        report("E303", p.type.span, fmt::format("BRTDfunc '{}' needs 10 string and 9 real arguments, got {} and {}", p.id.text,
                                                p.strings.size(), p.reals.size()), &p);
        return std::nullopt;
    }
    for (size_t i = 6; i < 9; ++i)
        if (p.strings[i].text != "0") {
            refuse(d, p.strings[i].span, user, fmt::format("BRTDfunc '{}': its directional-diffuse function '{}' is not supported (crex "
                                                           "renders BRTDfunc's specular and diffuse parts)", p.id.text, p.strings[i].text),
                   "write 0 for the three directional-diffuse functions");
            return std::nullopt;
        }
    SurfaceFunctions sf;
    for (int part = 0; part < 2; ++part) {
        FunctionPattern& f = part == 0 ? sf.reflection : sf.transmission;
        f.kind = FunctionPattern::Kind::kColorFunc;
        f.name = p.id.text;
        f.args = p.reals;
        for (size_t i = 0; i < 3; ++i) f.functions.push_back(p.strings[3 * static_cast<size_t>(part) + i].text);
        const std::vector<size_t> expressions = part == 0 ? std::vector<size_t>{0, 1, 2} : std::vector<size_t>{3, 4, 5};
        if (!complete_functions(p, f, 9, expressions, {}, 10)) return std::nullopt;
    }
    const std::vector<double>& r = p.reals;
    for (size_t i = 0; i < 9; ++i)
        if (!(r[i] >= 0 && r[i] <= 1)) {
            report("E303", p.real_spans[i], fmt::format("BRTDfunc '{}': a diffuse reflectance or transmittance must be in [0, 1], got {:g}",
                                                        p.id.text, r[i]), &p);
            return std::nullopt;
        }
    sf.front_diffuse = {r[0], r[1], r[2]};
    sf.back_diffuse = {r[3], r[4], r[5]};
    sf.diffuse_transmit = {r[6], r[7], r[8]};
    Material m;
    m.type = MaterialType::kTrans;
    // The constants say which lobes there may be (the census, the planner); the functions give
    // their weights at each hit.
    m.color = {1, 1, 1};
    m.specularity = 0.5;
    m.roughness = 0;
    m.transmissivity = 0.5;
    m.transmitted_specular = max_component(sf.diffuse_transmit) > 0 ? 0.5 : 1.0;
    m.surface_functions = std::move(sf);
    return m;
}

std::optional<Material> SceneBuilder::redirecting(const Definition& d, const Primitive& user) {
    // prism1: coef dx dy dz funcfile [transform]; prism2: coef1 dx1 dy1 dz1 coef2 dx2 dy2 dz2
    // funcfile [transform]. Expressions of the ray (RADIANCE's DxA.. are 0: no virtual sources).
    const Primitive& p = d.p;
    const std::string& t = p.type.text;
    const size_t parts = t == "prism2" ? 2 : 1, file_at = 4 * parts;
    if (p.strings.size() < file_at + 1) {
        report("E303", p.type.span, fmt::format("{} '{}' needs {} string arguments ({}function file), got {}", t, p.id.text, file_at + 1,
                                                parts == 2 ? "coef1 dx1 dy1 dz1 coef2 dx2 dy2 dz2 " : "coef dx dy dz ", p.strings.size()), &p);
        return std::nullopt;
    }
    if (d.modifier) {
        refuse(d, d.p.modifier.span, user, fmt::format("{} '{}' is modified by the {} '{}': crex renders {} unpatterned only", t, p.id.text,
                                                       d.modifier->p.type.text, d.modifier->p.id.text, t));
        return std::nullopt;
    }
    Material m;
    for (size_t k = 0; k < parts; ++k) {
        Redirection r;
        r.coefficient.kind = FunctionPattern::Kind::kBrightFunc;
        r.direction.kind = FunctionPattern::Kind::kColorFunc;
        for (FunctionPattern* f : {&r.coefficient, &r.direction}) {
            f->name = p.id.text;
            f->args = p.reals;
        }
        r.coefficient.functions = {p.strings[4 * k].text};
        for (size_t i = 1; i < 4; ++i) r.direction.functions.push_back(p.strings[4 * k + i].text);
        if (!complete_functions(p, r.coefficient, file_at, {4 * k}, {}, file_at + 1) ||
            !complete_functions(p, r.direction, file_at, {4 * k + 1, 4 * k + 2, 4 * k + 3}, {}, file_at + 1))
            return std::nullopt;
        m.redirections.push_back(std::move(r));
    }
    // Every ray goes on (redirected) as a specular transmission would.
    m.type = MaterialType::kTrans;
    m.color = {1, 1, 1};
    m.transmissivity = 1;
    m.transmitted_specular = 1;
    return m;
}

std::optional<Material> SceneBuilder::directional_function(const Definition& d, const Primitive& user) {
    // 2+ strings: the function's name, the function file, its transform. Reals: colour,
    // specularity (transfunc: then transmissivity and transmitted specularity), then A5.. (A7..)
    // for the function.
    const Primitive& p = d.p;
    const std::string& t = p.type.text;
    const bool trans = t == "transfunc";
    const size_t fixed = trans ? 6 : 4;
    if (p.strings.size() < 2 || p.reals.size() < fixed) {
        report("E303", p.type.span, fmt::format("{} '{}' needs 2 string arguments (function, function file) and at least {} real "
                                                "arguments, got {} and {}", t, p.id.text, fixed, p.strings.size(), p.reals.size()), &p);
        return std::nullopt;
    }
    if (d.modifier) {
        refuse(d, d.p.modifier.span, user, fmt::format("{} '{}' is modified by the {} '{}': crex renders {} unpatterned only", t, p.id.text,
                                                       d.modifier->p.type.text, d.modifier->p.id.text, t));
        return std::nullopt;
    }
    const std::vector<double>& r = p.reals;
    for (size_t i = 0; i < fixed; ++i)
        if (!(r[i] >= 0 && r[i] <= 1)) {
            report("E303", p.real_spans[i], fmt::format("{} '{}': its first {} real arguments must be in [0, 1], got {:g}", t, p.id.text,
                                                        fixed, r[i]), &p);
            return std::nullopt;
        }
    DirectionalFunction df;
    FunctionPattern& f = df.shape;
    f.kind = FunctionPattern::Kind::kBrightFunc;
    f.name = p.id.text;
    f.args = r;
    if (!complete_functions(p, f, 1, {}, {}, 2)) return std::nullopt;
    f.definitions = local_frame_definitions() + f.definitions;
    // The function is called with the light's direction (and its solid angle, which crex's
    // light samples do not have: 0), as many of those as it takes.
    calc::Program program;
    calc::Error e;
    program.define(f.definitions, e);
    const Word& name = p.strings[0];
    size_t takes = 0;
    for (size_t n : {4u, 3u})
        if (!takes && program.takes(name.text, n)) takes = n;
    if (!takes) {
        report("E307", name.span, fmt::format("{} '{}': '{}' is not a function of three or four arguments (the light's direction and "
                                              "solid angle) of this file or RADIANCE's library", t, p.id.text, name.text), &p);
        return std::nullopt;
    }
    f.functions = {fmt::format("{}(Lx_crex, Ly_crex, Lz_crex{})", name.text, takes == 4 ? ", 0" : "")};

    const Vec3 colour{r[0], r[1], r[2]};
    const double rspec = r[3];
    const double transmitted = trans ? r[4] * (1 - rspec) : 0, tspec = trans ? transmitted * r[5] : 0;
    df.diffuse_reflect = colour * (1 - transmitted - rspec);
    df.diffuse_transmit = colour * (transmitted - tspec);
    df.reflect = t == "metfunc" ? colour * rspec : Vec3{rspec, rspec, rspec};
    df.transmit = colour * tspec;
    Material m;
    // What every other ray sees: a diffuse surface, its colour in front (less what it
    // transmits), and behind what it transmits.
    m.type = trans ? MaterialType::kTrans : MaterialType::kPlastic;
    m.color = colour;
    m.transmissivity = transmitted;
    m.directional = std::move(df);
    return m;
}

std::string SceneBuilder::see_through_material() {
    // RADIANCE's void part of a mixture: the ray goes on as if the surface were not there.
    // crex passes it straight through (a trans of all specular transmission), shadow rays too
    // (they cross a trans surface by its specular transmission).
    const std::string name = "void (seen through)";
    if (!scene_.find_material(name)) {
        Material m;
        m.name = name;
        m.type = MaterialType::kTrans;
        m.color = {1, 1, 1};
        m.transmissivity = 1;
        m.transmitted_specular = 1;
        scene_.materials.push_back(m);
    }
    return name;
}

std::optional<Material> SceneBuilder::mixture(const Definition& d, const Primitive& user) {
    // mixfunc: foreground background coefficient funcfile [transform], the coefficient the
    // foreground's share at each point. mixtext: foreground background fontfile textfile (or
    // '.' and the text), the foreground inside the letters.
    const Primitive& p = d.p;
    const std::string& t = p.type.text;
    const bool text = t == "mixtext";
    if (d.modifier) {
        refuse(d, d.p.modifier.span, user, fmt::format("{} '{}' is modified by the {} '{}': crex mixes plain materials only", t, p.id.text,
                                                       d.modifier->p.type.text, d.modifier->p.id.text));
        return std::nullopt;
    }
    if (p.strings.size() < 4) {
        report("E303", p.type.span, fmt::format("{} '{}' needs at least 4 string arguments ({}), got {}", t, p.id.text,
                                                text ? "foreground background fontfile textfile" : "foreground background coefficient funcfile",
                                                p.strings.size()), &p);
        return std::nullopt;
    }
    std::optional<std::string> parts[2];
    for (int k = 0; k < 2; ++k) {
        const Word& w = p.strings[static_cast<size_t>(k)];
        if (w.text == "void") {
            parts[k] = see_through_material();
            continue;
        }
        DefPtr part = lookup(w, p, k == 0 ? "the foreground material" : "the background material");
        if (!part) return std::nullopt;
        parts[k] = material_of(part, user);
        if (!parts[k]) return std::nullopt;
        const Material* m = scene_.find_material(*parts[k]);
        if (parts[k]->empty() || !m) {
            refuse(d, w.span, user, fmt::format("{} '{}': '{}' is invisible (an illum without an alternate)", t, p.id.text, w.text));
            return std::nullopt;
        }
        if (is_sampled_emitter(*m) || m->mixture) {
            refuse(d, w.span, user, fmt::format("{} '{}': '{}' is {}, which crex does not mix", t, p.id.text, w.text,
                                                m->mixture ? "a mixture itself" : "a light source direct lighting samples"),
                   "mix surface materials and glows of radius 0 or less");
            return std::nullopt;
        }
    }
    Mixture mix;
    mix.background = *parts[1];
    FunctionPattern& c = mix.coefficient;
    c.name = p.id.text;
    if (text) {
        // The foreground's share: 1 inside the letters, 0 outside.
        if (p.reals.size() != 9 && p.reals.size() != 10) {
            report("E303", p.reals_span(), fmt::format("mixtext '{}' takes 9 or 10 real arguments (origin, right, down, [spacing]), got {}",
                                                       p.id.text, p.reals.size()), &p);
            return std::nullopt;
        }
        c.kind = FunctionPattern::Kind::kBrightText;
        c.args.assign(p.reals.begin(), p.reals.begin() + 9);
        c.args.push_back(1);
        c.args.push_back(0);
        if (p.reals.size() == 10) c.args.push_back(p.reals[9]);
        if (!text_of(p, 2, c)) return std::nullopt;
    } else {
        c.kind = FunctionPattern::Kind::kBrightFunc;
        c.args = p.reals;
        c.functions = {p.strings[2].text};
        if (!complete_functions(p, c, 3, {2}, {}, 4)) return std::nullopt;
    }
    Material m = *scene_.find_material(*parts[0]);
    m.name = unique_material_name(p.id.text);
    m.mixture = std::move(mix);
    return m;
}

}  // namespace crex::radiance
