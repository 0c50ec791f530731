#include "runtime/scene/radiance/scene_builder.h"

#include <fmt/format.h>

#include <cctype>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "runtime/scene/material.h"
#include "runtime/scene/radiance/calc.h"
#include "runtime/scene/radiance/generators.h"
#include "runtime/scene/radiance/primitive_types.h"
#include "runtime/scene/radiance/transform.h"
#include "runtime/scene/radiance_view.h"

namespace crex::radiance {


namespace {

const char* kSupportedHelp =
    "crex renders the surfaces polygon, sphere, bubble, ring, cone, cup, cylinder, tube and source, and the materials "
    "plastic, metal, trans, plastic2, metal2, trans2, ashik2, plasfunc, metfunc, transfunc, prism1, prism2, antimatter, glass, dielectric, interface, mirror, light, illum, glow and spotlight";

std::string article(const std::string& word) {
    return word.empty() || std::string("aeiouAEIOU").find(word[0]) == std::string::npos ? "a" : "an";
}

// What a pattern, texture or mixture needs, from its string arguments: its functions, their
// file, its data or picture ("flatcorr, src_phi4, src_theta of source.cal, data rect_fixture.dat").
std::string what_it_needs(const Primitive& p) {
    const std::string& t = p.type.text;
    auto at = [&](size_t i) { return i < p.strings.size() ? p.strings[i].text : std::string("?"); };
    auto list = [&](size_t from, size_t to) {
        std::string out;
        for (size_t i = from; i < std::min(to, p.strings.size()); ++i) {
            if (std::string(at(i)).rfind('-', 0) == 0 && i > from) break;  // a transform begins
            out += (out.empty() ? "" : ", ") + at(i);
        }
        return out;
    };
    auto file = [&](const std::string& f) { return f == "." ? std::string("the built-in library") : f; };
    if (t == "brightfunc") return fmt::format("{} of {}", at(0), file(at(1)));
    if (t == "colorfunc" || t == "texfunc") return fmt::format("{} of {}", list(0, 3), file(at(3)));
    if (t == "brightdata") return fmt::format("{}, {} of {}, data {}", at(0), list(3, p.strings.size()), file(at(2)), at(1));
    if (t == "colordata" || t == "texdata")
        return fmt::format("{}, {} of {}, data {}", list(0, 3), list(7, p.strings.size()), file(at(6)), list(3, 6));
    if (t == "colorpict") return fmt::format("{}, {}, {} of {}, picture {}", list(0, 3), at(5), at(6), file(at(4)), at(3));
    if (t == "mixfunc") return fmt::format("{} of {}", at(2), file(at(3)));
    if (t == "mixdata") return fmt::format("{}, {} of {}, data {}", at(2), list(5, p.strings.size()), file(at(4)), at(3));
    if (t == "mixpict") return fmt::format("{}, {}, {} of {}, picture {}", at(2), at(5), at(6), file(at(4)), at(3));
    if (t.find("text") != std::string::npos) return "text in a font";
    return "";
}

}  // namespace

Diagnostic& SceneBuilder::report(const char* code, SourceSpan span, std::string message, const Primitive* via) {
    Diagnostic& d = sink_.report(code, span, std::move(message));
    if (via && via->via)
        for (const SourceSpan& c : *via->via) d.notes.push_back({c, "read through this command"});
    return d;
}

void SceneBuilder::refuse(const Definition& d, const Primitive& user, const std::string& message, const std::string& help) {
    refuse(d, d.p.type.span, user, message, help);
}

void SceneBuilder::refuse(const Definition& d, SourceSpan at, const Primitive& user, const std::string& message, const std::string& help) {
    Diagnostic& diag = report("E307", at, message, &d.p);
    if (user.span.valid() && user.span.begin != d.p.span.begin) diag.notes.push_back({user.id.span, "needed by this surface"});
    diag.help = help.empty() ? kSupportedHelp : help;
}

SceneBuilder::DefPtr SceneBuilder::lookup(const Word& name, const Primitive& user, const char* role) {
    auto it = defs_.find(name.text);
    if (it != defs_.end()) return it->second;
    std::string known;
    for (const auto& [n, d] : defs_) known += (known.empty() ? "" : ", ") + n;
    Diagnostic& diag = report("E305", name.span,
                              fmt::format("{} '{}' uses {} '{}', which is not defined above it", user.type.text, user.id.text, role, name.text),
                              &user);
    if (defs_.empty()) diag.help = "define it (for instance 'void plastic " + name.text + " 0 0 5 .5 .5 .5 0 0') before the primitives using it";
    return nullptr;
}

void SceneBuilder::primitive(Primitive p) {
    const PrimitiveTypeInfo* info = find_primitive_type(p.type.text);
    if (!info) {
        report("E307", p.type.span, fmt::format("unknown RADIANCE type '{}' ('{}')", p.type.text, p.id.text), &p).help = kSupportedHelp;
        return;
    }
    if (info->kind == PrimitiveKind::kAlias) return alias(std::move(p));
    if (info->kind == PrimitiveKind::kSurface) return surface(std::move(p));
    define(std::move(p));
}

void SceneBuilder::define(Primitive p) {
    auto d = std::make_shared<Definition>();
    if (p.modifier.text != "void") {
        d->modifier = lookup(p.modifier, p, "the modifier");
        if (!d->modifier) return;
    }
    if ((p.type.text == "mirror" || p.type.text == "illum") && !p.strings.empty()) {
        const Word& alt = p.strings[0];
        if (alt.text == "void") {
            d->alternate_void = true;
        } else {
            d->alternate = lookup(alt, p, "the alternate material");
            if (!d->alternate) return;
        }
    }
    d->p = std::move(p);
    defs_[d->p.id.text] = d;
    // Materials crex renders are converted (and their arguments checked) where they are
    // defined, used or not; what crex does not render is refused only if a surface needs it.
    static const char* kConvertible[] = {"plastic", "metal", "trans", "plastic2", "metal2", "trans2", "glass", "dielectric",
                                         "interface", "mirror", "light", "glow", "illum", "spotlight", "ashik2"};
    if (!d->modifier)
        for (const char* t : kConvertible)
            if (d->p.type.text == t) {
                material_of(d, d->p);
                break;
            }
}

void SceneBuilder::alias(Primitive p) {
    auto it = defs_.find(p.alias_of.text);
    if (it == defs_.end()) {
        lookup(p.alias_of, p, "the original");
        return;
    }
    const DefPtr& original = it->second;
    const std::string& mod = p.modifier.text;
    if (mod == "inherit" || mod == original->p.modifier.text) {  // the same definition under another name
        defs_[p.id.text] = original;
        return;
    }
    auto d = std::make_shared<Definition>(*original);
    d->converted = false;
    d->material.reset();
    d->p.modifier = p.modifier;
    d->p.id = p.id;
    d->modifier = nullptr;
    if (mod != "void") {
        d->modifier = lookup(p.modifier, p, "the modifier");
        if (!d->modifier) return;
    }
    defs_[p.id.text] = d;
}

std::string SceneBuilder::unique_material_name(const std::string& id) {
    int& uses = material_name_uses_[id];
    std::string name = uses == 0 ? id : fmt::format("{}#{}", id, uses + 1);
    ++uses;
    while (scene_.find_material(name)) name += "'";
    return name;
}

std::optional<std::string> SceneBuilder::material_of(const DefPtr& d, const Primitive& user) {
    if (!d->converted) {
        d->converted = true;
        auto m = convert(*d, user);
        if (m && m->name.empty()) {
            d->material = "";  // invisible
        } else if (m) {
            scene_.materials.push_back(*m);
            d->material = m->name;
        }
    }
    return d->material;
}

std::optional<std::string> SceneBuilder::alternate_of(const Definition& d, const Primitive& user) {
    if (d.alternate_void || !d.alternate) return "";
    return material_of(d.alternate, user);
}

std::optional<Transform> SceneBuilder::function_transform(const Primitive& p, size_t first) {
    // The strings after a function file are its transform (xform appends its own there).
    std::vector<std::string> words;
    for (size_t k = first; k < p.strings.size(); ++k) words.push_back(p.strings[k].text);
    Transform xf;
    size_t consumed = 0, bad = 0;
    std::string error;
    if (!parse_transform(words, 0, xf, consumed, error, bad) || consumed != words.size()) {
        report("E302", p.strings[std::min(first + (error.empty() ? consumed : bad), p.strings.size() - 1)].span,
               fmt::format("{} '{}': {}", p.type.text, p.id.text, error.empty() ? "expected a transform after the function file" : error), &p);
        return std::nullopt;
    }
    return xf;
}

bool SceneBuilder::orientation(const Definition& d, Vec3& out) {
    // ux uy uz funcfile [transform]: expressions evaluated in the function file's context,
    // then moved by its transform to world coordinates.
    const Primitive& p = d.p;
    if (p.strings.size() < 4) {
        report("E303", p.type.span, fmt::format("{} '{}' needs 4 string arguments (ux uy uz funcfile), got {}", p.type.text, p.id.text,
                                                p.strings.size()), &p);
        return false;
    }
    calc::Program program;
    const Word& file = p.strings[3];
    std::optional<std::string> text = function_file_text(file, p);
    if (!text) return false;
    if (calc::Error e; !program.define(*text, e)) {
        report("E302", file.span, fmt::format("function file '{}': {}", file.text, e.message), &p);
        return false;
    }
    double u[3];
    for (int k = 0; k < 3; ++k) {
        const Word& w = p.strings[static_cast<size_t>(k)];
        calc::Error e;
        auto expr = program.parse(w.text, e);
        std::optional<double> v;
        if (expr) v = program.evaluate(*expr, calc::Environment{{}, p.reals}, e);
        if (!v) {
            Diagnostic& diag = report("E307", w.span, fmt::format("{} '{}': the orientation '{}' cannot be evaluated once for the "
                                                                 "whole surface: {}", p.type.text, p.id.text, w.text, e.message), &p);
            diag.help = "crex takes a constant orientation vector (one varying over the surface, such as one using Px or Nx, is "
                        "not supported)";
            return false;
        }
        u[k] = *v;
    }
    std::optional<Transform> xf = function_transform(p, 4);
    if (!xf) return false;
    out = xf->vector({u[0], u[1], u[2]});
    if (!(length(out) > 0)) {
        report("E306", p.strings[0].span.merge(p.strings[2].span), fmt::format("{} '{}': the orientation vector is zero", p.type.text, p.id.text), &p);
        return false;
    }
    return true;
}

std::optional<Material> SceneBuilder::convert(const Definition& d, const Primitive& user) {
    const Primitive& p = d.p;
    const std::string& t = p.type.text;
    const PrimitiveTypeInfo* info = find_primitive_type(t);
    if (info->kind == PrimitiveKind::kPattern || info->kind == PrimitiveKind::kTexture) {
        refuse(d, user, fmt::format("'{}' is {} {} ({}), not a material: a surface's modifier must end in a material", p.id.text,
                                    article(t), t, info->kind == PrimitiveKind::kPattern ? "a pattern" : "a texture"));
        return std::nullopt;
    }
    if (t == "mixfunc" || t == "mixtext") return mixture(d, user);
    if (info->kind == PrimitiveKind::kMixture) {
        const std::string needs = what_it_needs(p);
        refuse(d, user, fmt::format("{} '{}' (a mixture of materials{}) is not supported", t, p.id.text, needs.empty() ? "" : ", by " + needs),
               "give the surface one of the materials the mixture blends");
        return std::nullopt;
    }
    // Patterns scale an emitter's radiance, or the colour of a material that reflects or
    // transmits by its colour.
    const bool emits = t == "light" || t == "glow" || t == "illum" || t == "spotlight";
    const bool coloured = t == "plastic" || t == "metal" || t == "trans" || t == "plastic2" || t == "metal2" || t == "trans2" || t == "mirror";
    std::vector<FunctionPattern> patterns;
    if (d.modifier && (emits || coloured) && is_emitter_pattern(d.modifier->p.type.text)) {
        if (!patterns_of(d, user, patterns)) return std::nullopt;
    } else if (d.modifier) {
        const Definition& m = *d.modifier;
        const std::string needs = what_it_needs(m.p);
        refuse(d, d.p.modifier.span, user, fmt::format("{} '{}' is modified by {} {} '{}'{}: patterns, textures and mixtures modifying a "
                                    "material are not supported", t, p.id.text, article(m.p.type.text), m.p.type.text, m.p.id.text,
                                    needs.empty() ? "" : " (" + needs + ")"),
               fmt::format("use 'void' as the modifier of '{}' to render it without the {}", p.id.text, m.p.type.text));
        return std::nullopt;
    }
    const std::vector<double>& r = p.reals;
    auto counts = [&](std::initializer_list<size_t> allowed) {
        for (size_t c : allowed)
            if (r.size() == c) return true;
        std::string want;
        for (size_t c : allowed) want += (want.empty() ? "" : " or ") + std::to_string(c);
        report("E303", p.reals_span(), fmt::format("{} '{}' takes {} real arguments, got {}", t, p.id.text, want, r.size()), &p);
        return false;
    };
    auto in_range = [&](size_t i, double lo, double hi, const char* what) {
        if (r[i] >= lo && r[i] <= hi) return true;
        report("E303", p.real_spans[i], fmt::format("{} '{}': {} must be in [{:g}, {:g}], got {:g}", t, p.id.text, what, lo, hi, r[i]), &p);
        return false;
    };
    auto colour = [&](Material& m, bool emitter) {
        for (size_t i = 0; i < 3; ++i)
            if (!in_range(i, 0, emitter ? INFINITY : 1, emitter ? "radiance" : "reflectance")) return false;
        m.color = {r[0], r[1], r[2]};
        return true;
    };
    auto no_strings = [&] {
        if (!p.strings.empty())
            report("W301", p.strings.front().span.merge(p.strings.back().span),
                   fmt::format("string arguments of {} '{}' are ignored", t, p.id.text), &p);
    };
    Material m;
    m.name = unique_material_name(p.id.text);
    m.patterns = patterns;
    if (t == "plastic" || t == "metal" || t == "trans") {
        no_strings();
        if (!counts({t == "trans" ? 7u : 5u}) || !colour(m, false) || !in_range(3, 0, 1, "specularity") || !in_range(4, 0, 1, "roughness"))
            return std::nullopt;
        m.type = t == "plastic" ? MaterialType::kPlastic : t == "metal" ? MaterialType::kMetal : MaterialType::kTrans;
        m.specularity = r[3], m.roughness = r[4];
        if (t == "trans") {
            if (!in_range(5, 0, 1, "transmissivity") || !in_range(6, 0, 1, "transmitted specularity")) return std::nullopt;
            m.transmissivity = r[5], m.transmitted_specular = r[6];
        }
        return m;
    }
    if (t == "plastic2" || t == "metal2" || t == "trans2") {
        if (!counts({t == "trans2" ? 8u : 6u}) || !colour(m, false) || !in_range(3, 0, 1, "specularity")) return std::nullopt;
        for (size_t i : {4u, 5u})
            if (!(r[i] > 0 && r[i] <= 1)) {
                report("E303", p.real_spans[i], fmt::format("{} '{}': roughness must be in (0, 1] (RADIANCE refuses 0 too: use {} "
                                                            "for a smooth surface), got {:g}", t, p.id.text, t.substr(0, t.size() - 1), r[i]), &p);
                return std::nullopt;
            }
        Anisotropy a;
        if (!orientation(d, a.orientation)) return std::nullopt;
        a.roughness_v = r[5];
        m.type = t == "plastic2" ? MaterialType::kPlastic : t == "metal2" ? MaterialType::kMetal : MaterialType::kTrans;
        m.specularity = r[3], m.roughness = r[4];
        m.anisotropy = a;
        if (t == "trans2") {
            if (!in_range(6, 0, 1, "transmissivity") || !in_range(7, 0, 1, "transmitted specularity")) return std::nullopt;
            m.transmissivity = r[6], m.transmitted_specular = r[7];
        }
        return m;
    }
    if (t == "ashik2") {
        // Ashikhmin-Shirley: crex has no lobe of that shape; the anisotropic Ward lobe of the
        // same widths (a cosine power n falls off as exp(-n theta^2 / 2): alpha = sqrt(2 / n))
        // with the diffuse colour kept and the specular colour's brightness as its specularity.
        if (!counts({8}) || !colour(m, false)) return std::nullopt;
        for (size_t i = 3; i < 6; ++i)
            if (!in_range(i, 0, 1, "specular reflectance")) return std::nullopt;
        for (size_t i : {6u, 7u})
            if (!(r[i] > 0 && std::isfinite(r[i]))) {
                report("E303", p.real_spans[i], fmt::format("ashik2 '{}': a specular power must be > 0, got {:g}", p.id.text, r[i]), &p);
                return std::nullopt;
            }
        Anisotropy a;
        if (!orientation(d, a.orientation)) return std::nullopt;
        const double spec = std::clamp(.265074 * r[3] + .670115 * r[4] + .064811 * r[5], 0.0, 0.99);
        m.type = MaterialType::kPlastic;
        m.specularity = spec;
        for (double* c : {&m.color.x, &m.color.y, &m.color.z}) *c = std::fmin(1.0, *c / (1 - spec));
        m.roughness = std::fmin(1.0, std::sqrt(2 / r[6]));
        a.roughness_v = std::fmin(1.0, std::sqrt(2 / r[7]));
        m.anisotropy = a;
        report("W306", p.type.span, fmt::format("ashik2 '{}': crex renders it as an anisotropic Ward plastic of the same lobe widths "
                                                "(roughness {:.3g} and {:.3g}) and specularity {:.3g}, without the Ashikhmin-Shirley "
                                                "Fresnel term", p.id.text, m.roughness, a.roughness_v, spec), &p);
        return m;
    }
    if (t == "glass" || t == "dielectric" || t == "interface") {
        no_strings();
        const bool counted = t == "glass" ? counts({3, 4}) : counts({t == "dielectric" ? 5u : 8u});
        if (!counted || !colour(m, false)) return std::nullopt;
        if (t == "glass") {
            if (r.size() == 4) m.ior = r[3];
            m.thin_glass = true;  // RADIANCE renders glass as a pane: straight through (glass.c)
        } else {
            m.ior = r[3];  // dielectric: r[4], the Hartmann constant, is not modelled
        }
        m.type = t == "glass" ? MaterialType::kGlass : MaterialType::kDielectric;
        if (t == "interface") {
            OutsideMedium o;
            for (size_t i = 4; i < 7; ++i)
                if (!in_range(i, 0, 1, "outside transmission")) return std::nullopt;
            o.color = {r[4], r[5], r[6]};
            o.ior = r[7];
            if (!(o.ior > 0)) {
                report("E303", p.real_spans[7], fmt::format("interface '{}': the outside index of refraction must be > 0", p.id.text), &p);
                return std::nullopt;
            }
            m.outside = o;
        }
        if (!(m.ior > 0)) {
            report("E303", p.real_spans[3], fmt::format("{} '{}': index of refraction must be > 0", t, p.id.text), &p);
            return std::nullopt;
        }
        return m;
    }
    if (t == "mirror") {
        if (!counts({3}) || !colour(m, false)) return std::nullopt;
        if (p.strings.size() > 1)
            report("W301", p.strings[1].span, fmt::format("mirror '{}': only one string argument (the alternate material) is read", p.id.text), &p);
        if (!p.strings.empty()) {
            // RADIANCE shades every ray but light-source rays with the alternate; crex has no
            // virtual light sources, so the surface is the alternate for every ray.
            auto alt = alternate_of(d, user);
            if (!alt) return std::nullopt;
            report("W306", p.strings[0].span, fmt::format("mirror '{}' with an alternate material: crex renders its surfaces as '{}' "
                                                          "(RADIANCE also mirrors the light sources in them, through virtual sources)",
                                                          p.id.text, p.strings[0].text), &p);
            if (alt->empty()) return Material{};  // an alternate of void: invisible
            const Material* a = scene_.find_material(*alt);
            if (!a) return std::nullopt;
            Material copy = *a;
            copy.name = m.name;
            return copy;
        }
        m.type = MaterialType::kMirror;
        return m;
    }
    if (t == "light" || t == "glow" || t == "illum" || t == "spotlight") {
        if (t != "illum") no_strings();
        if (!counts({t == "glow" ? 4u : t == "spotlight" ? 7u : 3u}) || !colour(m, true)) return std::nullopt;
        m.type = t == "glow" ? MaterialType::kGlow : t == "illum" ? MaterialType::kIllum : MaterialType::kLight;
        if (t == "glow") m.glow_radius = r[3];  // negative: never lights the scene
        if (t == "spotlight") {
            Spot s;
            if (!(r[3] > 0 && r[3] <= 360)) {
                report("E303", p.real_spans[3], fmt::format("spotlight '{}': the cone angle must be in (0, 360] degrees, got {:g}", p.id.text, r[3]), &p);
                return std::nullopt;
            }
            s.angle_deg = r[3];
            s.direction = {r[4], r[5], r[6]};
            if (!(length(s.direction) > 0)) {
                report("E306", p.reals_span(4, 6), fmt::format("spotlight '{}': the direction vector is zero", p.id.text), &p);
                return std::nullopt;
            }
            m.spot = s;
        }
        if (t == "illum") {
            if (p.strings.size() > 1)
                report("W301", p.strings[1].span, fmt::format("illum '{}': only one string argument (the alternate material) is read", p.id.text), &p);
            auto alt = alternate_of(d, user);
            if (!alt) return std::nullopt;
            m.alternate = *alt;
        }
        return m;
    }
    if (t == "antimatter") {
        // The modifiers whose surfaces its solid removes (void entries are skipped).
        for (const Word& w : p.strings) {
            if (w.text == "void") continue;
            DefPtr cut = lookup(w, p, "the modifier to clip");
            if (!cut) return std::nullopt;
            auto name = material_of(cut, user);
            if (!name) return std::nullopt;
            if (!name->empty()) m.clips.push_back(*name);
        }
        if (m.clips.empty()) {
            report("E303", p.type.span, fmt::format("antimatter '{}' names no material to clip (its string arguments)", p.id.text), &p);
            return std::nullopt;
        }
        m.type = MaterialType::kVoid;
        return m;
    }
    if (t == "prism1" || t == "prism2") {
        auto b = redirecting(d, user);
        if (b) b->name = m.name;
        return b;
    }
    if (t == "plasfunc" || t == "metfunc" || t == "transfunc") {
        auto b = directional_function(d, user);
        if (b) b->name = m.name;
        return b;
    }
    if (t == "BRTDfunc") {
        auto b = brtd_function(d, user);
        if (b) b->name = m.name;
        return b;
    }
    std::string help;
    if (t == "mist") help = "a mist bounds a medium: surfaces take it as their modifier, not as a material";
    else if (t.find("func") != std::string::npos || t.find("data") != std::string::npos || t == "BRTDfunc")
        help = "crex does not evaluate procedural or tabulated reflectance; approximate it with plastic, metal or trans";
    refuse(d, user, fmt::format("RADIANCE material type '{}' ('{}') is not supported", t, p.id.text), help);
    return std::nullopt;
}

void SceneBuilder::surface(Primitive p) {
    const std::optional<Tag> tag = tag_for_next_surface();
    const std::string& t = p.type.text;
    if (t == "mesh") return mesh(p, tag);          // void: the mesh's own materials
    if (t == "instance") return instance(p, tag);  // void: the octree's own materials
    if (p.modifier.text == "void") return;  // invisible in RADIANCE too
    DefPtr d = lookup(p.modifier, p, "the modifier");
    if (!d) return;
    if (d->p.type.text == "mist") return mist_surface(d, p);
    std::vector<Vec3> smooth;  // per vertex: a smoothed triangle's normals
    if (t == "polygon" && d->p.type.text == "texfunc") {
        std::vector<Vec3> vertices;
        for (size_t i = 0; i + 2 < p.reals.size(); i += 3) vertices.push_back({p.reals[i], p.reals[i + 1], p.reals[i + 2]});
        if (mesh_normals(*d, p, vertices, smooth)) {
            if (smooth.empty()) return;  // reported
            d = d->modifier;
            if (!d) return;  // void: invisible
        }
    }
    if (t == "source" && d->modifier && d->modifier->p.type.text == "brightfunc" && !d->modifier->p.strings.empty() &&
        d->modifier->p.strings[0].text == "skybr") {
        // A sky: a glow source whose brightness is gensky's (skybright.cal's skybr).
        std::optional<SkyModel> sky = sky_of(*d->modifier, p);
        if (!sky) return;
        if (!d->unpatterned) {
            Definition plain = *d;
            plain.modifier = nullptr;
            auto m = convert(plain, p);
            d->unpatterned = m ? std::optional<std::string>(m->name) : std::optional<std::string>("");
            if (m) scene_.materials.push_back(*m);
        }
        const Material* m = d->unpatterned->empty() ? nullptr : scene_.find_material(*d->unpatterned);
        if (m) distant_light(p, *m, sky);
        return;
    }
    auto name = material_of(d, p);
    if (!name || name->empty()) return;  // reported, or invisible (an alternate of void)
    const Material* m = scene_.find_material(*name);
    if (!m) return;
    if (t == "source") return distant_light(p, *m, std::nullopt);
    const std::vector<double>& r = p.reals;
    const SourceSpan where = p.type.span.merge(p.id.span);
    auto need = [&](size_t n) {
        if (r.size() == n) return true;
        report("E303", where, fmt::format("{} '{}' takes {} real arguments, got {}", t, p.id.text, n, r.size()), &p);
        return false;
    };
    Shape s;
    s.name = p.id.text;
    s.material = *name;
    s.tag = tag;
    if (t == "polygon") {
        if (r.size() < 9 || r.size() % 3 != 0) {
            report("E303", where, fmt::format("polygon '{}' needs 3 numbers per vertex and at least 3 vertices, got {} numbers",
                                              p.id.text, r.size()), &p);
            return;
        }
        s.type = ShapeType::kPolygon;
        for (size_t i = 0; i < r.size(); i += 3) s.vertices.push_back({r[i], r[i + 1], r[i + 2]});
        if (!smooth.empty()) {
            // A smoothed triangle joins the one before it when they are one object.
            const bool flat = smooth[0] == Vec3{};
            if (smooth_shape_ < scene_.shapes.size() && smooth_shape_ + 1 == scene_.shapes.size()) {
                Shape& last = scene_.shapes[smooth_shape_];
                if (last.name == s.name && last.material == s.material && last.tag == s.tag && last.normals.empty() == flat &&
                    last.vertices.size() < (size_t{1} << 24)) {
                    const auto first = static_cast<uint32_t>(last.vertices.size());
                    last.vertices.insert(last.vertices.end(), s.vertices.begin(), s.vertices.end());
                    if (!flat) last.normals.insert(last.normals.end(), smooth.begin(), smooth.end());
                    last.triangles.push_back({first, first + 1, first + 2});
                    return;
                }
            }
            s.type = ShapeType::kMesh;
            s.triangles.push_back({0, 1, 2});
            if (!flat) s.normals = smooth;
            smooth_shape_ = scene_.shapes.size();
        }
    } else if (t == "sphere" || t == "bubble") {
        if (!need(4)) return;
        s.type = ShapeType::kSphere;
        s.center = {r[0], r[1], r[2]};
        s.radius = r[3];
        s.inward = t == "bubble";
    } else if (t == "ring") {
        if (!need(8)) return;
        s.type = ShapeType::kRing;
        s.center = {r[0], r[1], r[2]};
        s.normal = {r[3], r[4], r[5]};
        s.r0 = std::fmin(r[6], r[7]);  // RADIANCE takes the radii in either order
        s.r1 = std::fmax(r[6], r[7]);
    } else if (t == "cone" || t == "cup") {
        if (!need(8)) return;
        s.type = ShapeType::kCone;
        s.p0 = {r[0], r[1], r[2]};
        s.p1 = {r[3], r[4], r[5]};
        s.r0 = r[6], s.r1 = r[7];
        s.inward = t == "cup";
        if (s.r0 == s.r1) s.type = ShapeType::kCylinder, s.radius = s.r0;
    } else {  // cylinder, tube
        if (!need(7)) return;
        s.type = ShapeType::kCylinder;
        s.p0 = {r[0], r[1], r[2]};
        s.p1 = {r[3], r[4], r[5]};
        s.radius = r[6];
        s.inward = t == "tube";
    }
    shape_spans_.push_back(where);
    shape_modifiers_.push_back(p.modifier.text);
    shape_tag_explicit_.push_back(tag.has_value());
    scene_.shapes.push_back(std::move(s));
}

std::optional<SkyModel> SceneBuilder::sky_of(const Definition& pattern, const Primitive& user) {
    // gensky's output names its sky function and file: `brightfunc 2 skybr skybright.cal`,
    // with the type, zenith and ground brightness (and for a sunny sky the normalisation and
    // the sun's direction) as real arguments. crex evaluates that sky itself.
    const Primitive& p = pattern.p;
    if (p.strings.size() < 2 || p.strings[0].text != "skybr" || p.strings[1].text != "skybright.cal") {
        refuse(pattern, user, fmt::format("brightfunc '{}' ({}) on a source is not supported: crex evaluates the sky function "
                                          "skybr of skybright.cal (what gensky writes) only", p.id.text,
                                          p.strings.size() >= 2 ? p.strings[0].text + " of " + p.strings[1].text : "no function"),
               "make the sky with '!gensky' (crex runs it itself), or give the source's glow no pattern");
        return std::nullopt;
    }
    const std::vector<double>& r = p.reals;
    if (r.size() != 3 && r.size() != 7) {
        report("E303", p.reals_span(), fmt::format("brightfunc '{}': skybr takes 3 or 7 real arguments, got {}", p.id.text, r.size()), &p);
        return std::nullopt;
    }
    SkyModel sky;
    if (!(r[0] == 1 || r[0] == 2 || r[0] == 3 || r[0] == 4)) {
        report("E303", p.real_spans[0], fmt::format("brightfunc '{}': the sky type must be 1 (clear), 2 (overcast), 3 (uniform) or "
                                                    "4 (intermediate), got {:g}", p.id.text, r[0]), &p);
        return std::nullopt;
    }
    sky.type = static_cast<SkyModel::Type>(static_cast<int>(r[0]));
    sky.zenith = r[1];
    sky.ground = r[2];
    if (r.size() == 7) {
        sky.normalization = r[3];
        sky.sun = normalize_or_zero({r[4], r[5], r[6]});
    } else if (sky.type == SkyModel::Type::kClear || sky.type == SkyModel::Type::kIntermediate) {
        report("E303", p.reals_span(), fmt::format("brightfunc '{}': a clear or intermediate sky needs 7 real arguments (with the "
                                                   "normalisation and the sun's direction)", p.id.text), &p);
        return std::nullopt;
    }
    if (!(sky.zenith >= 0 && sky.ground >= 0 && sky.normalization > 0) || sky.sun == Vec3{}) {
        report("E303", p.reals_span(), fmt::format("brightfunc '{}': the brightnesses must be >= 0, the normalisation > 0 and the sun's "
                                                   "direction non-zero", p.id.text), &p);
        return std::nullopt;
    }
    // A transform (from xform) may turn the sky about the zenith; it may not tip it.
    std::optional<Transform> xf = function_transform(p, 2);
    if (!xf) return std::nullopt;
    const Vec3 up = normalize_or_zero(xf->vector({0, 0, 1}));
    if (!(up.z > 1 - 1e-9)) {
        report("E307", p.strings.back().span, fmt::format("brightfunc '{}': a sky tipped away from +z is not supported", p.id.text), &p);
        return std::nullopt;
    }
    sky.sun = normalize_or_zero(xf->vector(sky.sun));
    return sky;
}

void SceneBuilder::distant_light(const Primitive& p, const Material& m, const std::optional<SkyModel>& sky) {
    const std::vector<double>& r = p.reals;
    if (r.size() != 4) {
        report("E303", p.reals_span(), fmt::format("source '{}' takes 4 real arguments (direction and angle), got {}", p.id.text, r.size()), &p);
        return;
    }
    if (m.type != MaterialType::kLight && m.type != MaterialType::kGlow && m.type != MaterialType::kIllum) {
        report("E303", p.modifier.span, fmt::format("source '{}': a distant source needs a light or glow material, '{}' is {}", p.id.text,
                                                    p.modifier.text, material_type_name(m.type)), &p);
        return;
    }
    DistantLight l;
    l.name = p.id.text;
    l.material = m.name;
    l.sky = sky;
    if (sky && m.type != MaterialType::kGlow) {
        report("E307", p.modifier.span, fmt::format("source '{}': a sky pattern is supported on a glow material only", p.id.text), &p);
        return;
    }
    l.direction = {r[0], r[1], r[2]};
    l.angle_deg = r[3];
    if (!(length(l.direction) > 0)) {
        report("E306", p.reals_span(0, 2), fmt::format("source '{}': the direction is zero", p.id.text), &p);
        return;
    }
    if (!(l.angle_deg > 0 && l.angle_deg <= 360)) {
        report("E303", p.real_spans[3], fmt::format("source '{}': the angle must be in (0, 360] degrees, got {:g}", p.id.text, l.angle_deg), &p);
        return;
    }
    if (m.spot) report("W306", p.modifier.span, fmt::format("source '{}': a distant source ignores its spotlight cone (as RADIANCE does)", p.id.text), &p);
    scene_.distant_lights.push_back(std::move(l));
}

// ---- #@crex directives -----------------------------------------------------------------------

void SceneBuilder::directive(const Directive& d) {
    std::vector<Word> words;
    const std::string& t = d.text;
    for (size_t i = 0; i < t.size();) {
        while (i < t.size() && std::isspace(static_cast<unsigned char>(t[i]))) ++i;
        size_t b = i;
        while (i < t.size() && !std::isspace(static_cast<unsigned char>(t[i]))) ++i;
        if (i > b) words.push_back({t.substr(b, i - b), {d.span.file, d.span.begin + static_cast<uint32_t>(b), d.span.begin + static_cast<uint32_t>(i)}});
    }
    if (words.size() >= 2 && words[1].text == "tag") return read_tag(words, d);
    if (words.size() >= 2 && words[1].text == "view") {
        std::vector<ViewWord> view;
        for (size_t k = 2; k < words.size(); ++k) view.push_back({words[k].text, words[k].span.begin, words[k].span.end});
        apply_radiance_view(*d.span.file, view, scene_.camera, !view_seen_, sink_);
        view_seen_ = true;
        return;
    }
    sink_.report("W301", d.span, "unknown #@crex directive (ignored); known: '#@crex tag ...', '#@crex view ...'");
}

void SceneBuilder::read_tag(const std::vector<Word>& words, const Directive& d) {
    if (words.size() == 3 && words[2].text == "end") {
        if (!block_tag_) {
            sink_.report("W301", words[2].span, "'#@crex tag end' with no '#@crex tag ... begin' open (ignored)");
            return;
        }
        finished_scopes_.push_back(*block_tag_);
        block_tag_.reset();
        return;
    }
    TagScope scope;
    scope.where = d.span;
    bool begin = false, have_name = false;
    std::optional<TagRule> rule;
    for (size_t k = 2; k < words.size(); ++k) {
        const std::string& w = words[k].text;
        size_t eq = w.find('=');
        std::string key = w.substr(0, eq), value = eq == std::string::npos ? "" : w.substr(eq + 1);
        if (w == "begin") begin = true;
        else if (key == "name" && !value.empty()) scope.tag.name = value, have_name = true;
        else if (key == "task" && value.size() == 1 && value[0] >= '0' && value[0] <= '3') scope.tag.task = value[0] - '0';
        else if (key == "distractor" && (value == "true" || value == "false")) scope.tag.distractor = value == "true";
        else if ((key == "object" || key == "prefix" || key == "modifier") && !value.empty() && eq != std::string::npos)
            rule = TagRule{key == "object" ? TagRule::Kind::kObject : key == "prefix" ? TagRule::Kind::kPrefix : TagRule::Kind::kModifier, value, {}};
        else
            sink_.report("E303", words[k].span, fmt::format("tag: cannot read '{}'; expected name=NAME, task=0..3, distractor=true|false, "
                                                            "and at most one of object=NAME, prefix=TEXT, modifier=NAME or begin", w));
    }
    if (!have_name) {
        sink_.report("E304", d.span, "tag: name=NAME is missing");
        return;
    }
    if (rule && begin) {
        sink_.report("E303", d.span, "tag: 'begin' tags what follows; object=, prefix= and modifier= tag by name: give one of them");
        return;
    }
    if (rule) {
        rule->scope = scope;
        rules_.push_back(std::move(*rule));
    } else if (begin) {
        if (block_tag_) {
            sink_.report("E303", d.span, "tag: a '#@crex tag ... begin' is already open; blocks do not nest").notes.push_back(
                {block_tag_->where, "opened here"});
            return;
        }
        block_tag_ = scope;
    } else {
        if (pending_tag_) finished_scopes_.push_back(*pending_tag_);  // tags nothing: warned at the end
        pending_tag_ = scope;
    }
}

std::optional<Tag> SceneBuilder::tag_for_next_surface() {
    if (pending_tag_) {  // the next surface's own tag
        ++pending_tag_->surfaces;
        finished_scopes_.push_back(*pending_tag_);
        pending_tag_.reset();
        return finished_scopes_.back().tag;
    }
    for (auto it = command_tags_.rbegin(); it != command_tags_.rend(); ++it)
        if (*it) {
            ++(*it)->surfaces;
            return (*it)->tag;
        }
    if (block_tag_) {
        ++block_tag_->surfaces;
        return block_tag_->tag;
    }
    return std::nullopt;
}

void SceneBuilder::command_begins(const SourceSpan&) {
    command_tags_.push_back(pending_tag_);
    pending_tag_.reset();
}

void SceneBuilder::command_ends() {
    if (command_tags_.empty()) return;
    if (command_tags_.back()) finished_scopes_.push_back(*command_tags_.back());
    command_tags_.pop_back();
}

void SceneBuilder::finish() {
    finish_mists();
    if (pending_tag_) finished_scopes_.push_back(*pending_tag_), pending_tag_.reset();
    if (block_tag_) {
        sink_.report("W301", block_tag_->where, "'#@crex tag ... begin' is never ended: it tags everything to the end of the file");
        finished_scopes_.push_back(*block_tag_), block_tag_.reset();
    }
    for (TagRule& rule : rules_) {
        for (size_t i = 0; i < scene_.shapes.size(); ++i) {
            Shape& s = scene_.shapes[i];
            if (shape_tag_explicit_[i] || s.tag) continue;  // a surface's own tag wins; then the first rule
            bool match = false;
            if (rule.kind == TagRule::Kind::kModifier) match = shape_modifiers_[i] == rule.text;
            else if (rule.kind == TagRule::Kind::kPrefix) match = s.name.rfind(rule.text, 0) == 0;
            else match = s.name == rule.text || s.name.rfind(rule.text + ".", 0) == 0;
            if (!match) continue;
            s.tag = rule.scope.tag;
            ++rule.scope.surfaces;
        }
        finished_scopes_.push_back(rule.scope);
    }
    for (const TagScope& t : finished_scopes_)
        if (t.surfaces == 0)
            sink_.report("W307", t.where, fmt::format("tag '{}' tags no surface", t.tag.name)).help =
                "a tag without a scope tags the next surface, or everything the next '!' command makes; object=, prefix= and "
                "modifier= tag surfaces by name";
}

}  // namespace crex::radiance
