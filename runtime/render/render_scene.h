/// \file render_scene.h
/// What the renderer needs of a scene beyond the BVH: materials by geometry, the sampled
/// emitters (`light` surfaces) with a power-proportional choice between them, and the camera.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/render/bsdf.h"
#include "runtime/render/function_patterns.h"
#include "runtime/render/light_tree.h"
#include "runtime/render/medium.h"
#include "runtime/render/surface.h"
#include "runtime/render/triangle_weights.h"
#include "runtime/scene/scene.h"
#include "runtime/trace/embree_scene.h"

namespace crex {

/// A surface whose emission is an image (a TV screen, a sign, a backlit poster): direct
/// lighting samples its triangles as it samples a `light`'s, and each sample's radiance is
/// read from the image where the point falls. Unsampled, such a surface lit a room only
/// through the rays that happened to hit it: grain everywhere its light fell.
struct TexturedEmission {
    const SurfaceTextures* textures = nullptr;
    const GeometryInfo* geometry = nullptr;
    uint32_t material = 0;
    Vec3 origin_offset;  ///< local coordinates plus this are the scene's (planar mappings)
    /// The emission at barycentrics (b1, b2) of triangle `prim` (weights of its second and
    /// third corners), at local `position`; read from the image's coarse copy, as every lookup
    /// whose light is averaged with many others' is. (That copy averages an sRGB image's texels
    /// before they are made linear, which darkens high-contrast images a little: the living
    /// room's screen lit the room 0.7 % less than from the full image, which cost 5 % more
    /// time to read; its hits, read through the pixel's footprint, had lit it 2.3 % less.)
    Vec3 at(uint32_t prim, double b1, double b2, const Vec3& position) const;
};

/// What limits where an emitter's light goes: a spotlight's cone (with the distance of its
/// focus behind the emitter) and a glow's radius of influence.
struct EmitterLimits {
    double spot_cos = -2;  ///< cosine of the cone's half angle; below -1: no cone
    Vec3 spot_axis;        ///< unit
    double focal = 0;      ///< the light falls off as from this far behind the emitter
    double max_distance = INFINITY;  ///< beyond this the emitter lights nothing (glow radius)
    const PatternChain* pattern = nullptr;  ///< its radiance varies by direction (a luminaire's distribution)
    const TexturedEmission* emission = nullptr;  ///< its radiance varies over the surface (an image)
    bool limited() const { return spot_cos >= -1 || std::isfinite(max_distance) || pattern || emission; }
};

struct LightSample {
    Vec3 position;  ///< local coordinates
    Vec3 normal;    ///< unit, the emitting side
    Vec3 radiance;
    double pdf_area = 0;  ///< pdf of this point, per unit area, including the choice of emitter
    bool sphere = false;  ///< on an analytic sphere (whose hit distance Embree finds less precisely)
    /// A glow or an illum (local or distant): an illum in the way blocks it (RADIANCE's
    /// illumblock), where it lets rays to a `light` through.
    bool weak = false;
    const EmitterLimits* limits = nullptr;  ///< spot cone, glow radius (nullptr: none)
    /// A distant source (the sun, a sky): a direction, not a point; pdf_area stays 0, so what
    /// handles only local emitters ignores it.
    bool distant = false;
    Vec3 direction{};           ///< unit, towards the source
    double pdf_direction = 0;   ///< per unit solid angle, including the choice of emitter
    /// A textured emission's triangle and the point's barycentrics in it (limits->emission).
    uint32_t prim = 0;
    double b1 = 0, b2 = 0;
};

/// The radiance of a local emitter's sample towards a point `distance` away along unit `wi`
/// (from that point to the emitter): its pattern's factor for that ray, when it has one.
inline Vec3 patterned_radiance(const LightSample& ls, const Vec3& wi, double distance) {
    if (!ls.limits) return ls.radiance;
    if (ls.limits->emission) return ls.limits->emission->at(ls.prim, ls.b1, ls.b2, ls.position);
    if (!ls.limits->pattern) return ls.radiance;
    PatternRay r;
    r.direction = wi;
    r.normal = ls.normal;
    r.point = ls.position;
    r.distance = distance;
    return ls.radiance * ls.limits->pattern->value(r);
}

/// RADIANCE's distant sources (`source`): a disk of directions (the sun) or a sky dome
/// (a glow source, possibly with a sky brightness pattern), sampled by direct lighting and
/// seen by camera rays and rays from ideal specular lobes that escape the scene.
class DistantEmitters {
public:
    DistantEmitters(const Scene& scene, double scene_radius, const ScenePatterns* patterns);
    size_t size() const { return sources_.size(); }
    /// Irradiance-like weight of source i (radiance x solid angle) and its power entering the
    /// scene (times the scene's cross-section), for choosing between emitters.
    double weight(size_t i) const { return sources_[i].weight; }
    double power(size_t i) const { return sources_[i].weight * scene_area_; }
    /// Source i is a glow (a sky), not a `light` (the sun).
    bool weak(size_t i) const { return sources_[i].weak; }
    /// Every direction of source i is at or below the plane through the origin with unit
    /// normal `n` (a cone no wider than a hemisphere, tipped away from n by at least its half
    /// angle): a surface facing n sees none of it.
    bool below_horizon(size_t i, const Vec3& n) const {
        const Source& s = sources_[i];
        return s.cos_max >= 0 && dot(s.axis, n) <= -std::sqrt(std::fmax(0.0, 1 - s.cos_max * s.cos_max));
    }
    /// A direction of source i for (u, v); pdf per solid angle.
    void sample(size_t i, double u, double v, Vec3& direction, Vec3& radiance, double& pdf) const;
    /// Source i covers a hemisphere or more (a sky, a ground): worth sampling from a surface's
    /// side (sample_above) rather than over the whole cone.
    bool wide(size_t i) const { return sources_[i].cos_max < 1e-9; }  // cos(90 degrees) is 6e-17
    /// A direction of source i for a surface facing unit `n`: cosine-distributed about n, or,
    /// for a sky with a brightness pattern, that 30 % of the time and by the pattern (sample())
    /// otherwise (one sample of the two mixed; pdf the mixture's). Over the whole cone, half
    /// of a 360-degree sky's directions were behind the surface, and a uniform sky lighting a
    /// floor came out noisy where cosine sampling gives its exact irradiance. (A CIE clear sky
    /// seen by a surface facing the sun is the exception: 12 % more variance there, where the
    /// pattern alone is close to the product with the cosine; 30 % rather than half keeps that
    /// small, tests/numerics/light_choice_test.cpp.) Directions outside the cone have radiance 0.
    void sample_above(size_t i, const Vec3& n, double u, double v, Vec3& direction, Vec3& radiance, double& pdf) const;
    /// What an escaped ray along unit `d` sees of them all.
    Vec3 escaped(const Vec3& d) const;

private:
    struct Source {
        Vec3 axis, t, b;     // unit axis towards the source, and a basis around it
        double cos_max = 1;  // cosine of the half angle
        Vec3 color;
        std::optional<SkyModel> sky;
        const PatternChain* pattern = nullptr;  // a photographed sky, ...
        double weight = 0;
        bool weak = false;
        // A sky: equal-solid-angle cells of (cos, phi) around the axis, chosen by brightness.
        int cells_z = 0, cells_phi = 0;
        std::vector<double> cdf;
    };
    Vec3 radiance_of(const Source& s, const Vec3& d) const;
    /// The factor of its sky and pattern towards `d` (white without either), and its luminance.
    static Vec3 pattern_of(const Source& s, const Vec3& d);
    static double brightness_of(const Source& s, const Vec3& d);
    /// sample()'s pdf of unit direction d (0 outside the cone).
    static double cone_pdf(const Source& s, const Vec3& d);
    std::vector<Source> sources_;
    double scene_area_ = 1;
};

/// Emitters sampled by direct lighting: `light` and `illum` surfaces and `glow`s with a radius
/// (each triangle or sphere), and distant sources; then a point (or direction) on the chosen
/// one. Seen from a shading point x, scenes with up to kLocalChoiceMax emitters choose by an
/// estimate of what each brings to x: power / max(distance to its centre^2, its area) (a
/// distant source: radiance x solid angle), and 0 for a planar emitter x is behind (it cannot
/// light x) or a glow x is beyond the reach of. Larger scenes descend a tree over their local
/// emitters (light_tree.h) by the same estimate made for groups of them.
class LightSampler {
public:
    static constexpr size_t kLocalChoiceMax = 64;

