#include "runtime/scene/text_pattern.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

namespace crex {
namespace {

// RADIANCE's fixed cells: each character with a glyph 255 units wide.
int uniform(const Font& f, const std::string& s, std::vector<int>& sp) {
    sp.assign(s.size() + 1, 0);
    int width = 0;
    for (size_t k = 0; k < s.size(); ++k) width += sp[k + 1] = f.glyph(s[k]) ? 255 : 0;
    return width;
}

// RADIANCE's squeezed text: `gap` font units between letters' extents, half of it at each
// end; a blank glyph (a space) takes the font's mean width.
int squeeze(const Font& f, const std::string& s, std::vector<int>& sp, int gap) {
    sp.assign(s.size() + 1, 0);
    size_t t = 0, k = 0;
    const Font::Glyph* g = nullptr;
    while (t < s.size() && !(g = f.glyph(s[t++]))) sp[k++] = 0;
    const int half = gap / 2;
    sp[k] = half;
    int width = 0;
    while (g) {
        if (!g->vertices.empty()) {
            sp[k] += half - g->left;
            width += sp[k++];
            sp[k] = g->right + half;
        } else {
            width += sp[k++];
            sp[k] = f.mean_width;
        }
        g = nullptr;
        while (t < s.size() && !(g = f.glyph(s[t++]))) {
            width += sp[k++];
            sp[k] = 0;
        }
    }
    sp[k] += half;
    return width + sp[k];
}

// RADIANCE's proportional text: squeezed, then each run of letters (ended by more than
// `indent` blanks) stretched to (mean width + gap) per character, the difference shared
// among its slots.
int proportional(const Font& f, const std::string& s, std::vector<int>& sp, int gap, size_t indent) {
    squeeze(f, s, sp, gap);
    size_t k = 0, t = 0;
    int width = sp[k++];
    while (t < s.size()) {
        long target = 0, actual = 0;
        size_t next = k, end = t, tab = t;
        for (; end < s.size(); end = tab) {
            tab = end + 1;
            actual += sp[next++];
            if (f.glyph(s[end])) {
                const Font::Glyph* g;
                while (tab < s.size() && (g = f.glyph(s[tab])) && g->vertices.empty()) {
                    actual += sp[next++];
                    ++tab;
                }
                target += static_cast<long>(tab - end);
            }
            if (indent && tab - end > indent) break;
        }
        target *= f.mean_width + gap;
        width += static_cast<int>(target);
        long adjust = target - actual;
        while (k < next) {
            const long share = adjust / static_cast<long>(next - k);
            sp[k++] += static_cast<int>(share);
            adjust -= share;
        }
        t = tab;
    }
    return width;
}

}  // namespace

bool parse_font(const std::string& text, Font& out, std::string& error) {
    // Whitespace-separated integers; '#' to the end of the line is a comment.
    Font f;
    size_t i = 0;
    int line = 1;
    auto next = [&](long& value) -> int {  // 1: a value, 0: end of text, -1: not an integer
        for (;;) {
            while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) line += text[i++] == '\n';
            if (i < text.size() && text[i] == '#') {
                while (i < text.size() && text[i] != '\n') ++i;
                continue;
            }
            break;
        }
        if (i >= text.size()) return 0;
        const char* begin = text.c_str() + i;
        char* end = nullptr;
        value = std::strtol(begin, &end, 10);
        if (end == begin || (*end && !std::isspace(static_cast<unsigned char>(*end)) && *end != '#')) return -1;
        i += static_cast<size_t>(end - begin);
        return 1;
    };
    auto fail = [&](const std::string& what) {
        error = fmt::format("line {}: {}", line, what);
        return false;
    };
    long wsum = 0, count = 0;
    for (;;) {
        long code = 0, n = 0;
        const int got = next(code);
        if (got == 0) break;
        if (got < 0) return fail("expected a character code (an integer)");
        if (code < 1 || code > 255) return fail(fmt::format("a character code must be 1 to 255, got {}", code));
        Font::Glyph& g = f.glyphs[static_cast<size_t>(code)];
        if (g.present) return fail(fmt::format("character {} is defined twice", code));
        if (next(n) <= 0 || n < 0 || n > 32000) return fail(fmt::format("character {}: expected its number of vertices (0 to 32000)", code));
        g.present = true;
        for (long v = 0; v < n; ++v) {
            long x = 0, y = 0;
            if (next(x) <= 0 || next(y) <= 0 || x < 0 || x > 255 || y < 0 || y > 255)
                return fail(fmt::format("character {}: vertex {} needs two integers from 0 to 255", code, v + 1));
            g.vertices.push_back({static_cast<int>(x), static_cast<int>(y)});
            g.left = std::min(g.left, static_cast<int>(x)), g.right = std::max(g.right, static_cast<int>(x));
            g.bottom = std::min(g.bottom, static_cast<int>(y)), g.top = std::max(g.top, static_cast<int>(y));
        }
        if (g.right - g.left && g.top - g.bottom) ++count, wsum += g.right - g.left;
    }
    if (count) f.mean_width = static_cast<int>(wsum / count);
    out = std::move(f);
    return true;
}

