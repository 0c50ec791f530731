#include "runtime/cache/caustic_photons.h"

#include <nanoflann.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "runtime/base/sampling.h"
#include "runtime/render/bsdf.h"
#include "runtime/render/shade.h"
#include "runtime/trace/trace_batch.h"

namespace crex {
namespace {

/// A bounding sphere of one delta shape or trans surface: what photons are aimed at.
struct Target {
    Vec3 centre;
    double radius = 0;
};

std::vector<Target> pass_through_targets(const RenderScene& scene) {
    std::vector<Target> out;
    const double pad = 1e-4 * scene.embree->extent();
    Vec3 all_lo{1e300, 1e300, 1e300}, all_hi{-1e300, -1e300, -1e300};
    for (const GeometryInfo& g : scene.embree->geometries()) {
        const bool passes = is_delta_material(scene.scene.materials[g.material].type) || transmission_share(scene.bsdfs[g.material]) > 0;
        if (!passes) continue;
        Target t;
        Vec3 lo, hi;
        if (g.sphere) {
            lo = g.center - Vec3{g.radius, g.radius, g.radius}, hi = g.center + Vec3{g.radius, g.radius, g.radius};
            t = {g.center, g.radius + pad};
        } else {
            if (g.positions.empty()) continue;
            lo = hi = g.positions.front();
            for (const Vec3& p : g.positions) lo = vmin(lo, p), hi = vmax(hi, p);
            t.centre = (lo + hi) * 0.5;
            for (const Vec3& p : g.positions) t.radius = std::fmax(t.radius, length(p - t.centre));
            t.radius += pad;
        }
        all_lo = vmin(all_lo, lo), all_hi = vmax(all_hi, hi);
        out.push_back(t);
    }
    // Many delta shapes (a faceted chandelier): one sphere around them all keeps aiming cheap.
    if (out.size() > 64) out = {{(all_lo + all_hi) * 0.5, length(all_hi - all_lo) * 0.5 + pad}};
    return out;
}

/// The cone of directions from y to a target: cos of its half-angle and its solid angle
/// (the whole sphere when y is inside the target's sphere).
struct Cone {
    Vec3 axis;
    double cos_half = -1, solid_angle = 4 * kPi;
};

Cone cone_to(const Vec3& y, const Target& t) {
    Vec3 d = t.centre - y;
    double dist = length(d);
    if (!(dist > t.radius)) return {};
    Cone c;
    c.axis = d / dist;
    double s = t.radius / dist;
    c.cos_half = std::sqrt(std::fmax(0.0, 1 - s * s));
    c.solid_angle = 2 * kPi * (1 - c.cos_half);
    return c;
}

Vec3 to_vec(const float v[3]) { return {v[0], v[1], v[2]}; }
void put(float out[3], const Vec3& v) {
    out[0] = static_cast<float>(v.x), out[1] = static_cast<float>(v.y), out[2] = static_cast<float>(v.z);
}

/// The k nearest as a max-heap on distance (nanoflann's KNNResultSet inserts in sorted order,
/// O(k) a point: at k = 64 most of the map's build time). Unsorted; the farthest is first.
class NearestHeap {
public:
    NearestHeap(uint32_t k, float r2, uint32_t* index, float* dist2) : k_(k), r2_(r2), index_(index), dist2_(dist2) {}
    size_t size() const { return count_; }
    bool full() const { return count_ == k_; }
    float worstDist() const { return count_ < k_ ? r2_ : dist2_[0]; }
    bool addPoint(float d2, uint32_t i) {
        if (count_ < k_) {
            dist2_[count_] = d2, index_[count_] = i;
            sift_up(count_++);
        } else if (d2 < dist2_[0]) {
            dist2_[0] = d2, index_[0] = i;
            sift_down(0);
        }
        return true;
    }

private:
    void swap_at(size_t a, size_t b) { std::swap(dist2_[a], dist2_[b]), std::swap(index_[a], index_[b]); }
    // Ties broken by index, so the set found does not depend on the order of the search.
    bool above(size_t a, size_t b) const { return dist2_[a] > dist2_[b] || (dist2_[a] == dist2_[b] && index_[a] > index_[b]); }
    void sift_up(size_t c) {
        while (c > 0 && above(c, (c - 1) / 2)) swap_at(c, (c - 1) / 2), c = (c - 1) / 2;
    }
    void sift_down(size_t p) {
        for (;;) {
            size_t l = 2 * p + 1, r = l + 1, m = p;
            if (l < count_ && above(l, m)) m = l;
            if (r < count_ && above(r, m)) m = r;
            if (m == p) return;
            swap_at(p, m), p = m;
        }
    }
    uint32_t k_, count_ = 0;
    float r2_;
    uint32_t* index_;
    float* dist2_;
};

/// nanoflann's view of points with a `position` (the photons, for their density estimates).
template <class Point>
struct PointTree {
    struct Cloud {
        const std::vector<Point>* points;
        size_t kdtree_get_point_count() const { return points->size(); }
        float kdtree_get_pt(size_t i, size_t dim) const { return (*points)[i].position[dim]; }
        template <class Box>
        bool kdtree_get_bbox(Box&) const { return false; }
    };
    using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3, uint32_t>;
    Cloud cloud;
    Index index;
    explicit PointTree(const std::vector<Point>& p) : cloud{&p}, index(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(12)) {}
    /// Up to k (<= 1024) nearest points closer than sqrt(r2); returns how many, the farthest
    /// first, in no other order.
    size_t nearest(const Vec3& x, uint32_t k, float r2, uint32_t* index_out, float* dist2_out) const {
        NearestHeap result(k, r2, index_out, dist2_out);
        const float q[3] = {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)};
        index.findNeighbors(result, q, nanoflann::SearchParams());
        return result.size();
    }
};

}  // namespace