    /// `textures`: surfaces whose emission is an image are sampled too (TexturedEmission).
    LightSampler(const Scene& scene, const EmbreeScene& embree, const ScenePatterns* patterns = nullptr,
                 const SurfaceTextures* textures = nullptr);
    bool empty() const { return entries_.empty(); }
    /// Is geometry `geom`'s emission (a material's `emission`) sampled by direct lighting? Then
    /// only camera rays and rays from delta lobes count it where they hit, as a `light`'s.
    bool samples_emission(uint32_t geom) const { return geom < emission_sampled_.size() && emission_sampled_[geom]; }
    const DistantEmitters& distant() const { return distant_; }
    /// Scales each distant source's share of shadow rays by `fraction[i]` (in (0, 1]: how much
    /// of it the surfaces in view can see, light_visibility.h), from its unscaled share.
    void weigh_distant(const std::vector<double>& fraction);

    /// What each emitter brings to one shading point, the weights its choice is made by. Made
    /// once a hit for all of its shadow rays: with four shadow rays a hit, weighing every
    /// emitter again for each was 6 % of a cached render of the corridor.
    struct LocalWeights {
        double w[kLocalChoiceMax];  // left unset: only the sampler's first entries are read (the distant ones' with a tree)
        double total = 0;
        bool by_tree = false;       // more emitters than kLocalChoiceMax: the local ones by the tree
        bool by_power = false;      // more distant sources than kLocalChoiceMax: all by power alone
        double distant_total = 0;   // with the tree: the distant sources' weights; the tree's is total - distant_total
        Vec3 point{};               // the shading point: a sphere is sampled in the cone it fills there
        Vec3 horizon{};             // with `above`: the surface's unit normal there
        bool above = false;         // a surface that only reflects: wide distant sources are sampled above it
    };
    /// The weights at x. With `horizon` (the unit normal of a surface that only reflects, Bsdf::reflects_only),
    /// an emitter wholly at or below the surface's plane weighs 0: it cannot light x, and the
    /// shadow rays it was given came to nothing (a table's underside under ceiling lamps, a
    /// floor and RADIANCE's `ground` source, a ceiling and the `sky`, a wall facing away from
    /// the sun). Exact: each such sample's value was 0.
    LocalWeights weights_at(const Vec3& x, const Vec3* horizon = nullptr) const {
        LocalWeights lw;
        lw.point = x;
        if (horizon) lw.horizon = *horizon, lw.above = true;
        if (!tree_.empty()) {
            lw.by_tree = true;
            for (size_t k = 0; k < distant_entries_.size(); ++k) {
                const Entry& e = entries_[distant_entries_[k]];
                lw.distant_total += lw.w[k] = horizon && below_horizon(e, x, *horizon) ? 0.0 : e.distant_weight;
            }
            lw.total = lw.distant_total + tree_.importance_at(x, horizon);
            return lw;
        }
        if (entries_.size() > kLocalChoiceMax) {  // and no tree: more distant sources than that
            lw.by_power = true;
            return lw;
        }
        if (one_flat_) {
            // One emitter is chosen whatever its weight: only whether it can light x matters.
            const Entry& e = entries_[0];
            lw.total = lw.w[0] = dot(x - e.a, e.normal) > 0 && !(horizon && below_horizon(e, x, *horizon)) ? 1.0 : 0.0;
            return lw;
        }
        if (!triangles_.empty()) {
            triangles_.weigh(x, horizon, lw.w);
            for (size_t i = 0; i < entries_.size(); ++i) lw.total += lw.w[i];
            return lw;
        }
        for (size_t i = 0; i < entries_.size(); ++i) {
            const Entry& e = entries_[i];
            lw.total += lw.w[i] = weight_of(e, x, horizon);
        }
        return lw;
    }

