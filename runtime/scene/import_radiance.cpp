// RADIANCE scene description (.rad) -> Scene. Supported: polygon, sphere, ring, cone, cylinder;
// plastic, metal, trans, glass, dielectric, mirror, light, glow, void. Everything else (inline
// `!` commands, patterns, textures, instances, sources, ...) is a located E307 naming itself,
// and parsing goes on with the next primitive so every problem is reported in one pass.
//
// Extensions in comments (ignored by RADIANCE itself):
//   #@crex tag name=exit_sign task=3 distractor=true    tags the next surface
//   #@crex view -vp 0 0 3.4 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 40
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <map>

#include "runtime/scene/load_scene.h"
#include "runtime/scene/material.h"
#include "runtime/scene/radiance_view.h"

namespace crex {
namespace {

struct Token {
    std::string text;
    uint32_t begin = 0, end = 0;
};

constexpr const char* kUnsupportedTypes[] = {
    "source", "bubble", "cup", "tube", "mesh", "instance", "alias", "texfunc", "texdata", "brightfunc",
    "brightdata", "brighttext", "colorfunc", "colordata", "colorpict", "colortext", "mixfunc", "mixdata",
    "mixpict", "mixtext", "plasfunc", "metfunc", "transfunc", "plasdata", "metdata", "transdata", "BRTDfunc",
    "antimatter", "interface", "illum", "spotlight", "prism1", "prism2", "mist", "ashik2", "BSDF", "aBSDF",
    "WGMDfunc", "mirror2"};

class RadianceReader {
public:
    RadianceReader(const SourceFile& file, DiagnosticSink& sink)
        : file_(file), sink_(sink), errors_before_(sink.error_count()) {
        tokenize();
    }

    std::optional<Scene> read(const SourceFile* view_file) {
        size_t errors_before = errors_before_;  // tokenising already reports '!' commands
        while (pos_ < tokens_.size()) {
            run_directives_before(pos_);
            read_primitive();
        }
        run_directives_before(SIZE_MAX);
        if (view_file) read_view_file(*view_file);
        if (sink_.error_count() != errors_before) return std::nullopt;
        validate_scene(scene_, sink_, [&](size_t i) {
            return i < shape_spans_.size() ? shape_spans_[i] : SourceSpan{&file_, 0, 0};
        });
        if (sink_.error_count() != errors_before) return std::nullopt;
        return scene_;
    }

private:
    SourceSpan span(const Token& t) const { return {&file_, t.begin, t.end}; }
    SourceSpan span_at_end() const {
        uint32_t n = static_cast<uint32_t>(file_.text().size());
        return {&file_, n, n};
    }

    // Whitespace-separated words; `#` comments to the end of the line (our `#@crex` directives
    // are read here); a line starting with `!` is an inline command, which we cannot run.
    void tokenize() {
        const std::string& t = file_.text();
        size_t i = 0;
        bool line_start = true;
        while (i < t.size()) {
            char c = t[i];
            if (c == '\n') {
                line_start = true;
                ++i;
                continue;
            }
            if (std::isspace(static_cast<unsigned char>(c))) {
                ++i;
                continue;
            }
            if (c == '#' || (c == '!' && line_start)) {
                size_t end = t.find('\n', i);
                if (end == std::string::npos) end = t.size();
                std::string_view line(t.data() + i, end - i);
                if (c == '!') {
                    sink_.report("E307", {&file_, static_cast<uint32_t>(i), static_cast<uint32_t>(end)},
                                 "inline commands ('!...') are not supported")
                        .help = "run the command yourself (e.g. xform) and paste its output into the file";
                } else if (line.rfind("#@crex", 0) == 0) {
                    directives_.push_back({tokens_.size(), std::string(line), static_cast<uint32_t>(i)});
                }
                i = end;
                continue;
            }
            line_start = false;
            size_t begin = i;
            while (i < t.size() && !std::isspace(static_cast<unsigned char>(t[i]))) ++i;
            tokens_.push_back({t.substr(begin, i - begin), static_cast<uint32_t>(begin), static_cast<uint32_t>(i)});
        }
    }

    // Directives apply where they stand: before the primitive that follows them.
    void run_directives_before(size_t token_index) {
        while (next_directive_ < directives_.size() && directives_[next_directive_].before_token <= token_index) {
            const Directive& d = directives_[next_directive_++];
            directive(d.text, d.offset);
        }
    }