CausticPhotons::~CausticPhotons() = default;

std::shared_ptr<const CausticPhotons> build_caustic_photons(const RenderScene& scene, uint32_t photons, uint64_t seed,
                                                           std::function<void(const char* phase, double done)> progress) {
    if (photons == 0) return nullptr;
    CausticPhotonSettings cs;
    cs.photons = photons;
    cs.seed = seed;
    cs.progress = std::move(progress);
    return std::make_shared<const CausticPhotons>(scene, cs);
}

CausticPhotons::CausticPhotons(const RenderScene& scene, const CausticPhotonSettings& settings)
    : neighbours_(std::clamp(settings.neighbours, 1u, 1024u)) {
    const double extent = scene.embree->extent();
    max_radius_ = settings.max_radius > 0 ? settings.max_radius : extent / 16;
    const std::vector<Target> targets = pass_through_targets(scene);
    if (targets.empty() || !scene.lights || scene.lights->empty() || settings.photons == 0) return;

    const size_t total_photons = settings.photons;
    const uint64_t base = hash_combine(settings.seed, 0xca057ull);
    // In chunks of 64 Ki photons, each in the memory of the chunk before (11 MB of rays and
    // state): memory stays bounded whatever --caustic-photons asks, and pages touched for the
    // first time, which cost more than tracing on some machines (a 200,000-photon map on the
    // Cornell box spent half its time in page faults when a chunk held them all), are touched
    // once. Photon j's numbers depend on j alone, so the chunk size changes no photon.
    constexpr size_t kChunk = size_t{1} << 16;
    const size_t most = std::min(kChunk, total_photons);
    std::vector<RTCRayHit> rays(most), batch(most);
    std::vector<Vec3> power(most), dir(most);
    std::vector<uint8_t> state(most), through_trans(most), passed(most);
    std::vector<Photon> stored(most);
    std::vector<size_t> go;
    go.reserve(most);
    // Room for every photon kept, reserved once: growing by doubling copied the photons into
    // fresh pages at every step, and shrinking to fit once more (12 % of a default render's page
    // faults). Pages are touched as photons are written, so the unused tail costs no memory.
    photons_.reserve(total_photons);
    if (settings.progress) settings.progress("tracing", 0);
    for (size_t first = 0; first < total_photons; first += kChunk) {
        const size_t n = std::min(kChunk, total_photons - first);
        // Emission: a point on an emitter (by power), then a direction uniformly in the union of
        // the cones towards the targets, chosen by solid angle: pdf(w) = (cones holding w) / sum of
        // their solid angles, so overlapping cones are counted once each (one-sample MIS).
        tbb::parallel_for(size_t{0}, n, [&](size_t j) {
            RTCRayHit& r = rays[j];
            r = RTCRayHit{};
            r.ray.tnear = 1.0f, r.ray.tfar = 0.0f, r.ray.mask = 0xFFFFFFFFu;  // a hole unless aimed
            r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            const uint64_t key = hash_combine(base, first + j);
            HitRandom rnd(key, 0);
            double u, v;
            rnd.pair(RandomUse::kLight, u, v);
            LightSample ls = scene.lights->sample(rnd(RandomUse::kLightPick), u, v);
            // Photons leave local `light` and `illum` emitters (not distant sources, nor glows,
            // whose light is direct lighting's near them and the rays' beyond).
            // Nor textured emissions: rays through glass see those (Bsdf::emission_sampled).
            if (!(ls.pdf_area > 0) || (ls.limits && (std::isfinite(ls.limits->max_distance) || ls.limits->emission))) return;
            std::array<Cone, 64> cones;
            double total = 0;
            for (size_t k = 0; k < targets.size(); ++k) total += (cones[k] = cone_to(ls.position, targets[k])).solid_angle;
            double pick = rnd(RandomUse::kLobeD) * total, acc = 0;
            size_t chosen = 0;
            for (; chosen + 1 < targets.size(); ++chosen)
                if (pick < (acc += cones[chosen].solid_angle)) break;
            const Cone& c = cones[chosen];
            double a, b;
            rnd.pair(RandomUse::kLobeDT, a, b);
            double cos_t = 1 - a * (1 - c.cos_half), sin_t = std::sqrt(std::fmax(0.0, 1 - cos_t * cos_t)), phi = 2 * kPi * b;
            Vec3 t1, t2;
            Vec3 axis = c.cos_half > -1 ? c.axis : Vec3{0, 0, 1};
            orthonormal_basis(axis, t1, t2);
            Vec3 w = t1 * (sin_t * std::cos(phi)) + t2 * (sin_t * std::sin(phi)) + axis * cos_t;
            double cos_light = dot(w, ls.normal);
            if (!(cos_light > 0)) return;  // emitters light their front side only
            if (ls.limits && ls.limits->spot_cos >= -1 && dot(w, ls.limits->spot_axis) < ls.limits->spot_cos) return;  // outside the cone
            int holding = 0;
            for (size_t k = 0; k < targets.size(); ++k) holding += cones[k].cos_half <= -1 || dot(w, cones[k].axis) >= cones[k].cos_half;
            double pdf_w = std::max(holding, 1) / total;
            power[j] = patterned_radiance(ls, -w, 0) * (cos_light / (ls.pdf_area * pdf_w * static_cast<double>(total_photons)));
            if (!is_finite(power[j])) return;
            dir[j] = w;
            Vec3 o = ls.position + ls.normal * scene.embree->epsilon_at(ls.position);
            set_ray(r, static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(w.x), static_cast<float>(w.y),
                    static_cast<float>(w.z), static_cast<unsigned>(j));
        });
        intersect_batch(*scene.embree, rays.data(), n, false);
        rays_ += n;

        // Follow each photon through the delta shapes and through trans surfaces' specular
        // transmission (the lobes the cache's hemisphere rays follow, chosen the same way);
        // keep it at the first surface it is shaded at after at least one of them, if that has
        // a diffuse lobe. A photon shaded at its first hit is light the records see by themselves.
        std::fill_n(state.begin(), n, uint8_t{0});  // 0 travelling, 1 stored, 2 dropped
        std::fill_n(through_trans.begin(), n, uint8_t{0});
        std::fill_n(passed.begin(), n, uint8_t{0});
        for (uint32_t bounce = 0; bounce <= 8; ++bounce) {
            go.clear();
            tbb::parallel_for(size_t{0}, n, [&](size_t j) {
                if (state[j] != 0) return;
                through_trans[j] = 0;
                const RTCRayHit& h = rays[j];
                if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID || !(h.ray.tfar > h.ray.tnear)) {
                    state[j] = 2;
                    return;
                }
                if (scene.medium) power[j] = power[j] * scene.medium->transmittance(Vec3{h.ray.org_x, h.ray.org_y, h.ray.org_z}, dir[j], h.ray.tfar);
                const Bsdf& b = scene.bsdf_of(h.hit.geomID);
                if (is_delta_material(b.type)) return;
                const double pass = transmission_share(b);
                if (pass > 0 && random_at(hash_combine(base, first + j), bounce + 1, RandomUse::kIcTrans) < pass) {
                    through_trans[j] = 1;
                    return;
                }
                state[j] = 2;
                if (!passed[j] || !(max_component(b.diffuse) > 0)) return;
                Vec3 o{h.ray.org_x, h.ray.org_y, h.ray.org_z};
                HitFrame f = hit_frame(*scene.embree, h.hit, o + dir[j] * static_cast<double>(h.ray.tfar), dir[j], h.ray.tfar);
                put(stored[j].position, f.position), put(stored[j].normal, f.normal), put(stored[j].power, power[j] / (1 - pass));
                state[j] = 1;
            });
            for (size_t j = 0; j < n; ++j)
                if (state[j] == 0) go.push_back(j);
            if (go.empty()) break;
            if (bounce == 8) break;  // still inside glass after 8 interfaces: dropped
            tbb::parallel_for(size_t{0}, go.size(), [&](size_t g) {
                const size_t j = go[g];
                RTCRayHit& h = rays[j];
                Vec3 o{h.ray.org_x, h.ray.org_y, h.ray.org_z};
                double t = h.ray.tfar;
                HitFrame f = hit_frame(*scene.embree, h.hit, o + dir[j] * t, dir[j], t);
                const uint64_t key = hash_combine(base, first + j);
                // Whether the photon passes a trans surface is the material's constants' choice
                // (as in the loop above); the lobes it scatters into are the surface's own.
                Bsdf textured;
                const Bsdf& b = through_trans[j] ? scene.bsdf_of(h.hit.geomID) : surface_at(scene, h.hit, f, textured, SurfaceDetail::kAveraged);
                h = RTCRayHit{};
                h.ray.tnear = 1.0f, h.ray.tfar = 0.0f, h.ray.mask = 0xFFFFFFFFu;
                h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                Lobe lobe;
                double prob = 0;
                if (through_trans[j]) {
                    lobe = {Component::kT, dir[j], b.specular_transmit, true, true, b.clear_transmission};  // undeviated
                    prob = transmission_share(b);
                } else {
                    std::array<Lobe, kMaxLobes> lobes;
                    int nl = scatter(b, f, HitRandom(key, bounce + 1), lobes);
                    const int pick = choose_lobe(lobes, nl, random_at(key, bounce + 1, RandomUse::kIcLobe), prob);
                    if (pick < 0) return;  // absorbed: found a hole next round
                    lobe = lobes[static_cast<size_t>(pick)];
                }
                power[j] = power[j] * lobe.weight / prob;
                // Light that only went straight through thin glass or trans is direct lighting's
                // (shadow rays cross those): a caustic needs a bend.
                if (!lobe.straight) passed[j] = 1;
                dir[j] = lobe.direction;
                Vec3 no = f.position + (lobe.transmits ? -f.normal : f.normal) * f.epsilon;
                set_ray(h, static_cast<float>(no.x), static_cast<float>(no.y), static_cast<float>(no.z), static_cast<float>(lobe.direction.x),
                        static_cast<float>(lobe.direction.y), static_cast<float>(lobe.direction.z), static_cast<unsigned>(j));
            });
            for (size_t g = 0; g < go.size(); ++g) batch[g] = rays[go[g]];
            intersect_batch(*scene.embree, batch.data(), go.size(), false);
            for (size_t g = 0; g < go.size(); ++g) rays[go[g]] = batch[g];
            rays_ += go.size();
        }
        for (size_t j = 0; j < n; ++j)
            if (state[j] == 1 && is_finite(to_vec(stored[j].power))) photons_.push_back(stored[j]);
        if (settings.progress) settings.progress("tracing", static_cast<double>(first + n) / static_cast<double>(total_photons));
    }

    if (photons_.empty()) return;
    precompute(settings.progress);
    build_disc_grid();
}

