/// \file ray_batch.h
/// A bin's rays, structure of arrays: plain data that can be serialised and shipped (MPI,
/// later). A ray carries its origin and direction (local scene coordinates), its throughput
/// beta (RGB), its pixel, its depth (camera rays 0), its path id (the key of every random
/// number drawn along it) and flags.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "runtime/base/vec3.h"

namespace crex {

enum RayFlags : uint8_t {
    kRayFromDeltaLobe = 1,  ///< spawned by S, T, R or M: sees sampled emitters (spec §1)
    kRayIcQuery = 2,        ///< a D irradiance-cache query: direction holds the normal
    kRayOddSample = 4,      ///< descends from an odd camera sample: the film's second half-buffer
    /// Bits 3-5: 1 + the component of the ray spawned at the camera hit that this ray descends
    /// from (its branch), 0 for camera rays: what capict interpolates is a branch (thesis 7.4).
    kRayBranchMask = 0x38,
    /// Its hit is a surface the camera sees: a camera ray, or a chain of S, T, R or M lobes
    /// from one (a reflection in a mirror, the floor through glass). Direct light there takes
    /// the pixel's shadow rays; deeper hits take one (shadow_rays_at).
    kRaySeenByCamera = 0x40,
    /// Left a diffuse lobe and has passed only S, T, R or M lobes since, in a render whose
    /// caustics come from a photon map (ShadeParams::caustic_irradiance): a `light` emitter it
    /// reaches is light the map gave at the diffuse hit it left, so it brings nothing here.
    kRayCausticPath = 0x80,
};
inline constexpr unsigned kRayBranchShift = 3;

struct RayRecord {
    Vec3 origin, direction, beta;
    uint32_t pixel = 0;
    uint16_t depth = 0;
    uint8_t flags = 0;
    uint64_t path = 0;
};

struct RayBatch {
    std::vector<float> ox, oy, oz, dx, dy, dz, br, bg, bb;
    std::vector<uint32_t> pixel;
    std::vector<uint16_t> depth;
    std::vector<uint8_t> flags;
    std::vector<uint64_t> path;

    size_t size() const { return pixel.size(); }
    bool empty() const { return pixel.empty(); }

    void push(const RayRecord& r) { append(&r, 1); }

    /// Appends `count` rays at once: each array grows once, then a plain loop fills them (13
    /// push_backs per ray cost ~40 ns; a uint8_t store may alias every vector's pointers).
    void append(const RayRecord* records, size_t count) {
        const size_t at = size();
        resize(at + count);
        write(at, records, count);
    }

    /// Overwrites rays [at, at + count), which the batch must already hold.
    void write(size_t at, const RayRecord* records, size_t count) {
        float *pox = ox.data() + at, *poy = oy.data() + at, *poz = oz.data() + at;
        float *pdx = dx.data() + at, *pdy = dy.data() + at, *pdz = dz.data() + at;
        float *pbr = br.data() + at, *pbg = bg.data() + at, *pbb = bb.data() + at;
        uint32_t* ppixel = pixel.data() + at;
        uint16_t* pdepth = depth.data() + at;
        uint8_t* pflags = flags.data() + at;
        uint64_t* ppath = path.data() + at;
        for (size_t i = 0; i < count; ++i) {
            const RayRecord& r = records[i];
            pox[i] = static_cast<float>(r.origin.x), poy[i] = static_cast<float>(r.origin.y), poz[i] = static_cast<float>(r.origin.z);
            pdx[i] = static_cast<float>(r.direction.x), pdy[i] = static_cast<float>(r.direction.y), pdz[i] = static_cast<float>(r.direction.z);
            pbr[i] = static_cast<float>(r.beta.x), pbg[i] = static_cast<float>(r.beta.y), pbb[i] = static_cast<float>(r.beta.z);
            ppixel[i] = r.pixel, pdepth[i] = r.depth, pflags[i] = r.flags, ppath[i] = r.path;
        }
    }

    void resize(size_t n) {
        for_each_array([n](auto member, RayBatch& self) { (self.*member).resize(n); });
    }

    RayRecord get(size_t i) const {
        return {{ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]}, {br[i], bg[i], bb[i]}, pixel[i], depth[i], flags[i], path[i]};
    }

    /// Appends rays [begin, end) of `o`, array by array (much cheaper than ray by ray).
    void append(const RayBatch& o, size_t begin, size_t end) {
        for_each_array([&o, begin, end](auto member, RayBatch& self) {
            const auto& from = o.*member;
            (self.*member).insert((self.*member).end(), from.begin() + static_cast<std::ptrdiff_t>(begin),
                                  from.begin() + static_cast<std::ptrdiff_t>(end));
        });
    }
    void append(const RayBatch& o) { append(o, 0, o.size()); }

    /// The batch's arrays, for copying them one by one (in parallel): array k of 0..kArrays-1.
    static constexpr size_t kArrays = 13;
    /// Appends array k of each of `parts` (in order) to array k of this batch.
    template <class Parts>
    void append_array(size_t k, const Parts& parts) {
        size_t index = 0;
        for_each_array([&](auto member, RayBatch& self) {
            if (index++ != k) return;
            auto& dst = self.*member;
            size_t total = dst.size();
            for (const RayBatch* p : parts) total += ((*p).*member).size();
            if (total > dst.capacity()) dst.reserve(std::max(total, 2 * dst.capacity()));  // geometric growth
            for (const RayBatch* p : parts) dst.insert(dst.end(), ((*p).*member).begin(), ((*p).*member).end());
        });
    }

    /// Empties the batch but keeps its memory for reuse.
    void reset() {
        for_each_array([](auto member, RayBatch& self) { (self.*member).clear(); });
    }

    /// Calls f(pointer to member, *this) for each of the kArrays arrays, in a fixed order.
    template <class F>
    void for_each_array(F&& f) {
        f(&RayBatch::ox, *this), f(&RayBatch::oy, *this), f(&RayBatch::oz, *this);
        f(&RayBatch::dx, *this), f(&RayBatch::dy, *this), f(&RayBatch::dz, *this);
        f(&RayBatch::br, *this), f(&RayBatch::bg, *this), f(&RayBatch::bb, *this);
        f(&RayBatch::pixel, *this), f(&RayBatch::depth, *this), f(&RayBatch::flags, *this), f(&RayBatch::path, *this);
    }

    void clear() { *this = RayBatch{}; }
};

}  // namespace crex
