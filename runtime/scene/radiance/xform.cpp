#include "runtime/scene/radiance/xform.h"

#include <algorithm>
#include <cmath>

#include "runtime/scene/radiance/primitive_types.h"

namespace crex::radiance {
namespace {

Vec3 at(const std::vector<double>& r, size_t i) { return {r[i], r[i + 1], r[i + 2]}; }
void put(std::vector<double>& r, size_t i, const Vec3& v) { r[i] = v.x, r[i + 1] = v.y, r[i + 2] = v.z; }

// Mist names the light sources it scatters; they are renamed with the prefix as surfaces are
// ("a>b" names source b relayed by a: each part gets it).
std::string prefixed_source_list(const std::string& prefix, const std::string& names) {
    std::string out;
    size_t start = 0;
    while (start <= names.size()) {
        size_t gt = names.find('>', start);
        std::string part = names.substr(start, gt == std::string::npos ? std::string::npos : gt - start);
        out += prefix + "." + part;
        if (gt == std::string::npos) break;
        out += '>';
        start = gt + 1;
    }
    return out;
}

void transform_surface(const XformContext& c, Primitive& p, bool reverse) {
    const Transform& t = c.xf;
    const double s = std::fabs(t.scale());
    std::vector<double>& r = p.reals;
    const std::string& type = p.type.text;
    if (type == "source") {
        if (r.size() == 4) put(r, 0, t.vector(at(r, 0)));
    } else if (type == "sphere" || type == "bubble") {
        if (r.size() == 4) put(r, 0, t.point(at(r, 0))), r[3] *= s;
    } else if (type == "polygon") {
        if (r.size() % 3 != 0) return;
        const size_t n = r.size() / 3;
        std::vector<double> out(r.size());
        std::vector<SourceSpan> spans(p.real_spans.size());
        for (size_t v = 0; v < n; ++v) {
            const size_t from = reverse ? n - 1 - v : v;
            put(out, 3 * v, t.point(at(r, 3 * from)));
            if (spans.size() == r.size())
                for (size_t k = 0; k < 3; ++k) spans[3 * v + k] = p.real_spans[3 * from + k];
        }
        r = std::move(out);
        if (spans.size() == r.size()) p.real_spans = std::move(spans);
    } else if (type == "cone" || type == "cup") {
        if (r.size() == 8) put(r, 0, t.point(at(r, 0))), put(r, 3, t.point(at(r, 3))), r[6] *= s, r[7] *= s;
    } else if (type == "cylinder" || type == "tube") {
        if (r.size() == 7) put(r, 0, t.point(at(r, 0))), put(r, 3, t.point(at(r, 3))), r[6] *= s;
    } else if (type == "ring") {
        if (r.size() != 8) return;
        put(r, 0, t.point(at(r, 0)));
        Vec3 n = t.vector(at(r, 3));
        put(r, 3, c.invert ? -n : n);
        r[6] *= s, r[7] *= s;
    }
}

void transform_modifier(const XformContext& c, Primitive& p, const PrimitiveTypeInfo* info) {
    const Transform& t = c.xf;
    const double s = std::fabs(t.scale());
    std::vector<double>& r = p.reals;
    const std::string& type = p.type.text;
    if (type == "glow") {
        if (r.size() == 4) r[3] *= s;
    } else if (type == "spotlight") {
        if (r.size() == 7) put(r, 4, t.vector(at(r, 4)));
    } else if (type == "dielectric" || type == "interface") {
        // Transmission per unit length: a unit of the scene grows by s.
        auto per_unit = [&](size_t i) {
            for (size_t k = i; k < i + 3; ++k) r[k] = std::pow(std::fmax(r[k], 0.0), 1.0 / s);
        };
        if (type == "dielectric" && r.size() == 5) per_unit(0);
        if (type == "interface" && r.size() == 8) per_unit(0), per_unit(4);
    } else if (type == "mist") {
        if (r.size() >= 3 && r.size() <= 7)
            for (size_t k = 0; k < 3; ++k) r[k] /= s;
        if (!c.prefix.empty())
            for (Word& w : p.strings) w.text = prefixed_source_list(c.prefix, w.text);
    } else if (type == "colortext" || type == "brighttext" || type == "mixtext") {
        if (r.size() >= 9) put(r, 0, t.point(at(r, 0))), put(r, 3, t.vector(at(r, 3))), put(r, 6, t.vector(at(r, 6)));
    }
    if (info && info->function_transform && !c.xf_words.empty()) {
        const SourceSpan where = p.strings.empty() ? p.span : p.strings.back().span;
        for (const std::string& w : c.xf_words) p.strings.push_back({w, where});
    }
}

}  // namespace

std::vector<std::string> XformContext::appended_words(const std::vector<std::string>& words) {
    if (words.empty()) return {};
    std::vector<std::string> out;
    if (words.front() != "-i") out = {"-i", "1"};
    out.insert(out.end(), words.begin(), words.end());
    return out;
}

XformContext XformContext::nest(const XformContext& inner, const XformContext& outer) {
    XformContext c;
    c.xf = inner.xf.then(outer.xf);
    c.xf_words = inner.xf_words;
    c.xf_words.insert(c.xf_words.end(), outer.xf_words.begin(), outer.xf_words.end());
    c.prefix = outer.prefix.empty() ? inner.prefix : inner.prefix.empty() ? outer.prefix : outer.prefix + "." + inner.prefix;
    c.modifier = outer.modifier ? outer.modifier : inner.modifier;
    c.invert = inner.invert != outer.invert;
    return c;
}

void apply_xform(const XformContext& c, Primitive& p) {
    if (c.identity()) return;
    const PrimitiveTypeInfo* info = find_primitive_type(p.type.text);
    if (p.is_alias() || !info) return;
    if (info->kind != PrimitiveKind::kSurface) {
        transform_modifier(c, p, info);
        return;
    }
    if (c.modifier) p.modifier = *c.modifier;
    if (c.invert) p.type.text = std::string(inverted_surface_type(p.type.text));
    if (!c.prefix.empty()) p.id.text = c.prefix + "." + p.id.text;
    transform_surface(c, p, c.xf.mirrors() != c.invert);
    if (info->function_transform && !c.xf_words.empty()) {  // instance, mesh: their transform follows the file
        const SourceSpan where = p.strings.empty() ? p.span : p.strings.back().span;
        for (const std::string& w : c.xf_words) p.strings.push_back({w, where});
    }
}

}  // namespace crex::radiance