namespace {

// The density estimate at x (Jensen): the k nearest photons within max_radius on the side
// `n` faces, through an Epanechnikov kernel over the disc to the k-th of them; r2_out is the
// disc's squared radius.
Vec3 photon_density(const std::vector<CausticPhotons::Photon>& photons, const PointTree<CausticPhotons::Photon>& tree, uint32_t k,
                    double max_radius, const Vec3& x, const Vec3& n, double& r2_out) {
    std::array<uint32_t, 1024> index{};
    std::array<float, 1024> dist2{};
    const float r_max2 = static_cast<float>(max_radius * max_radius);
    const size_t found = tree.nearest(x, k, r_max2, index.data(), dist2.data());
    // The disc reaches the k-th neighbour, or max_radius when fewer are that close.
    const double r2 = found == k ? std::min<double>(dist2[0], r_max2) : r_max2;
    r2_out = r2;
    if (found == 0 || !(r2 > 0)) return {};
    Vec3 sum{};
    for (size_t i = 0; i < found; ++i) {
        const CausticPhotons::Photon& p = photons[index[i]];
        if (!(dot(to_vec(p.normal), n) > 0.5)) continue;  // another surface, or the far side of this one
        sum += to_vec(p.power) * std::fmax(0.0, 1 - dist2[i] / r2);
    }
    Vec3 e = sum * (2 / (kPi * r2));  // Epanechnikov: the kernel integrates to pi r^2 / 2
    return is_finite(e) ? e : Vec3{};
}

// The cells a disc's bounding cube covers along each axis, clamped to the grid.
struct CellSpan {
    int lo[3], hi[3];
    size_t count() const { return size_t(hi[0] - lo[0] + 1) * size_t(hi[1] - lo[1] + 1) * size_t(hi[2] - lo[2] + 1); }
};

}  // namespace

