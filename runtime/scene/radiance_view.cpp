#include "runtime/scene/radiance_view.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace crex {

std::vector<ViewWord> view_file_words(const SourceFile& vf) {
    std::vector<ViewWord> words;
    const std::string& t = vf.text();
    size_t i = 0;
    while (i < t.size()) {
        if (t[i] == '#') {
            while (i < t.size() && t[i] != '\n') ++i;
            continue;
        }
        if (std::isspace(static_cast<unsigned char>(t[i]))) {
            ++i;
            continue;
        }
        size_t b = i;
        while (i < t.size() && !std::isspace(static_cast<unsigned char>(t[i]))) ++i;
        words.push_back({t.substr(b, i - b), static_cast<uint32_t>(b), static_cast<uint32_t>(i)});
    }
    if (!words.empty() && words[0].text.rfind("-", 0) != 0) words.erase(words.begin());
    return words;
}

namespace {

// The largest field of view each projection can show (degrees): perspective and the
// cylinder's height stop short of 180, the fisheyes reach around.
double max_fov(Projection p, bool horizontal) {
    switch (p) {
    case Projection::kPerspective: return 180;
    case Projection::kParallel: return INFINITY;
    case Projection::kAngular: return 360;
    case Projection::kHemispherical: return 180;
    case Projection::kStereographic: return 360;
    case Projection::kCylindrical: return horizontal ? 360 : 180;
    }
    return 180;
}

bool closed_limit(Projection p, bool horizontal) {
    return p == Projection::kAngular || p == Projection::kHemispherical || (p == Projection::kCylindrical && horizontal);
}

}  // namespace

void apply_radiance_view(const SourceFile& f, const std::vector<ViewWord>& w, Camera& cam, bool fresh, DiagnosticSink& sink) {
    if (fresh) {
        cam.position = {0, 0, 0};
        cam.direction = {0, 1, 0};
        cam.up = {0, 0, 1};
        cam.vfov_deg = 45;
        cam.hfov_deg = 45;
        cam.projection = Projection::kPerspective;
        cam.fore_clip = 0;
    }
    auto number = [&](size_t k, double& out) {
        if (k >= w.size()) {
            sink.report("E301", {&f, w.back().end, w.back().end}, fmt::format("view option '{}' needs more numbers", w.back().text));
            return false;
        }
        char* end = nullptr;
        out = std::strtod(w[k].text.c_str(), &end);
        if (end != w[k].text.c_str() + w[k].text.size() || !std::isfinite(out)) {
            sink.report("E302", {&f, w[k].begin, w[k].end}, fmt::format("view: expected a finite number, got '{}'", w[k].text));
            return false;
        }
        return true;
    };
    // Angles are checked once the view type is known (a fisheye takes up to 360 degrees).
    struct Angle {
        bool horizontal;
        double value;
        size_t word;
    };
    std::vector<Angle> angles;
    bool ok = true;
    for (size_t k = 0; k < w.size() && ok; ++k) {
        const std::string& o = w[k].text;
        Vec3* v = o == "-vp" ? &cam.position : o == "-vd" ? &cam.direction : o == "-vu" ? &cam.up : nullptr;
        if (v) {
            double x, y, z;
            if (!number(k + 1, x) || !number(k + 2, y) || !number(k + 3, z)) return;
            *v = {x, y, z};
            k += 3;
        } else if (o == "-vh" || o == "-vv") {
            double a;
            if (!number(k + 1, a)) return;
            (o == "-vh" ? cam.hfov_deg : cam.vfov_deg) = a;
            angles.push_back({o == "-vh", a, k + 1});
            ++k;
        } else if (o == "-vo") {
            double d;
            if (!number(k + 1, d)) return;
            if (!(d >= 0)) {
                sink.report("E303", {&f, w[k + 1].begin, w[k + 1].end}, fmt::format("view -vo: the fore clipping distance must be >= 0, got {}", d));
                return;
            }
            cam.fore_clip = d;
            ++k;
        } else if (o.size() == 4 && o.rfind("-vt", 0) == 0 && std::string("vlahsc").find(o[3]) != std::string::npos) {
            switch (o[3]) {
            case 'v': cam.projection = Projection::kPerspective; break;
            case 'l': cam.projection = Projection::kParallel; break;
            case 'a': cam.projection = Projection::kAngular; break;
            case 'h': cam.projection = Projection::kHemispherical; break;
            case 's': cam.projection = Projection::kStereographic; break;
            default: cam.projection = Projection::kCylindrical; break;
            }
        } else if (o.rfind("-vt", 0) == 0) {
            sink.report("E307", {&f, w[k].begin, w[k].end},
                        fmt::format("view type '{}' is not a RADIANCE view type; known: -vtv -vtl -vta -vth -vts -vtc", o));
            ok = false;
        } else if (o == "-vs" || o == "-vl" || o == "-va") {
            double x;
            if (!number(k + 1, x)) return;
            if (x != 0)
                sink.report("W301", {&f, w[k].begin, w[k + 1].end}, fmt::format("view option '{}' (view shift, lift or aft clipping) is ignored", o));
            ++k;
        } else {
            sink.report("W301", {&f, w[k].begin, w[k].end}, fmt::format("view option '{}' is ignored", o));
        }
    }
    for (const Angle& a : angles) {
        const double hi = max_fov(cam.projection, a.horizontal);
        const bool closed = closed_limit(cam.projection, a.horizontal);
        if (!(a.value > 0 && (closed ? a.value <= hi : a.value < hi))) {
            sink.report("E303", {&f, w[a.word].begin, w[a.word].end},
                        cam.projection == Projection::kParallel
                            ? fmt::format("view {}: a parallel view's size must be > 0, got {}", a.horizontal ? "-vh" : "-vv", a.value)
                            : fmt::format("view {}: expected an angle in (0, {}{} degrees for this view type, got {}", a.horizontal ? "-vh" : "-vv",
                                          hi, closed ? "]" : ")", a.value));
            return;
        }
    }
    if (!(length(cross(cam.direction, cam.up)) > 0))
        sink.report("E306", {&f, w.empty() ? 0 : w.front().begin, w.empty() ? 0 : w.back().end},
                    "view: the direction is zero or parallel to the up vector");
}

}  // namespace crex