    /// An emitter point for the shading point `weights` were made at; pdf_area 0 when no
    /// emitter faces it.
    LightSample sample(const LocalWeights& weights, double u_pick, double u, double v) const {
        const Choice c = choose(weights, u_pick);
        return c.pdf_area > 0 ? at(c, u, v, &weights) : LightSample{};
    }

    /// The same choice of emitter made with u, whose position within the chosen emitter's
    /// share, rescaled to [0, 1), is then the u of the point on it: a stratified 2-D set stays
    /// stratified on each emitter. (With a separate pick, the points an emitter gets are a
    /// random subset of the set, no longer stratified: pixel-stratified light samples were
    /// noisier than independent ones on the Cornell box's lamp when it was two triangles.)
    LightSample sample_reusing(const LocalWeights& weights, double u, double v) const {
        const Choice c = choose(weights, u);
        return c.pdf_area > 0 ? at(c, c.rescaled, v, &weights) : LightSample{};
    }

    /// Whether along() can answer at the shading point `weights` were made at: the emitters
    /// are chosen among a few by their weights there (no tree, not by power alone).
    static bool finds_along(const LocalWeights& weights) { return !weights.by_tree && !weights.by_power && weights.total > 0; }
    /// The first point of a local emitter that the ray from the shading point along unit `dir`
    /// meets, as the light sample sample() would have made there: its pdf_area is what
    /// sample() gives that point (choice of emitter included; 0 where it never would, or where
    /// no emitter is met, or its back is). Multiple importance sampling weighs a direction a
    /// BSDF sampled by it (glossy_light_sample()). Distant sources are not searched.
    LightSample along(const LocalWeights& weights, const Vec3& dir) const;