void CausticPhotons::precompute(const std::function<void(const char*, double)>& progress) {
    // Christensen (1999): the density estimate at every 8th photon, once; a query then blends
    // the estimates near it instead of gathering k photons (64-spp --ic on the Cornell box
    // spent 2 of its 5 s gathering). Every 8th with k = 32 measured as good as every 4th with
    // k = 64 (FLIP 0.0354 against 0.0358, 16 spp) at two thirds of the build time.
    if (progress) progress("photon tree", 0);
    const PointTree<Photon> tree(photons_);  // needed for the estimates alone
    constexpr size_t kStride = 8;
    estimates_.resize((photons_.size() + kStride - 1) / kStride);
    // In parts, to say how far it got (a part is at least 64 Ki estimates: no cost in parallelism).
    const size_t part = std::max<size_t>(size_t{1} << 16, (estimates_.size() + 99) / 100);
    if (progress) progress("density estimates", 0);  // the phase's clock starts here
    for (size_t begin = 0; begin < estimates_.size(); begin += part) {
        const size_t end = std::min(estimates_.size(), begin + part);
        tbb::parallel_for(begin, end, [&](size_t i) {
            const Photon& p = photons_[kStride * i];
            Estimate& e = estimates_[i];
            std::copy(p.position, p.position + 3, e.position);
            std::copy(p.normal, p.normal + 3, e.normal);
            double r2 = 0;
            put(e.irradiance, photon_density(photons_, tree, neighbours_, max_radius_, to_vec(p.position), to_vec(p.normal), r2));
            e.radius2 = static_cast<float>(r2);
        });
        if (progress) progress("density estimates", static_cast<double>(end) / static_cast<double>(estimates_.size()));
    }
}