    void directive(std::string_view line, uint32_t offset) {
        std::vector<Token> words;
        size_t i = 0;
        while (i < line.size()) {
            while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
            size_t b = i;
            while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
            if (i > b) words.push_back({std::string(line.substr(b, i - b)), offset + static_cast<uint32_t>(b), offset + static_cast<uint32_t>(i)});
        }
        if (words.size() >= 2 && words[1].text == "tag") {
            Tag tag;
            for (size_t k = 2; k < words.size(); ++k) {
                const std::string& w = words[k].text;
                size_t eq = w.find('=');
                std::string key = w.substr(0, eq), value = eq == std::string::npos ? "" : w.substr(eq + 1);
                if (key == "name") tag.name = value;
                else if (key == "task" && value.size() == 1 && value[0] >= '0' && value[0] <= '3') tag.task = value[0] - '0';
                else if (key == "distractor" && (value == "true" || value == "false")) tag.distractor = value == "true";
                else
                    sink_.report("E303", span(words[k]), fmt::format("tag: cannot read '{}'; expected name=NAME, task=0..3 "
                                                                     "or distractor=true|false", w));
            }
            pending_tag_ = tag;
        } else if (words.size() >= 2 && words[1].text == "view") {
            read_view(std::vector<Token>(words.begin() + 2, words.end()));
        } else {
            sink_.report("W301", {&file_, offset, offset + static_cast<uint32_t>(line.size())},
                         "unknown #@crex directive (ignored); known: '#@crex tag ...', '#@crex view ...'");
        }
    }

    void read_view_file(const SourceFile& vf) {
        apply_radiance_view(vf, view_file_words(vf), scene_.camera, !view_seen_, sink_);
        view_seen_ = true;
    }

    void read_view(const std::vector<Token>& w) {
        std::vector<ViewWord> words;
        for (const auto& t : w) words.push_back({t.text, t.begin, t.end});
        apply_radiance_view(file_, words, scene_.camera, !view_seen_, sink_);
        view_seen_ = true;
    }

    const Token* next() { return pos_ < tokens_.size() ? &tokens_[pos_++] : nullptr; }

    // Reads "N arg1 .. argN" for strings, integers or reals. Returns false on a malformed count.
    bool read_args(const Token& id, const char* what, std::vector<Token>& out) {
        const Token* count = next();
        if (!count) {
            sink_.report("E301", span_at_end(), fmt::format("unexpected end of file: '{}' needs its number of {} arguments",
                                                            id.text, what));
            return false;
        }
        char* end = nullptr;
        long n = std::strtol(count->text.c_str(), &end, 10);
        if (end != count->text.c_str() + count->text.size() || n < 0 || n > 1000000) {
            sink_.report("E302", span(*count), fmt::format("'{}': expected the number of {} arguments, got '{}'", id.text,
                                                           what, count->text));
            return false;
        }
        out.clear();
        for (long k = 0; k < n; ++k) {
            const Token* t = next();
            if (!t) {
                sink_.report("E301", span_at_end(), fmt::format("unexpected end of file: '{}' needs {} {} arguments, found {}",
                                                                id.text, n, what, k));
                return false;
            }
            out.push_back(*t);
        }
        return true;
    }

    bool reals(const std::vector<Token>& args, std::vector<double>& out) {
        out.clear();
        for (const auto& a : args) {
            char* end = nullptr;
            double x = std::strtod(a.text.c_str(), &end);
            if (end != a.text.c_str() + a.text.size()) {
                sink_.report("E302", span(a), fmt::format("expected a real number, got '{}'", a.text));
                return false;
            }
            if (!std::isfinite(x)) {
                sink_.report("E303", span(a), fmt::format("expected a finite number, got '{}'", a.text));
                return false;
            }
            out.push_back(x);
        }
        return true;
    }

