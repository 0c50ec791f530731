/// \file render_scene.h
/// What the renderer needs of a scene beyond the BVH: materials by geometry, the sampled
/// emitters (`light` surfaces) with a power-proportional choice between them, and the camera.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "runtime/render/bsdf.h"
#include "runtime/render/medium.h"
#include "runtime/scene/scene.h"
#include "runtime/trace/embree_scene.h"

namespace crex {

struct LightSample {
    Vec3 position;  ///< local coordinates
    Vec3 normal;    ///< unit, the emitting side
    Vec3 radiance;
    double pdf_area = 0;  ///< pdf of this point, per unit area, including the choice of emitter
    bool sphere = false;  ///< on an analytic sphere (whose hit distance Embree finds less precisely)
};

/// Emitters of type `light` (each triangle or sphere), then a point uniformly on the chosen one.
/// Seen from a shading point x, scenes with up to kLocalChoiceMax emitters choose by an estimate
/// of what each brings to x: power / max(distance to its centre^2, its area), and 0 for a planar
/// emitter x is behind (it cannot light x). Larger scenes choose by power alone.
class LightSampler {
public:
    static constexpr size_t kLocalChoiceMax = 64;

    LightSampler(const Scene& scene, const EmbreeScene& embree);
    bool empty() const { return entries_.empty(); }

    /// An emitter point for shading point x; pdf_area 0 when no emitter faces x.
    LightSample sample(const Vec3& x, double u_pick, double u, double v) const {
        const Choice c = choose(x, u_pick);
        return c.pdf_area > 0 ? at(c, u, v) : LightSample{};
    }

    /// The same choice of emitter made with u, whose position within the chosen emitter's
    /// share, rescaled to [0, 1), is then the u of the point on it: a stratified 2-D set stays
    /// stratified on each emitter. (With a separate pick, the points an emitter gets are a
    /// random subset of the set, no longer stratified: pixel-stratified light samples were
    /// noisier than independent ones on the Cornell box's two-triangle lamp.)
    LightSample sample_reusing(const Vec3& x, double u, double v) const {
        const Choice c = choose(x, u);
        return c.pdf_area > 0 ? at(c, c.rescaled, v) : LightSample{};
    }

    /// An emitter point chosen by power alone (no shading point).
    LightSample sample(double u_pick, double u, double v) const {
        const Choice c = choose_by_power(u_pick);
        return at(c, u, v);
    }

private:
    struct Entry {
        Vec3 a, b, c;         // triangle corners, or sphere: a = centre, b.x = radius
        Vec3 normal;          // triangle: unit normal
        Vec3 centre;          // triangle: centroid; sphere: centre
        bool sphere = false;
        Vec3 radiance;
        double area = 0;
        double power = 0;     // area x luminance
        double pdf_area = 0;  // probability of this entry by power alone / area
    };
    static double local_weight(const Entry& e, const Vec3& x) {
        if (!e.sphere && !(dot(x - e.a, e.normal) > 0)) return 0;  // behind a planar emitter
        Vec3 d = x - e.centre;
        return e.power / std::fmax(dot(d, d), e.area);
    }
    /// An emitter, the probability of its area's points, and u_pick's place in its share.
    struct Choice {
        size_t index = 0;
        double pdf_area = 0;
        double rescaled = 0;
    };
    static double place(double u, double lo, double width) {
        return width > 0 ? std::clamp((u - lo) / width, 0.0, 0x1.fffffffffffffp-1) : 0.5;
    }
    Choice choose_by_power(double u_pick) const {
        // A linear scan for the few emitters of most scenes (lower_bound's branches cost more).
        size_t i = 0;
        if (cdf_.size() <= 16) {
            while (i + 1 < cdf_.size() && cdf_[i] < u_pick) ++i;
        } else {
            i = std::min(static_cast<size_t>(std::lower_bound(cdf_.begin(), cdf_.end(), u_pick) - cdf_.begin()), entries_.size() - 1);
        }
        const double lo = i == 0 ? 0.0 : cdf_[i - 1];
        return {i, entries_[i].pdf_area, place(u_pick, lo, cdf_[i] - lo)};
    }
    Choice choose(const Vec3& x, double u_pick) const {
        if (entries_.size() > kLocalChoiceMax) return choose_by_power(u_pick);
        // In a corridor of three equal lamps, choosing by power alone spent two thirds of the
        // shadow rays on far lamps: grain on every wall.
        double w[kLocalChoiceMax];
        double total = 0;
        for (size_t i = 0; i < entries_.size(); ++i) total += w[i] = local_weight(entries_[i], x);
        if (!(total > 0) || !std::isfinite(total)) return {};
        const double target = u_pick * total;
        double acc = 0;
        size_t chosen = 0;
        for (size_t i = 0; i < entries_.size(); ++i) {
            if (!(w[i] > 0)) continue;
            chosen = i, acc += w[i];
            if (target < acc) break;
        }
        return {chosen, w[chosen] / (total * entries_[chosen].area), place(target, acc - w[chosen], w[chosen])};
    }
    LightSample at(const Choice& c, double u, double v) const {
        LightSample s = point_on(entries_[c.index], u, v);
        s.pdf_area = c.pdf_area;
        return s;
    }
    static LightSample point_on(const Entry& e, double u, double v) {
        LightSample s;
        s.radiance = e.radiance;
        if (e.sphere) {
            s.sphere = true;
            sample_sphere(e, u, v, s);
            return s;
        }
        double su = std::sqrt(u);
        double b0 = 1 - su, b1 = v * su;
        s.position = e.a * b0 + e.b * b1 + e.c * (1 - b0 - b1);
        s.normal = e.normal;
        return s;
    }
    std::vector<Entry> entries_;
    std::vector<double> cdf_;  // cumulative, normalised
    static void sample_sphere(const Entry& e, double u, double v, LightSample& s);  // position, normal
};

/// Pinhole camera. Pixel (0, 0) is the top-left; (x + u, y + v) for u, v in [0, 1) within it.
/// Pixels are square: when the scene gives both fields of view, the one the image's aspect
/// cannot hold is narrowed (rpict's rule).
class CameraRays {
public:
    CameraRays(const Camera& camera, int width, int height, const Vec3& origin_offset);
    void generate(double px, double py, Vec3& origin, Vec3& direction) const;

private:
    Vec3 origin_, forward_, right_, up_;
    double tan_x_ = 1, tan_y_ = 1;
    int width_, height_;
};

struct RenderScene {
    const Scene& scene;
    std::unique_ptr<EmbreeScene> embree;
    std::unique_ptr<LightSampler> lights;
    std::vector<Bsdf> bsdfs;  ///< per material, prepared once
    std::optional<MediumModel> medium;  ///< the scene's homogeneous medium, if any

    explicit RenderScene(const Scene& s);
    const Material& material_of(uint32_t geometry) const {
        return scene.materials[embree->geometries()[geometry].material];
    }
    const Bsdf& bsdf_of(uint32_t geometry) const { return bsdfs[embree->geometries()[geometry].material]; }
};

}  // namespace crex