void CausticPhotons::build_disc_grid() {
    if (estimates_.empty() || estimates_.size() > std::numeric_limits<uint32_t>::max()) return;
    // Each disc's bounding cube, a little larger than the disc (float rounding of the test
    // d2 < r2 at a query must never find a disc in a cell it was not listed in).
    std::vector<std::pair<Vec3, Vec3>> cubes(estimates_.size());
    constexpr double kInf = std::numeric_limits<double>::infinity();
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    for (size_t i = 0; i < estimates_.size(); ++i) {
        const Estimate& e = estimates_[i];
        const Vec3 p = to_vec(e.position);
        const double r = std::sqrt(static_cast<double>(e.radius2)) * (1 + 1e-5) + 1e-6 * length(p);
        cubes[i] = {p - Vec3{r, r, r}, p + Vec3{r, r, r}};
        lo = vmin(lo, cubes[i].first), hi = vmax(hi, cubes[i].second);
    }
    const double side = std::fmax(hi.x - lo.x, std::fmax(hi.y - lo.y, hi.z - lo.z));
    if (!(side > 0) || !std::isfinite(side)) return;  // no grid: no query finds a disc
    // Cells as small as 64 along the longest side allow, grown while the lists would hold more
    // than 8 Mi entries (32 MB; a disc of a sparse region spans many small cells).
    constexpr int kMostCells = 64;
    constexpr size_t kMostEntries = size_t{8} << 20;
    grid_.origin = lo;
    grid_.cell = side / kMostCells;
    std::vector<CellSpan> spans(cubes.size());
    for (;;) {
        const double extent[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
        for (int a = 0; a < 3; ++a) grid_.dims[a] = std::clamp(static_cast<int>(std::ceil(extent[a] / grid_.cell)) + 1, 1, kMostCells + 1);
        size_t entries = 0;
        for (size_t i = 0; i < cubes.size(); ++i) {
            const double l[3] = {cubes[i].first.x, cubes[i].first.y, cubes[i].first.z}, h[3] = {cubes[i].second.x, cubes[i].second.y, cubes[i].second.z};
            const double o[3] = {lo.x, lo.y, lo.z};
            for (int a = 0; a < 3; ++a) {
                spans[i].lo[a] = std::clamp(static_cast<int>(std::floor((l[a] - o[a]) / grid_.cell)), 0, grid_.dims[a] - 1);
                spans[i].hi[a] = std::clamp(static_cast<int>(std::floor((h[a] - o[a]) / grid_.cell)), 0, grid_.dims[a] - 1);
            }
            entries += spans[i].count();
        }
        if (entries <= kMostEntries || (grid_.dims[0] == 1 && grid_.dims[1] == 1 && grid_.dims[2] == 1)) break;
        grid_.cell *= 1.5;
    }
    // Compressed rows: count each cell's discs, then list them in index order.
    const size_t cells = static_cast<size_t>(grid_.dims[0]) * grid_.dims[1] * grid_.dims[2];
    auto for_each_cell = [&](const CellSpan& s, auto&& visit) {
        for (int x = s.lo[0]; x <= s.hi[0]; ++x)
            for (int y = s.lo[1]; y <= s.hi[1]; ++y)
                for (int z = s.lo[2]; z <= s.hi[2]; ++z) visit((static_cast<size_t>(x) * grid_.dims[1] + y) * grid_.dims[2] + z);
    };
    grid_.first.assign(cells + 1, 0);
    for (const CellSpan& s : spans) for_each_cell(s, [&](size_t c) { ++grid_.first[c + 1]; });
    for (size_t c = 0; c < cells; ++c) grid_.first[c + 1] += grid_.first[c];
    grid_.discs.resize(grid_.first[cells]);
    std::vector<uint32_t> next(grid_.first.begin(), grid_.first.end() - 1);
    for (size_t i = 0; i < spans.size(); ++i) for_each_cell(spans[i], [&](size_t c) { grid_.discs[next[c]++] = static_cast<uint32_t>(i); });
}

int64_t CausticPhotons::DiscGrid::cell_of(const Vec3& x) const {
    if (first.empty()) return -1;
    const double p[3] = {x.x, x.y, x.z}, o[3] = {origin.x, origin.y, origin.z};
    int64_t c[3];
    for (int k = 0; k < 3; ++k) {
        const double f = std::floor((p[k] - o[k]) / cell);
        if (!(f >= 0 && f < dims[k])) return -1;  // outside every disc, or not a number
        c[k] = static_cast<int64_t>(f);
    }
    return (c[0] * dims[1] + c[1]) * dims[2] + c[2];
}

Vec3 CausticPhotons::irradiance(const Vec3& x, const Vec3& n) const {
    const int64_t c = grid_.cell_of(x);
    if (c < 0) return {};
    const float q[3] = {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)};
    // Each estimate whose disc holds x reaches it through its own kernel, normalised by the
    // disc's area: weights of (1 - d^2/r^2) alone favoured the sparse side's larger discs (-8 %
    // where a mirror's caustic fades).
    double sum_w = 0;
    Vec3 sum{};
    for (uint32_t k = grid_.first[static_cast<size_t>(c)], end = grid_.first[static_cast<size_t>(c) + 1]; k < end; ++k) {
        const Estimate& e = estimates_[grid_.discs[k]];
        const float dx = q[0] - e.position[0], dy = q[1] - e.position[1], dz = q[2] - e.position[2];
        const float d2 = dx * dx + dy * dy + dz * dz;
        if (!(d2 < e.radius2) || !(dot(to_vec(e.normal), n) > 0.5)) continue;
        const double w = (1 - d2 / e.radius2) / e.radius2;
        sum_w += w;
        sum += to_vec(e.irradiance) * w;
    }
    if (!(sum_w > 0)) return {};
    Vec3 e = sum / sum_w;
    return is_finite(e) ? e : Vec3{};
}

}  // namespace crex
