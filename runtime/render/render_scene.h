/// \file render_scene.h
/// What the renderer needs of a scene beyond the BVH: materials by geometry, the sampled
/// emitters (`light` surfaces) with a power-proportional choice between them, and the camera.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "runtime/render/bsdf.h"
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

/// Emitters of type `light`, each triangle or sphere chosen with probability proportional to
/// area times luminance, then a point uniformly on it.
class LightSampler {
public:
    LightSampler(const Scene& scene, const EmbreeScene& embree);
    bool empty() const { return entries_.empty(); }
    LightSample sample(double u_pick, double u, double v) const {
        // A linear scan for the few emitters of most scenes (lower_bound's branches cost more).
        size_t i = 0;
        if (cdf_.size() <= 16) {
            while (i + 1 < cdf_.size() && cdf_[i] < u_pick) ++i;
        } else {
            i = std::min(static_cast<size_t>(std::lower_bound(cdf_.begin(), cdf_.end(), u_pick) - cdf_.begin()), entries_.size() - 1);
        }
        const Entry& e = entries_[i];
        LightSample s;
        s.radiance = e.radiance;
        s.pdf_area = e.pdf_area;
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

private:
    struct Entry {
        Vec3 a, b, c;         // triangle corners, or sphere: a = centre, b.x = radius
        Vec3 normal;          // triangle: unit normal
        bool sphere = false;
        Vec3 radiance;
        double area = 0;
        double pdf_area = 0;  // probability of this entry / area
    };
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

    explicit RenderScene(const Scene& s);
    const Material& material_of(uint32_t geometry) const {
        return scene.materials[embree->geometries()[geometry].material];
    }
    const Bsdf& bsdf_of(uint32_t geometry) const { return bsdfs[embree->geometries()[geometry].material]; }
};

}  // namespace crex