    /// An emitter point chosen by power alone (no shading point).
    LightSample sample(double u_pick, double u, double v) const {
        const Choice c = choose_by_power(u_pick);
        return at(c, u, v);
    }

private:
    struct Entry {
        Vec3 a, b, c;         // triangle corners (a parallelogram's: b and c beside a), or sphere: a = centre, b.x = radius
        Vec3 d;               // a parallelogram's fourth corner, opposite a; a triangle repeats a
        bool parallelogram = false;  // two triangles of one quad, sampled as one emitter
        Vec3 normal;          // triangle: unit normal
        Vec3 centre;          // triangle: centroid; sphere: centre
        bool sphere = false;
        bool weak = false;    // a glow or an illum
        int distant = -1;     // >= 0: this distant source (a, b, c unused)
        Vec3 radiance;
        double area = 0;      // distant: solid angle
        double reach = 0;     // distance from the centre to the farthest point of the entry
        double power = 0;     // area x luminance (distant: as it enters the scene)
        double pdf_area = 0;  // probability of this entry by power alone / area
        double distant_weight = 0;  // distant: radiance x solid angle, the weight at any point
        double pattern_mean = 1;    // its pattern's mean over the directions it emits into
        const EmitterLimits* limits = nullptr;
        uint32_t prim = 0;          // a textured emission's triangle in its mesh (never joined)
    };
    bool below_horizon(const Entry& e, const Vec3& x, const Vec3& n) const {
        if (e.distant >= 0) return distant_.below_horizon(static_cast<size_t>(e.distant), n);
        if (e.sphere) return dot(e.a - x, n) <= -e.b.x;
        return dot(e.a - x, n) <= 0 && dot(e.b - x, n) <= 0 && dot(e.c - x, n) <= 0 && dot(e.d - x, n) <= 0;
    }
    /// Entry e's weight at x, the one rule for weights_at and the tree's leaves: 0 below the
    /// horizon of a surface that only reflects, else local_weight.
    double weight_of(const Entry& e, const Vec3& x, const Vec3* horizon) const {
        return horizon && below_horizon(e, x, *horizon) ? 0.0 : local_weight(e, x, horizon);
    }
    /// Its power over the squared distance (at least its area), times the two cosines of its
    /// light on the way to x, each widened by the sine of the angle its sphere (its reach) fills
    /// from x and at most 1: at the emitter (a flat one seen edge-on gives little) and at a
    /// surface that only reflects (`horizon`: an emitter low over its plane gives little). One
    /// square root, no bound's trigonometry: a weight only has to be positive wherever the
    /// emitter can light x, and both are (x in front of a flat emitter has a positive cosine
    /// to its centre; a point of it above the horizon, within `reach` of the centre, makes the
    /// centre's cosine above minus that sine). 0 behind a flat emitter and beyond a glow's reach.
    static double local_weight(const Entry& e, const Vec3& x, const Vec3* horizon) {
        if (e.distant >= 0) return e.distant_weight;
        if (!e.sphere && !(dot(x - e.a, e.normal) > 0)) return 0;  // behind a planar emitter
        const Vec3 d = x - e.centre;
        const double d2 = dot(d, d);
        if (e.limits && std::isfinite(e.limits->max_distance)) {
            const double near = std::sqrt(d2) - e.reach;  // no point of it is within reach of x
            if (near > e.limits->max_distance) return 0;
        }
        const double w = e.power / max_of(d2, e.area);
        if (!(d2 > e.reach * e.reach) || (e.sphere && !horizon)) return w;  // x within its sphere: both factors are 1
        const double inv_d = 1 / std::sqrt(d2), sin_b = e.reach * inv_d;
        double cosines = 1;
        if (!e.sphere) cosines *= min_of(1.0, dot(d, e.normal) * inv_d + sin_b);
        if (horizon) cosines *= min_of(1.0, -dot(d, *horizon) * inv_d + sin_b);
        return w * max_of(cosines, 1e-9);  // rounding must not make it 0
    }
    /// An emitter, the probability of its area's points, and u_pick's place in its share.
    struct Choice {
        size_t index = 0;
        double pdf_area = 0;
        double rescaled = 0;
        const Entry* entry = nullptr;  ///< entries_[index] or its copy in tree_slots_ (a leaf's memory, in cache)
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
    Choice choose_in_tree(const LocalWeights& weights, double u_pick) const {
        const double target = u_pick * weights.total;
        if (!(weights.total > 0) || !std::isfinite(weights.total)) return {};
        if (target < weights.distant_total) {  // a distant source, by its weight
            double acc = 0;
            size_t k = 0;
            for (; k + 1 < distant_entries_.size() && !(target < acc + weights.w[k]); ++k) acc += weights.w[k];
            const size_t i = distant_entries_[k];
            return {i, weights.w[k] / (weights.total * entries_[i].area), place(target, acc, weights.w[k])};
        }
        const double tree_share = weights.total - weights.distant_total;
        const double u = place(target, weights.distant_total, tree_share);
        const LightTree::Choice c = tree_.choose(weights.point, weights.above ? &weights.horizon : nullptr, u,
                                                 [&](uint32_t slot) { return weight_of(tree_slots_[slot], weights.point, weights.above ? &weights.horizon : nullptr); });
        if (!(c.probability > 0)) return {};
        const Entry& e = tree_slots_[c.slot];
        return {tree_entries_[c.index], tree_share / weights.total * c.probability / e.area, c.rescaled, &e};
    }
    Choice choose(const LocalWeights& weights, double u_pick) const {
        if (weights.by_tree) return choose_in_tree(weights, u_pick);
        if (weights.by_power) return choose_by_power(u_pick);
        // In a corridor of three equal lamps, choosing by power alone spent two thirds of the
        // shadow rays on far lamps: grain on every wall.
        const double* w = weights.w;
        const double total = weights.total;
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
    /// A point of the chosen emitter; seen from `from` (a shading point), a sphere's point is
    /// sampled uniformly in the cone of directions it fills there, else uniformly by area, and
    /// a wide distant source above the surface there has one (DistantEmitters::sample_above).
    LightSample at(const Choice& c, double u, double v, const LocalWeights* from = nullptr) const {
        const Entry& e = c.entry ? *c.entry : entries_[c.index];
        if (e.distant >= 0) {  // pdf_area holds the choice's probability per steradian here
            LightSample s;
            s.distant = true;
            s.weak = distant_.weak(static_cast<size_t>(e.distant));
            double pdf = 0;
            const size_t i = static_cast<size_t>(e.distant);
            if (from && from->above && distant_.wide(i))
                distant_.sample_above(i, from->horizon, u, v, s.direction, s.radiance, pdf);
            else
                distant_.sample(i, u, v, s.direction, s.radiance, pdf);
            s.pdf_direction = pdf * c.pdf_area * e.area;
            return s;
        }
        if (e.sphere) {
            LightSample s;
            s.radiance = e.radiance;
            s.limits = e.limits;
            s.sphere = true;
            s.pdf_area = c.pdf_area;
            if (!from || !sample_sphere_seen(e, from->point, u, v, s)) sample_sphere(e, u, v, s);
            s.weak = e.weak;
            return s;
        }
        // A point of the triangle, made whole (the fields not named take their initialisers): a
        // sample default-made and then filled in was zeroed first (a `rep stos` per shadow ray).
        if (e.parallelogram)  // (u, v) across its two sides: a stratified set stays stratified, no fold
            return LightSample{.position = e.a + (e.b - e.a) * u + (e.c - e.a) * v,
                               .normal = e.normal,
                               .radiance = e.radiance,
                               .pdf_area = c.pdf_area,
                               .weak = e.weak,
                               .limits = e.limits};
        const double su = std::sqrt(u);
        const double b0 = 1 - su, b1 = v * su;
        return LightSample{.position = e.a * b0 + e.b * b1 + e.c * (1 - b0 - b1),
                           .normal = e.normal,
                           .radiance = e.radiance,
                           .pdf_area = c.pdf_area,
                           .weak = e.weak,
                           .limits = e.limits,
                           .prim = e.prim,
                           .b1 = b1,
                           .b2 = 1 - b0 - b1};
    }
    void make_cdf();  // cdf_ and each entry's pdf_area from the entries' power
    /// The entries' weights in vector code; empty unless every one is a flat emitter with no
    /// limit to its reach (the rule local_weight() applies to those).
    static TriangleWeights flat_weights(const std::vector<Entry>& entries);
    /// Two emitter triangles that make one parallelogram (two corners shared, the same side
    /// lit, the same light) as one entry: a quad lamp is then one emitter, sampled without a
    /// fold, and a scene lit by it alone weighs nothing at a hit. False when they do not.
    static bool join_parallelogram(const Entry& t0, const Entry& t1, Entry& joined);
    std::vector<Entry> entries_;
    std::vector<double> cdf_;  // cumulative, normalised
    LightTree tree_;                      // over the local entries, when there are more than kLocalChoiceMax entries
    std::vector<size_t> tree_entries_;    // the tree's emitters: entries_ indices
    // The tree's emitters again, in its leaves' order: a leaf's are weighed from consecutive
    // memory (read through two indices, each emitter's weight waited on a cache miss).
    std::vector<Entry> tree_slots_;
    std::vector<size_t> distant_entries_; // with the tree: the distant entries
    TriangleWeights triangles_;  // when every entry is a flat emitter without a distance limit, and no tree: weights_at in vector code
    bool one_flat_ = false;      // and there is one: weights_at only asks whether it can light x
    std::vector<std::unique_ptr<EmitterLimits>> limits_;
    std::vector<std::unique_ptr<TexturedEmission>> textured_;
    std::vector<uint8_t> emission_sampled_;  // per geometry: samples_emission()
    DistantEmitters distant_;
    static void sample_sphere(const Entry& e, double u, double v, LightSample& s);  // position, normal
    /// A point of the part of the sphere seen from x, uniform in the cone of directions it fills
    /// (pdf_area scaled from the emitter's by area to that per unit area of this point): area
    /// sampling spent half its samples on the far side, which x cannot see. False, leaving s
    /// as it was, when x is inside the sphere or too near it to tell.
    static bool sample_sphere_seen(const Entry& e, const Vec3& x, double u, double v, LightSample& s);
};

/// The camera's rays for image positions: pixel (0, 0) is the top-left; (x + u, y + v) for u, v
/// in [0, 1) within it. Every projection of Camera (perspective, parallel, the fisheyes, the
/// cylindrical panorama), as RADIANCE's views define them. Pixels are square: when the scene
/// gives both fields of view, the one the image's aspect cannot hold is narrowed (rpict's rule).
class CameraRays {
public:
    CameraRays(const Camera& camera, int width, int height, const Vec3& origin_offset);
    /// False where the projection has no ray (outside a fisheye's circle): `direction` is then
    /// the view direction, and the sample must carry no light.
    bool generate(double px, double py, Vec3& origin, Vec3& direction) const;