    void read_primitive() {
        const Token* modifier = next();
        const Token* type = next();
        const Token* id = next();
        if (!type || !id) {
            sink_.report("E301", span_at_end(), fmt::format("unexpected end of file after '{}': a primitive is "
                                                            "'modifier type identifier' and three argument lists", modifier->text));
            return;
        }
        std::vector<Token> strings, ints, real_tokens;
        if (!read_args(*id, "string", strings) || !read_args(*id, "integer", ints) || !read_args(*id, "real", real_tokens)) {
            pos_ = tokens_.size();  // the structure is lost: stop rather than misread the rest
            return;
        }
        SourceSpan where = span(*type).merge(span(*id));
        std::vector<double> r;
        if (!reals(real_tokens, r)) return;

        const std::string& t = type->text;
        if (auto mt = material_type_from_name(t); mt && t != "void") {
            read_material(*modifier, *type, *id, *mt, r, real_tokens, strings);
            return;
        }
        if (t == "polygon" || t == "sphere" || t == "ring" || t == "cone" || t == "cylinder") {
            read_surface(*modifier, *type, *id, r, where);
            return;
        }
        bool known = false;
        for (const char* u : kUnsupportedTypes) known = known || t == u;
        sink_.report("E307", span(*type), known ? fmt::format("RADIANCE type '{}' ('{}') is not supported", t, id->text)
                                                : fmt::format("unknown RADIANCE type '{}' ('{}')", t, id->text))
            .help = "supported: polygon, sphere, ring, cone, cylinder; plastic, metal, trans, glass, dielectric, "
                    "mirror, light, glow";
    }

    bool expect_reals(const Token& type, const Token& id, const std::vector<double>& r, std::initializer_list<size_t> counts,
                      const std::vector<Token>& toks) {
        for (size_t c : counts)
            if (r.size() == c) return true;
        std::string want;
        for (size_t c : counts) want += (want.empty() ? "" : " or ") + std::to_string(c);
        SourceSpan s = toks.empty() ? span(id) : span(toks.front()).merge(span(toks.back()));
        sink_.report("E303", s, fmt::format("{} '{}' takes {} real arguments, got {}", type.text, id.text, want, r.size()));
        return false;
    }

    void read_material(const Token& modifier, const Token& type, const Token& id, MaterialType mt,
                       const std::vector<double>& r, const std::vector<Token>& toks, const std::vector<Token>& strings) {
        if (modifier.text != "void") {
            sink_.report("E307", span(modifier), fmt::format("material '{}' is modified by '{}': patterns, textures and "
                                                             "material mixing are not supported", id.text, modifier.text));
            return;
        }
        if (!strings.empty())
            sink_.report("W301", span(strings.front()).merge(span(strings.back())),
                         fmt::format("string arguments of {} '{}' are ignored", type.text, id.text));
        Material m;
        m.name = id.text;
        m.type = mt;
        bool ok = false;
        switch (mt) {
        case MaterialType::kPlastic:
        case MaterialType::kMetal: ok = expect_reals(type, id, r, {5}, toks); break;
        case MaterialType::kTrans: ok = expect_reals(type, id, r, {7}, toks); break;
        case MaterialType::kGlass: ok = expect_reals(type, id, r, {3, 4}, toks); break;
        case MaterialType::kDielectric: ok = expect_reals(type, id, r, {5}, toks); break;
        case MaterialType::kMirror:
        case MaterialType::kLight: ok = expect_reals(type, id, r, {3}, toks); break;
        case MaterialType::kGlow: ok = expect_reals(type, id, r, {4}, toks); break;
        case MaterialType::kVoid: break;
        }
        if (!ok) return;
        m.color = {r[0], r[1], r[2]};
        bool emitter = mt == MaterialType::kLight || mt == MaterialType::kGlow;
        auto check_range = [&](size_t i, double lo, double hi, const char* what) {
            if (r[i] >= lo && r[i] <= hi) return true;
            sink_.report("E303", span(toks[i]), fmt::format("{} '{}': {} must be in [{:g}, {:g}], got {:g}", type.text, id.text, what, lo, hi, r[i]));
            return false;
        };
        for (size_t i = 0; i < 3; ++i)
            if (!check_range(i, 0, emitter ? INFINITY : 1, emitter ? "radiance" : "reflectance")) return;
        if (mt == MaterialType::kPlastic || mt == MaterialType::kMetal || mt == MaterialType::kTrans) {
            if (!check_range(3, 0, 1, "specularity") || !check_range(4, 0, 1, "roughness")) return;
            m.specularity = r[3];
            m.roughness = r[4];
        }
        if (mt == MaterialType::kTrans) {
            if (!check_range(5, 0, 1, "transmissivity") || !check_range(6, 0, 1, "transmitted specularity")) return;
            m.transmissivity = r[5];
            m.transmitted_specular = r[6];
        }
        if (mt == MaterialType::kGlass && r.size() == 4) m.ior = r[3];
        if (mt == MaterialType::kDielectric) m.ior = r[3];  // r[4], the Hartmann constant, is not modelled
        if ((mt == MaterialType::kGlass || mt == MaterialType::kDielectric) && !(m.ior > 0)) {
            sink_.report("E303", span(toks[3]), fmt::format("{} '{}': index of refraction must be > 0", type.text, id.text));
            return;
        }
        if (mt == MaterialType::kGlow) {
            if (!check_range(3, 0, INFINITY, "maximum radius")) return;
            m.glow_radius = r[3];
        }
        if (defined_.count(m.name)) {
            // RADIANCE lets a later definition shadow an earlier one; we keep one per name.
            sink_.report("E305", span(id), fmt::format("material '{}' is defined twice", m.name));
            return;
        }
        defined_[m.name] = scene_.materials.size();
        scene_.materials.push_back(m);
    }

