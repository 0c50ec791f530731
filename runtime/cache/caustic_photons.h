/// \file caustic_photons.h
/// A caustic photon map (Jensen 1996) beside the irradiance cache: the light that reaches a
/// diffuse surface from a `light` emitter through mirrors, glass, dielectrics or a trans
/// surface's specular transmission (paths L S+ D, T counting as S).
/// A record's hemisphere rays find that light only when one of them happens to be sent onto a
/// small emitter's image in a mirror or a lens; on the Cornell box those few rays were most of
/// the cache's noise (two seeds' 64-spp `--ic` renders differed at perr 29.9 %, 0.3 % with
/// those paths left out); a lamp seen through a frosted screen lit whole records' discs behind
/// it. Photons are aimed from the emitters at the bounding spheres of the delta shapes and
/// trans surfaces, followed through them (one lobe by its weight; through a trans surface with
/// its T lobe's share, as the hemisphere rays are; up to 8 interfaces) and kept at the first
/// surface they are shaded at, if it has a diffuse lobe. Irradiance at a point is a k-nearest-neighbour
/// density estimate with an Epanechnikov kernel over the photons of its side of the surface,
/// made at every 8th photon once (Christensen 1999); a query blends the estimates whose discs hold it.
///
/// Deterministic: photon j's random numbers are a hash of (seed, j), the photons are kept in
/// index order, the tree is built from them in that order, and a query adds its estimates in
/// index order.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "runtime/base/vec3.h"
#include "runtime/render/render_scene.h"

namespace crex {

struct CausticPhotonSettings {
    uint32_t photons = 200000;   ///< emitted towards the delta shapes and trans surfaces (0: no map)
    uint32_t neighbours = 32;    ///< k of the density estimate
    double max_radius = 0;       ///< of the density estimate; 0: the scene's extent / 16
    uint64_t seed = 0;
    /// Called as the map is built (from the thread that builds it) with the phase ("tracing",
    /// "photon tree", "density estimates") and the share of it done: 20 million photons took
    /// 54 s before the first camera ray, 40 of them in the estimates.
    std::function<void(const char* phase, double done)> progress;
};

class CausticPhotons {
public:
    CausticPhotons(const RenderScene& scene, const CausticPhotonSettings& settings);
    ~CausticPhotons();
    CausticPhotons(const CausticPhotons&) = delete;
    CausticPhotons& operator=(const CausticPhotons&) = delete;

    /// True when the scene has no delta shape or trans surface, or no `light` emitter: there
    /// are no such paths.
    bool empty() const { return photons_.empty(); }
    size_t size() const { return photons_.size(); }
    /// Rays traced to build the map.
    uint64_t rays() const { return rays_; }
    /// Irradiance at x from the photons on the side of the surface that unit `n` points to.
    Vec3 irradiance(const Vec3& x, const Vec3& n) const;

    struct Photon {
        float position[3];
        float normal[3];  ///< unit, the side the photon arrived from
        float power[3];   ///< flux (W)
    };

    /// The density estimate at a photon, and the disc it covers.
    struct Estimate {
        float position[3];
        float normal[3];
        float irradiance[3];
        float radius2;
    };

    /// The density estimates a query blends (for checks and diagnostics).
    const std::vector<Estimate>& estimates() const { return estimates_; }

private:
    /// The estimates' discs by the cells of a grid they reach (compressed rows: each cell's
    /// estimates in increasing index order). A query reads its cell's discs and blends those
    /// that hold it: a search for the 8 nearest estimates in a k-d tree visited about 27 of its
    /// leaves a query, a quarter of a default render of the Cornell box. A cell no disc reaches
    /// answers 0 at once, as most queries far from every caustic do.
    struct DiscGrid {
        Vec3 origin{};
        double cell = 0;
        int dims[3] = {0, 0, 0};
        std::vector<uint32_t> first;  ///< per cell, where its estimates start in `discs`; one more at the end
        std::vector<uint32_t> discs;  ///< estimate indices
        /// The cell x lies in, or -1 outside the grid (and for a non-finite x).
        int64_t cell_of(const Vec3& x) const;
    };
    void precompute(const std::function<void(const char* phase, double done)>& progress);
    void build_disc_grid();
    std::vector<Photon> photons_;
    std::vector<Estimate> estimates_;
    DiscGrid grid_;
    uint32_t neighbours_ = 32;
    double max_radius_ = 0;
    uint64_t rays_ = 0;
};

/// The map of `photons` photons (null for 0 photons): the one way both path tracing and the
/// irradiance cache build theirs. It is empty when the scene has no such paths (no delta shape or
/// trans surface, no lamp, or no photon through them lands on a diffuse surface); kept so, it
/// tells a later render of the same scene (a sequence's next frame) not to trace them again.
std::shared_ptr<const CausticPhotons> build_caustic_photons(const RenderScene& scene, uint32_t photons, uint64_t seed,
                                                           std::function<void(const char* phase, double done)> progress = nullptr);

/// `map` when it holds photons, else null: what a render looks caustics up in.
inline std::shared_ptr<const CausticPhotons> photons_in(const std::shared_ptr<const CausticPhotons>& map) {
    return map && !map->empty() ? map : nullptr;
}

}  // namespace crex
