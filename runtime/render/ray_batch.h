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
};

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
        for (auto* v : {&ox, &oy, &oz, &dx, &dy, &dz, &br, &bg, &bb}) v->resize(n);
        pixel.resize(n), depth.resize(n), flags.resize(n), path.resize(n);
    }

    RayRecord get(size_t i) const {
        return {{ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]}, {br[i], bg[i], bb[i]}, pixel[i], depth[i], flags[i], path[i]};
    }

    /// Appends rays [begin, end) of `o`, array by array.
    void append(const RayBatch& o, size_t begin, size_t end) {
        auto cat = [begin, end](auto& a, const auto& b) {
            a.insert(a.end(), b.begin() + static_cast<std::ptrdiff_t>(begin), b.begin() + static_cast<std::ptrdiff_t>(end));
        };
        cat(ox, o.ox), cat(oy, o.oy), cat(oz, o.oz), cat(dx, o.dx), cat(dy, o.dy), cat(dz, o.dz);
        cat(br, o.br), cat(bg, o.bg), cat(bb, o.bb), cat(pixel, o.pixel), cat(depth, o.depth), cat(flags, o.flags);
        cat(path, o.path);
    }
    /// Appends all of `o`, array by array (much cheaper than ray by ray).
    void append(const RayBatch& o) {
        auto cat = [](auto& a, const auto& b) { a.insert(a.end(), b.begin(), b.end()); };
        cat(ox, o.ox), cat(oy, o.oy), cat(oz, o.oz), cat(dx, o.dx), cat(dy, o.dy), cat(dz, o.dz);
        cat(br, o.br), cat(bg, o.bg), cat(bb, o.bb), cat(pixel, o.pixel), cat(depth, o.depth), cat(flags, o.flags);
        cat(path, o.path);
    }

    /// The batch's arrays, for copying them one by one (in parallel): array k of 0..kArrays-1.
    static constexpr size_t kArrays = 13;
    /// Appends array k of each of `parts` (in order) to array k of this batch.
    template <class Parts>
    void append_array(size_t k, const Parts& parts) {
        auto cat = [&parts](auto member, RayBatch& to) {
            auto& dst = to.*member;
            size_t total = dst.size();
            for (const RayBatch* p : parts) total += ((*p).*member).size();
            if (total > dst.capacity()) dst.reserve(std::max(total, 2 * dst.capacity()));  // geometric growth
            for (const RayBatch* p : parts) dst.insert(dst.end(), ((*p).*member).begin(), ((*p).*member).end());
        };
        switch (k) {
        case 0: cat(&RayBatch::ox, *this); break;
        case 1: cat(&RayBatch::oy, *this); break;
        case 2: cat(&RayBatch::oz, *this); break;
        case 3: cat(&RayBatch::dx, *this); break;
        case 4: cat(&RayBatch::dy, *this); break;
        case 5: cat(&RayBatch::dz, *this); break;
        case 6: cat(&RayBatch::br, *this); break;
        case 7: cat(&RayBatch::bg, *this); break;
        case 8: cat(&RayBatch::bb, *this); break;
        case 9: cat(&RayBatch::pixel, *this); break;
        case 10: cat(&RayBatch::depth, *this); break;
        case 11: cat(&RayBatch::flags, *this); break;
        default: cat(&RayBatch::path, *this); break;
        }
    }

    /// Empties the batch but keeps its memory for reuse.
    void reset() {
        for (auto* v : {&ox, &oy, &oz, &dx, &dy, &dz, &br, &bg, &bb}) v->clear();
        pixel.clear(), depth.clear(), flags.clear(), path.clear();
    }

    void clear() { *this = RayBatch{}; }
};

}  // namespace crex
