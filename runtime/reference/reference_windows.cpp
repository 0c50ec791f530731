#include "runtime/reference/reference_windows.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "runtime/cache/caustic_photons.h"
#include "runtime/pipeline/pixel_probe.h"
#include "runtime/render/render_scene.h"

namespace crex {
namespace {

// Means of one value a pixel over any rectangle, from a summed-area table.
class BoxMeans {
public:
    BoxMeans(const std::vector<double>& values, int width, int height) : w_(width), sums_((static_cast<size_t>(width) + 1) * (static_cast<size_t>(height) + 1), 0.0) {
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                at(x + 1, y + 1) = values[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] + at(x, y + 1) + at(x + 1, y) - at(x, y);
    }
    double mean(const PixelWindow& r) const {
        const double s = get(r.x + r.width, r.y + r.height) - get(r.x, r.y + r.height) - get(r.x + r.width, r.y) + get(r.x, r.y);
        return s / (static_cast<double>(r.width) * static_cast<double>(r.height));
    }

private:
    double& at(int x, int y) { return sums_[static_cast<size_t>(y) * (static_cast<size_t>(w_) + 1) + static_cast<size_t>(x)]; }
    double get(int x, int y) const { return sums_[static_cast<size_t>(y) * (static_cast<size_t>(w_) + 1) + static_cast<size_t>(x)]; }
    int w_;
    std::vector<double> sums_;
};

// Window positions on a grid of a quarter of the size, the last row and column flush with the
// frame's edge.
std::vector<PixelWindow> grid_positions(int width, int height, int size) {
    auto steps = [&](int extent) {
        std::vector<int> at;
        const int step = std::max(1, size / 4);
        for (int v = 0; v + size <= extent; v += step) at.push_back(v);
        if (at.empty() || at.back() != extent - size) at.push_back(extent - size);
        return at;
    };
    std::vector<PixelWindow> out;
    for (int y : steps(height))
        for (int x : steps(width)) out.push_back({x, y, size, size});
    return out;
}

bool overlaps(const PixelWindow& a, const PixelWindow& b) {
    return a.width > 0 && b.width > 0 && a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

class Placement {
public:
    Placement(int width, int height, int size) : positions_(grid_positions(width, height, size)) {}
    // Free positions: overlapping no window chosen so far.
    std::vector<PixelWindow> free() const {
        std::vector<PixelWindow> out;
        for (const PixelWindow& p : positions_)
            if (std::none_of(chosen_.begin(), chosen_.end(), [&](const ChosenWindow& c) { return overlaps(p, c.window); })) out.push_back(p);
        return out;
    }
    void add(ChosenWindow c) { chosen_.push_back(std::move(c)); }
    // The free position whose centre is nearest (cx, cy); width 0 if none is free.
    PixelWindow nearest(double cx, double cy) const {
        PixelWindow best{};
        double d_best = std::numeric_limits<double>::infinity();
        for (const PixelWindow& p : free()) {
            const double dx = p.x + p.width / 2.0 - cx, dy = p.y + p.height / 2.0 - cy, d = dx * dx + dy * dy;
            if (d < d_best) d_best = d, best = p;
        }
        return best;
    }
    // The free position with the largest (sign +1) or smallest (-1) mean of `means`.
    PixelWindow extreme(const BoxMeans& means, double sign, double& value) const {
        return extreme_where(means, sign, value, [](const PixelWindow&) { return true; });
    }
    // The same among the positions `allowed` keeps; width 0 (value 0) if none is.
    template <typename Allowed>
    PixelWindow extreme_where(const BoxMeans& means, double sign, double& value, Allowed allowed) const {
        PixelWindow best{};
        double v_best = -std::numeric_limits<double>::infinity();
        for (const PixelWindow& p : free())
            if (const double v = sign * means.mean(p); v > v_best && allowed(p)) v_best = v, best = p;
        value = best.width ? sign * v_best : 0;
        return best;
    }
    const std::vector<ChosenWindow>& chosen() const { return chosen_; }

private:
    std::vector<PixelWindow> positions_;
    std::vector<ChosenWindow> chosen_;
};

struct Centroid {
    double x = 0, y = 0;
    size_t pixels = 0;
};

Centroid centroid_of(const std::vector<char>& mask, int width) {
    Centroid c;
    for (size_t p = 0; p < mask.size(); ++p)
        if (mask[p]) c.x += static_cast<double>(p % static_cast<size_t>(width)) + 0.5, c.y += static_cast<double>(p / static_cast<size_t>(width)) + 0.5, ++c.pixels;
    if (c.pixels) c.x /= static_cast<double>(c.pixels), c.y /= static_cast<double>(c.pixels);
    return c;
}

bool emits(const Material& m) { return m.type == MaterialType::kLight || m.type == MaterialType::kGlow; }

}  // namespace

std::vector<ChosenWindow> choose_reference_windows(const Scene& scene, const FrameContext& context, int size, uint64_t seed) {
    const int width = context.width, height = context.height;
    size = std::clamp(size, 1, std::min(width, height));
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    RenderScene rs(scene);
    const PixelProbe probe = probe_pixels(rs, width, height);
    Placement place(width, height, size);
    auto material_of_shape = [&](int32_t s) -> const Material& { return *scene.find_material(scene.shapes[static_cast<size_t>(s)].material); };

    // 1-2. Tagged objects.
    for (const std::string kind : {"task", "distractor"}) {
        std::vector<char> mask(pixels, 0);
        for (size_t p = 0; p < pixels; ++p) {
            if (probe.shape[p] < 0) continue;
            const auto& tag = scene.shapes[static_cast<size_t>(probe.shape[p])].tag;
            mask[p] = tag && (kind == "task" ? tag->task > 0 : tag->distractor);
        }
        const Centroid c = centroid_of(mask, width);
        if (!c.pixels) {
            place.add({kind, {}, fmt::format("no tagged {} object in view", kind)});
            continue;
        }
        double share = 0;
        const PixelWindow w = place.extreme(BoxMeans(std::vector<double>(mask.begin(), mask.end()), width, height), +1, share);
        place.add({kind, w, w.width && share > 0 ? fmt::format("covers the most of its {} pixels ({:.0f} % of the window)", c.pixels, 100 * share)
                                                  : "no room left"});
    }

    // 3. The emitter covering most pixels, at the point of its outline nearest its centroid.
    {
        // Seen directly, else in a mirror (the Cornell box at 16:9 shows its lamp only in the
        // mirror ball).
        const std::vector<int32_t>* sees = &probe.shape;
        std::map<int32_t, size_t> seen;
        for (const std::vector<int32_t>* through : {&probe.shape, &probe.detected}) {
            for (size_t p = 0; p < pixels; ++p)
                if ((*through)[p] >= 0 && emits(material_of_shape((*through)[p]))) ++seen[(*through)[p]];
            sees = through;
            if (!seen.empty()) break;
        }
        if (seen.empty()) {
            place.add({"lamp", {}, "no emitter in view"});
        } else {
            const int32_t lamp = std::max_element(seen.begin(), seen.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
            std::vector<char> mask(pixels, 0);
            for (size_t p = 0; p < pixels; ++p) mask[p] = (*sees)[p] == lamp;
            const Centroid c = centroid_of(mask, width);
            double best = std::numeric_limits<double>::infinity(), tx = c.x, ty = c.y;
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x) {
                    auto in = [&](int u, int v) { return u < 0 || v < 0 || u >= width || v >= height || mask[static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u)]; };
                    if (!mask[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)]) continue;
                    if (in(x - 1, y) && in(x + 1, y) && in(x, y - 1) && in(x, y + 1)) continue;  // inside, or cut by the frame
                    const double dx = x + 0.5 - c.x, dy = y + 0.5 - c.y;
                    if (dx * dx + dy * dy < best) best = dx * dx + dy * dy, tx = x + 0.5, ty = y + 0.5;
                }
            const PixelWindow w = place.nearest(tx, ty);
            const std::string& name = scene.shapes[static_cast<size_t>(lamp)].name;
            place.add({"lamp", w, w.width ? fmt::format("emitter '{}' ({} pixels{}): nearest its outline's point ({:.0f}, {:.0f}) closest to its centroid",
                                                        name.empty() ? fmt::format("#{}", lamp) : name, seen[lamp],
                                                        sees == &probe.shape ? "" : " seen in a mirror", tx, ty)
                                          : "no room left"});
        }
    }