    void read_surface(const Token& modifier, const Token& type, const Token& id, const std::vector<double>& r,
                      SourceSpan where) {
        std::optional<Tag> tag = std::move(pending_tag_);
        pending_tag_.reset();
        if (modifier.text == "void") return;  // invisible in RADIANCE too
        if (!defined_.count(modifier.text)) {
            sink_.report("E305", span(modifier), fmt::format("{} '{}' uses modifier '{}', which is not defined above it",
                                                             type.text, id.text, modifier.text));
            return;
        }
        Shape s;
        s.name = id.text;
        s.material = modifier.text;
        s.tag = tag;
        const std::string& t = type.text;
        auto need = [&](size_t n) {
            if (r.size() == n) return true;
            sink_.report("E303", where, fmt::format("{} '{}' takes {} real arguments, got {}", t, id.text, n, r.size()));
            return false;
        };
        if (t == "polygon") {
            if (r.size() < 9 || r.size() % 3 != 0) {
                sink_.report("E303", where, fmt::format("polygon '{}' needs 3 numbers per vertex and at least 3 vertices, got {} "
                                                        "numbers", id.text, r.size()));
                return;
            }
            s.type = ShapeType::kPolygon;
            for (size_t i = 0; i < r.size(); i += 3) s.vertices.push_back({r[i], r[i + 1], r[i + 2]});
        } else if (t == "sphere") {
            if (!need(4)) return;
            s.type = ShapeType::kSphere;
            s.center = {r[0], r[1], r[2]};
            s.radius = r[3];
        } else if (t == "ring") {
            if (!need(8)) return;
            s.type = ShapeType::kRing;
            s.center = {r[0], r[1], r[2]};
            s.normal = {r[3], r[4], r[5]};
            s.r0 = r[6];
            s.r1 = r[7];
        } else if (t == "cone") {
            if (!need(8)) return;
            s.type = ShapeType::kCone;
            s.p0 = {r[0], r[1], r[2]};
            s.p1 = {r[3], r[4], r[5]};
            s.r0 = r[6];
            s.r1 = r[7];
        } else {
            if (!need(7)) return;
            s.type = ShapeType::kCylinder;
            s.p0 = {r[0], r[1], r[2]};
            s.p1 = {r[3], r[4], r[5]};
            s.radius = r[6];
        }
        shape_spans_.push_back(where);
        scene_.shapes.push_back(std::move(s));
    }

    const SourceFile& file_;
    DiagnosticSink& sink_;
    size_t errors_before_;
    struct Directive {
        size_t before_token;
        std::string text;
        uint32_t offset;
    };
    std::vector<Token> tokens_;
    std::vector<Directive> directives_;
    size_t next_directive_ = 0;
    size_t pos_ = 0;
    Scene scene_;
    std::map<std::string, size_t> defined_;
    std::vector<SourceSpan> shape_spans_;
    std::optional<Tag> pending_tag_;
    bool view_seen_ = false;
};

}  // namespace

std::optional<Scene> import_radiance(const SourceFile& file, const SourceFile* view_file, DiagnosticSink& sink) {
    auto scene = RadianceReader(file, sink).read(view_file);
    if (scene) scene->source = file.name();
    return scene;
}

std::optional<Scene> import_radiance(const SourceFile& file, DiagnosticSink& sink) {
    return import_radiance(file, nullptr, sink);
}

}  // namespace crex