TextLayout::TextLayout(Font font, std::vector<std::string> lines, Vec3 origin, Vec3 right, Vec3 down, bool has_spacing, double spacing)
    : font_(std::move(font)), origin_(origin) {
    // The dual basis: right_ . right = 1, right_ . down = 0, and the same for down_.
    const Vec3 dxr = cross(down, right);
    const Vec3 a = cross(dxr, down), b = cross(right, dxr);
    const double la = dot(a, a), lb = dot(b, b);
    constexpr double kTiny = 1e-24;  // RADIANCE's FTINY^4
    valid_ = la > kTiny && lb > kTiny && std::isfinite(la) && std::isfinite(lb);
    if (!valid_) return;
    right_ = a * (dot(down, down) / la);
    down_ = b * (dot(right, right) / lb);
    if (has_spacing) scale_ = font_.mean_width + 255 * std::fabs(spacing);
    const int gap = static_cast<int>(std::fmax(-1e6, std::fmin(1e6, spacing * 255)));
    for (std::string& text : lines) {
        Line l;
        l.text = std::move(text);
        l.width = gap < 0 ? squeeze(font_, l.text, l.offsets, -gap)
                : gap > 0 ? proportional(font_, l.text, l.offsets, gap, 3)
                          : uniform(font_, l.text, l.offsets);
        lines_.push_back(std::move(l));
    }
}

bool TextLayout::inside(const Vec3& point) const {
    if (!valid_) return false;
    const Vec3 v = point - origin_;
    double x = dot(v, right_) * scale_;
    const double y = dot(v, down_);
    if (!(x >= 0 && y >= 0) || x > 1e9 || y > 1e9) return false;
    int h = static_cast<int>(x);
    const auto row = static_cast<size_t>(y);
    x -= h;
    const double gy = (static_cast<double>(row + 1) - y) * 255;  // 255 at the line's top, 0 at its foot
    if (row >= lines_.size() || h >= lines_[row].width) return false;
    const Line& l = lines_[row];
    for (size_t c = 0; c < l.offsets.size() && (h -= l.offsets[c]) >= 0; ++c)
        if (c < l.text.size() && h < 255 && in_glyph(h + x, gy, font_.glyph(l.text[c]))) return true;
    return false;
}

bool TextLayout::in_glyph(double x, double y, const Font::Glyph* g) const {
    // Crossings of a ray along +x from the point, even-odd; the straddle tests use the centre of
    // the point's unit cell (no ties on integer vertices), the side test the point itself.
    if (!g || g->vertices.empty()) return false;
    const int xl = static_cast<int>(x), yl = static_cast<int>(y);
    if (g->left > xl || g->right <= xl || g->bottom > yl || g->top <= yl) return false;
    const int x2 = 2 * xl + 1, y2 = 2 * yl + 1;
    int crossings = 0;
    const auto& vs = g->vertices;
    const std::array<int, 2>* p0 = &vs.back();
    for (const auto& p1 : vs) {
        if ((2 * (*p0)[1] > y2) != (2 * p1[1] > y2)) {
            const int tv = (2 * (*p0)[0] > x2) | ((2 * p1[0] > x2) << 1);
            if (tv == 3) ++crossings;
            else if (tv)
                crossings += (p1[1] > (*p0)[1]) ^ (((*p0)[1] - y) * (p1[0] - x) > ((*p0)[0] - x) * (p1[1] - y));
        }
        p0 = &p1;
    }
    return crossings & 1;
}

}  // namespace crex