    // 4. The caustic map's irradiance on the surfaces seen.
    {
        CausticPhotonSettings cs;
        cs.seed = seed;
        const CausticPhotons photons(rs, cs);
        std::vector<double> caustic(pixels, 0.0);
        if (!photons.empty()) {
            CameraRays camera(scene.camera, width, height, rs.embree->origin_offset());
            for (size_t p = 0; p < pixels; ++p) {
                if (probe.shape[p] < 0 || emits(material_of_shape(probe.shape[p]))) continue;
                Vec3 o, d;
                camera.generate(static_cast<double>(p % static_cast<size_t>(width)) + 0.5, static_cast<double>(p / static_cast<size_t>(width)) + 0.5, o, d);
                const Vec3 e = photons.irradiance(o + d * static_cast<double>(probe.distance[p]), probe.normal[p]);
                caustic[p] = luminance(e);
            }
        }
        double value = 0;
        const PixelWindow w = place.extreme(BoxMeans(caustic, width, height), +1, value);
        if (photons.empty() || !(value > 0))
            place.add({"caustic", {}, photons.empty() ? "no caustic paths (no mirror, glass or trans surface lit by a lamp)" : "no caustic in view"});
        else
            place.add({"caustic", w, w.width ? fmt::format("largest mean caustic irradiance over the window ({:.3g})", value) : "no room left"});
    }

    // 5-6. The whole frame's saliency, away from emitters (the lamp has its window) and from
    // black pixels (the Cornell box's mirror ball shows the dark outside of the box, whose
    // rim is salient: a window there compares black with black, error 0 whatever the render).
    std::vector<double> excluded(pixels, 0.0);
    for (size_t p = 0; p < pixels; ++p)
        excluded[p] = (probe.shape[p] >= 0 && emits(material_of_shape(probe.shape[p]))) ||
                      !(luminance({context.rgb[3 * p], context.rgb[3 * p + 1], context.rgb[3 * p + 2]}) > 0);
    const BoxMeans lamps(excluded, width, height);
    const std::vector<double> saliency(context.saliency.begin(), context.saliency.end());
    const BoxMeans sal(saliency, width, height);
    for (const double sign : {+1.0, -1.0}) {
        double value = 0;
        const PixelWindow w = place.extreme_where(sal, sign, value, [&](const PixelWindow& p) { return lamps.mean(p) == 0; });
        const char* kind = sign > 0 ? "salient" : "plain";
        place.add({kind, w, w.width ? fmt::format("{} mean saliency over the window ({:.3f})", sign > 0 ? "largest" : "smallest", value) : "no room left"});
    }
    return place.chosen();
}

}  // namespace crex