    /// The view as OpenEXR's worldToCamera and worldToNDC attributes hold it (RenderMan's
    /// spaces; row vectors, row-major, p' = p M): camera space has +x right, +y up and +z along
    /// the view (left-handed); NDC has x and y in [0, 1] across the image from its top-left
    /// corner once divided by w (perspective: w is the depth, and z/w its inverse). False for
    /// the projections no matrix holds (fisheyes, panoramas), or a degenerate camera.
    bool world_to_camera(std::array<double, 16>& m) const;
    bool world_to_ndc(std::array<double, 16>& m) const;

private:
    Vec3 origin_, forward_, right_, up_;
    double ext_x_ = 1, ext_y_ = 1;  // half the image's extent, in the projection's own measure
    Projection projection_ = Projection::kPerspective;
    double fore_clip_ = 0;
    int width_, height_;
};

class HotSurfaces;

struct RenderScene {
    const Scene& scene;
    /// The scene's textures (one texture cache of `texture_cache_bytes`); null when no
    /// material has a texture or a constant opacity below 1.
    std::unique_ptr<SurfaceTextures> textures;
    std::unique_ptr<SceneCutouts> cutouts;  ///< when some material cuts holes
    std::unique_ptr<EmbreeScene> embree;
    std::unique_ptr<ScenePatterns> patterns;  ///< emitters' patterns; null when none has one
    std::unique_ptr<LightSampler> lights;
    std::vector<Bsdf> bsdfs;  ///< per material, prepared once
    std::optional<MediumModel> medium;  ///< the scene's homogeneous medium, if any
    /// Surfaces small lamps light from up close (a shade's inside), sampled as lights of their
    /// own (hot_surfaces.h); empty where there are none.
    std::unique_ptr<HotSurfaces> hot;
    /// Where texture lookups filter: the camera's pixel footprint (set_view()); without it,
    /// lookups are the sharpest (tests that never set an image size).
    PixelFootprint footprint;
    std::vector<Diagnostic> warnings;  ///< textures that cannot be read (they render magenta)

    /// `progress`: long work while it is built (a texture's tiled copy being made).
    explicit RenderScene(const Scene& s, size_t texture_cache_bytes = kDefaultTextureCacheBytes, TextureProgress progress = {});
    ~RenderScene();
    /// Texture filtering for images of width x height through the scene's camera, over
    /// `filter_width` pixels (1: one pixel's footprint; 0: the sharpest lookups, which alias).
    void set_view(int width, int height, double filter_width = 1);
    const Material& material_of(uint32_t geometry) const {
        return scene.materials[embree->geometries()[geometry].material];
    }
    const Bsdf& bsdf_of(uint32_t geometry) const { return bsdfs[embree->geometries()[geometry].material]; }
};

}  // namespace crex
