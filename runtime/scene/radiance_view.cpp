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

void apply_radiance_view(const SourceFile& f, const std::vector<ViewWord>& w, Camera& cam, bool fresh, DiagnosticSink& sink) {
    if (fresh) {
        cam.position = {0, 0, 0};
        cam.direction = {0, 1, 0};
        cam.up = {0, 0, 1};
        cam.vfov_deg = 45;
        cam.hfov_deg = 45;
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
    for (size_t k = 0; k < w.size(); ++k) {
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
            if (!(a > 0 && a < 180)) {
                sink.report("E303", {&f, w[k + 1].begin, w[k + 1].end}, fmt::format("view {}: expected an angle in (0, 180) degrees, got {}", o, a));
                return;
            }
            (o == "-vh" ? cam.hfov_deg : cam.vfov_deg) = a;
            ++k;
        } else if (o == "-vtv") {
            // perspective: the only projection we render
        } else if (o.rfind("-vt", 0) == 0) {
            sink.report("E307", {&f, w[k].begin, w[k].end}, fmt::format("view type '{}' is not supported; only perspective (-vtv)", o));
        } else {
            sink.report("W301", {&f, w[k].begin, w[k].end}, fmt::format("view option '{}' is ignored", o));
        }
    }
    if (!(length(cross(cam.direction, cam.up)) > 0))
        sink.report("E306", {&f, w.empty() ? 0 : w.front().begin, w.empty() ? 0 : w.back().end},
                    "view: the direction is zero or parallel to the up vector");
}

}  // namespace crex
