#include "runtime/cache/irradiance_cache.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "base/input_file.h"
#include "runtime/base/atomic_file.h"
#include "runtime/base/sampling.h"

namespace crex {
namespace {

double clamp_accuracy(double aa) { return std::isfinite(aa) ? std::clamp(aa, 1e-3, 1.0) : 1.0; }

}  // namespace

IrradianceCache::IrradianceCache(const RenderScene& scene, const IcSettings& settings, std::shared_ptr<const CausticPhotons> caustics)
    : scene_(scene), settings_(settings), hot_(settings.hot_surfaces && scene.hot && !scene.hot->empty() ? scene.hot.get() : nullptr) {
    double extent = scene.embree->extent();
    r_min_ = settings.min_radius > 0 ? settings.min_radius : extent / (settings.resolution > 0 ? settings.resolution : 2000);
    r_max_ = settings.max_radius > 0 ? settings.max_radius : 0.25 * extent;
    r_max_ = std::max(r_max_, r_min_);
    // Local coordinates lie within the extent: float positions are off by at most 6e-8 of it
    // per coordinate, so a margin of 5e-7 of it keeps the float test conservative.
    position_slack_ = static_cast<float>(5e-7 * extent);
    stats_.hot_triangles = hot_ ? hot_->size() : 0;
    max_aa_ = clamp_accuracy(settings.max_accuracy > 0 ? std::max(settings.max_accuracy, settings.accuracy) : settings.accuracy);
    // Validity radii lie in [aa_min r_min, r_max]: one grid level per halving.
    double top = 2 * r_max_;
    for (double c = top; c >= 2 * 1e-3 * r_min_ && cell_size_.size() < kMaxGridLevels; c /= 2) cell_size_.push_back(c);
    if (settings.caustic_photons > 0) {  // carried in when built already: the photons do not depend on the camera
        if (!caustics) {
            const auto start = std::chrono::steady_clock::now();
            caustics = build_caustic_photons(scene, settings.caustic_photons, settings.seed);
            stats_.caustic_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        }
        caustics_ = photons_in(caustics);
        if (caustics_) stats_.caustic_photons = caustics_->size();
    }
}

IrradianceCache::~IrradianceCache() = default;

double IcStats::throughput_past_last_bounce() const {
    if (albedo_rays.empty()) return 0;
    double t = 1;
    for (size_t l = 0; l < albedo_rays.size(); ++l) t *= albedo_rays[l] > 0 ? albedo_sum[l] / static_cast<double>(albedo_rays[l]) : 0.0;
    return t;
}

double IrradianceCache::level_accuracy(double aa, uint32_t level) const {
    return clamp_accuracy(std::min(aa, max_aa_) * static_cast<double>(1u << std::min(level, 10u)));
}

uint64_t IrradianceCache::cell_key(int x, int y, int z) const {
    auto u = [](int v) { return static_cast<uint64_t>(static_cast<uint32_t>(v) & 0x1fffffu); };
    return (u(x) << 42) | (u(y) << 21) | u(z);
}

void IrradianceCache::sync_normals() {
    // push_back's own doubling: a reserve of exactly records_.size() here reallocated at every
    // single insert().
    for (size_t i = normals_.size(); i < records_.size(); ++i) {
        const Vec3& n = records_[i].normal;
        normals_.push_back({static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)});
    }
}

void IrradianceCache::insert(const IrradianceRecord& r) {
    records_.push_back(r);
    sync_normals();
    make_grids(r.level);
    file(static_cast<uint32_t>(records_.size() - 1));
}

void IrradianceCache::make_grids(uint32_t level) {
    if (grids_.size() <= level) grids_.resize(level + 1u);
    if (grids_[level].empty()) grids_[level].resize(cell_size_.size());
}

void IrradianceCache::file(uint32_t index) {
    const IrradianceRecord& r = records_[index];
    // The largest radius at which any query may use it: its level's coarsest accuracy times R.
    double rad = level_accuracy(max_aa_, r.level) * r.harmonic_distance;
    size_t L = 0;
    while (L + 1 < cell_size_.size() && cell_size_[L + 1] >= 2 * rad) ++L;
    double cell = cell_size_[L];
    int x0 = static_cast<int>(std::floor((r.position.x - rad) / cell)), x1 = static_cast<int>(std::floor((r.position.x + rad) / cell));
    int y0 = static_cast<int>(std::floor((r.position.y - rad) / cell)), y1 = static_cast<int>(std::floor((r.position.y + rad) / cell));
    int z0 = static_cast<int>(std::floor((r.position.z - rad) / cell)), z1 = static_cast<int>(std::floor((r.position.z + rad) / cell));
    CellTable& table = grids_[r.level][L];
    for (int x = x0; x <= x1; ++x)
        for (int y = y0; y <= y1; ++y)
            for (int z = z0; z <= z1; ++z)
                table.add(cell_key(x, y, z), {static_cast<float>(r.position.x), static_cast<float>(r.position.y),
                                              static_cast<float>(r.position.z), static_cast<float>(r.harmonic_distance), index});
}

void IrradianceCache::insert(const std::vector<IrradianceRecord>& records, IcGrids* handed) {
    size_t first = records_.size();
    if (handed) {
        if (first == 0 && handed->filed <= handed->records.size() && handed->max_aa == max_aa_ && handed->cell_size == cell_size_) {
            records_ = std::move(handed->records);
            grids_ = std::move(handed->grids);
            first = handed->filed;  // filed already, in the records' order
        } else {
            records_.insert(records_.end(), std::make_move_iterator(handed->records.begin()), std::make_move_iterator(handed->records.end()));
        }
        handed->records = {};
        handed->grids = {};
    }
    records_.insert(records_.end(), records.begin(), records.end());
    sync_normals();
    uint32_t levels = 0;
    for (size_t i = first; i < records_.size(); ++i) levels = std::max(levels, records_[i].level + 1u);
    for (uint32_t level = 0; level < levels; ++level) make_grids(level);
    // Each bounce level has grids of its own: the levels are filed side by side, each in the
    // records' order, so every cell lists the same entries in the same order as one by one.
    // (A walk's later frame files every record carried: 136,000 on the living-room dolly,
    // serial, 5 % of the frame; level 1 holds about half of them.)
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, levels, 1), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t level = range.begin(); level < range.end(); ++level)
            for (size_t i = first; i < records_.size(); ++i)
                if (records_[i].level == level) file(static_cast<uint32_t>(i));
    }, tbb::simple_partitioner());
}

std::vector<IrradianceRecord> IrradianceCache::take_records(std::shared_ptr<IcGrids>* grids) {
    if (grids) *grids = std::make_shared<IcGrids>(IcGrids{{}, 0, records_.size(), max_aa_, cell_size_, std::move(grids_)});
    grids_.clear();
    std::vector<IrradianceRecord> out;
    out.swap(records_);
    normals_.clear();
    return out;
}

bool IrradianceCache::lookup(const Vec3& x, const Vec3& n, double aa, uint32_t level, Vec3& e, uint16_t divisions) const {
    aa = level_accuracy(aa, level);
    // A pixel that asks for quieter records than the cache's (`vary ic_rays`) takes none made with fewer rays.
    const uint32_t min_divisions = divisions ? divisions_of(divisions) : 0;
    const double aa2 = aa * aa;
    double sum_w = 0;
    Vec3 sum{};
    if (level >= grids_.size()) return false;
    const std::vector<CellTable>& grids = grids_[level];
    const float xf = static_cast<float>(x.x), yf = static_cast<float>(x.y), zf = static_cast<float>(x.z);
    const float aa_f = static_cast<float>(aa) * 1.001f;
    // Ward's weight passes only where sqrt(1 - n.n_i) < aa, so n.n_i > 1 - aa^2 (and > 0): a
    // candidate is asked that of its normal (in float, less a margin far beyond float's
    // rounding of unit normals) before its record is fetched.
    const float min_cos = static_cast<float>(std::max(1 - aa2, 0.0)) - 1e-5f;
    const float nxf = static_cast<float>(n.x), nyf = static_cast<float>(n.y), nzf = static_cast<float>(n.z);
    // A lookup waits on memory more than it computes: the slot of x's cell at every level,
    // the cell's entries, each record it reads. Each of those steps is asked for at every
    // level (and for every candidate) before the first is used, so the waits overlap; the
    // records are still taken in the same order, so the sums are the same.
    std::array<uint64_t, kMaxGridLevels> keys;
    std::array<const CellTable*, kMaxGridLevels> tables;
    size_t probes = 0;
    for (size_t L = 0; L < grids.size() && probes < kMaxGridLevels; ++L) {
        if (grids[L].empty()) continue;
        const double cell = cell_size_[L];
        keys[probes] = cell_key(static_cast<int>(std::floor(x.x / cell)), static_cast<int>(std::floor(x.y / cell)),
                                static_cast<int>(std::floor(x.z / cell)));
        tables[probes] = &grids[L];
        grids[L].prefetch(keys[probes++]);
    }
    std::array<const GridCell*, kMaxGridLevels> cells;
    size_t found = 0;
    for (size_t p = 0; p < probes; ++p)
        if (const GridCell* c = tables[p]->find(keys[p])) {
            c->prefetch();
            cells[found++] = c;
        }
    // A record made for a coarser accuracy is used too: Ward's test at this lookup's accuracy
    // already keeps it within aa R_i of its site. (Refusing such records drew a sharp band where
    // the `ic` map first lifted a pixel above the preview's accuracy.)
    auto use = [&](uint32_t index) {
        const IrradianceRecord& r = records_[index];
        if (min_divisions && divisions_of(r.divisions) < min_divisions) return;
        Vec3 dv = x - r.position;
        if (!(dot(dv, dv) < aa2 * r.harmonic_distance * r.harmonic_distance)) return;
        double w = ward_weight(r, x, n);
        if (!(w > 1 / aa) || in_front(r, x, n)) return;
        // Less the threshold, so a record's weight falls to 0 at the edge of its reach: with
        // Ward's 1/d alone it enters at 1/aa, and at a coarse accuracy the edges of large
        // records drew rings on smooth walls (the corridor's ceiling under ic_radius 0.75).
        w -= 1 / aa;
        sum_w += w;
        sum += extrapolate(r, x, n) * w;
    };
    // w > 1/aa needs |x - x_i| < aa R_i and n.n_i > 1 - aa^2: most candidates fail these cheap
    // tests, first on the entries and normals_ (in float, with margins), then exactly on the
    // record. Those that pass are gathered (their records asked for) and used in their order.
    constexpr size_t kGather = 32;
    std::array<uint32_t, kGather> gathered;
    size_t pending = 0;
    for (size_t c = 0; c < found; ++c)
        cells[c]->for_each_near(xf, yf, zf, aa_f, position_slack_, [&](uint32_t index) {
            if (pending == kGather) {
                for (size_t k = 0; k < pending; ++k) use(gathered[k]);
                pending = 0;
            }
            const std::array<float, 3>& m = normals_[index];
            if (!(nxf * m[0] + nyf * m[1] + nzf * m[2] > min_cos)) return;
            const char* r = reinterpret_cast<const char*>(&records_[index]);
            for (size_t line = 0; line < sizeof(IrradianceRecord); line += 64) __builtin_prefetch(r + line);
            __builtin_prefetch(r + sizeof(IrradianceRecord) - 1);
            gathered[pending++] = index;
        });
    for (size_t k = 0; k < pending; ++k) use(gathered[k]);
    if (!(sum_w > 0)) return false;
    e = sum / sum_w;
    return is_finite(e);
}

void IrradianceCache::irradiance(const std::vector<IcQuery>& queries, uint32_t level, std::vector<Vec3>& out) {
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    const auto start = Clock::now();
    double lookups = 0;
    out.assign(queries.size(), Vec3{});
    if (level == 0) stopped_ = false;
    std::vector<uint32_t> pending(queries.size());
    std::iota(pending.begin(), pending.end(), 0u);
    // Important pixels first: their records are made at their own (finer) accuracy.
    std::stable_sort(pending.begin(), pending.end(), [&](uint32_t a, uint32_t b) { return queries[a].priority > queries[b].priority; });
    stats_.lookups += queries.size();
    bool first = true;
    for (int round = 0; !pending.empty(); ++round) {
        // Lookups in parallel (the records do not change here); misses kept in order.
        std::vector<uint8_t> found(pending.size());
        const auto lookup_start = Clock::now();
        // In parts, between which a stop is asked: records filed for a coarse accuracy make a
        // fine one's lookups scan many (vary ic_radius 0.0001 .. 1: 215k lookups took 2.7 s).
        constexpr size_t kLookupPart = size_t{1} << 15;
        for (size_t from = 0; from < pending.size(); from += kLookupPart) {
            if (from > 0 && stopping()) {
                out.clear();
                return;
            }
            tbb::parallel_for(from, std::min(pending.size(), from + kLookupPart), [&](size_t k) {
                const IcQuery& q = queries[pending[k]];
                found[k] = lookup(q.position, q.normal, q.accuracy, level, out[pending[k]], q.divisions) ? 1 : 0;
            });
        }
        lookups += since(lookup_start);
        std::vector<uint32_t> misses;
        for (size_t k = 0; k < pending.size(); ++k)
            if (!found[k]) misses.push_back(pending[k]);
        if (first) stats_.interpolated += pending.size() - misses.size();
        first = false;
        if (misses.empty()) break;
        if (stopping()) {  // before choosing sites among the misses: at fine accuracies that alone takes long
            out.clear();
            return;
        }
        if (full()) {  // no more records: the rest take the value beyond the last bounce
            for (uint32_t q : misses) out[q] = settings_.ambient * kPi;
            stats_.over_limit += misses.size();
            break;
        }
        ++stats_.rounds;
        // Sites: sparse first, four times denser each round down to the cache's resolution
        // (records no closer than aa r_min, RADIANCE's -ar); after 8 rounds every miss is a site.
        // (Dropping to "every miss" as soon as the spacing passed r_min made a coarser -ar
        // create more records: 22,910 against 11,339 at -ar 32 on the Cornell box.)
        double spacing = round < 8 ? std::max(r_max_ / std::pow(4.0, round), r_min_) : 0;
        std::vector<IcQuery> sites;
        std::unordered_map<uint64_t, std::vector<uint32_t>> taken;  // spatial hash of chosen sites
        for (uint32_t q : misses) {
            const IcQuery& query = queries[q];
            double s = spacing * level_accuracy(query.accuracy, level);
            bool near = false;
            if (s > 0) {
                int cx = static_cast<int>(std::floor(query.position.x / s)), cy = static_cast<int>(std::floor(query.position.y / s)),
                    cz = static_cast<int>(std::floor(query.position.z / s));
                for (int dx = -1; dx <= 1 && !near; ++dx)
                    for (int dy = -1; dy <= 1 && !near; ++dy)
                        for (int dz = -1; dz <= 1 && !near; ++dz) {
                            auto t = taken.find(cell_key(cx + dx, cy + dy, cz + dz));
                            if (t == taken.end()) continue;
                            for (uint32_t si : t->second)
                                if (length(sites[si].position - query.position) < s && dot(sites[si].normal, query.normal) > 0.9) {
                                    near = true;
                                    break;
                                }
                        }
                if (!near) taken[cell_key(cx, cy, cz)].push_back(static_cast<uint32_t>(sites.size()));
            }
            if (!near) sites.push_back(query);
        }
        // In pieces of about 256 Ki hemisphere rays (~40 MB of rays, hits and throughputs),
        // so memory stays bounded: a piece's records ask the next bounce for theirs while its
        // buffers are alive, so up to `bounces` pieces are held at once (at 1 Mi rays a piece,
        // prog_dis_all at 512x512 peaked at 1.18 GB).
        // A piece's sites share their hemisphere rays (`vary ic_rays`): the quietest first, each
        // group in site order (a render of one setting keeps its order).
        std::stable_sort(sites.begin(), sites.end(),
                         [&](const IcQuery& a, const IcQuery& b) { return divisions_of(a.divisions) > divisions_of(b.divisions); });
        for (size_t begin = 0; begin < sites.size();) {
            const uint32_t divisions = divisions_of(sites[begin].divisions);
            const size_t per_piece = std::max<size_t>(1, (size_t{1} << 18) / std::max(16u, divisions >> std::min(level, 16u)));
            const size_t limit = std::min(sites.size(), begin + per_piece);
            size_t end = begin + 1;
            while (end < limit && divisions_of(sites[end].divisions) == divisions) ++end;
            if (full()) break;  // the next round gives the queries still missing the ambient value
            if (stopping()) {
                out.clear();
                return;
            }
            std::vector<IcQuery> piece(sites.begin() + static_cast<std::ptrdiff_t>(begin), sites.begin() + static_cast<std::ptrdiff_t>(end));
            std::vector<IrradianceRecord> made = compute(piece, level);
            if (stopped_) {  // a deeper level was stopped: these records lack its light
                out.clear();
                return;
            }
            for (const auto& r : made) insert(r);
            stats_.records += made.size();  // counted when kept (a stopped piece's are not)
            if (progress_) progress_(stats_);
            begin = end;
        }
        pending = std::move(misses);
        if (round > 40) {  // cannot happen (a record covers its own site); never loop forever
            for (uint32_t q : pending) out[q] = settings_.ambient * kPi;
            break;
        }
    }
    const double before_caustics = since(start);
    if (caustics_ && level == 0)
        tbb::parallel_for(size_t{0}, queries.size(), [&](size_t q) { out[q] += caustics_->irradiance(queries[q].position, queries[q].normal); });
    if (level == 0) {
        stats_.lookup_seconds += lookups;
        stats_.record_seconds += before_caustics - lookups;
        stats_.caustic_lookup_seconds += since(start) - before_caustics;
    }
}

size_t IrradianceCache::bytes() const {
    size_t total = records_.size() * sizeof(IrradianceRecord) + normals_.size() * sizeof(normals_[0]);
    for (const auto& level : grids_)
        for (const CellTable& table : level) total += table.bytes();
    return total;
}

bool IrradianceCache::stopping() {
    if (!stopped_ && stop_ && stop_()) stopped_ = true;
    return stopped_;
}

bool IrradianceCache::full() const { return settings_.max_bytes > 0 && bytes() >= settings_.max_bytes; }

IcFileSettings IrradianceCache::file_settings() const {
    return {settings_.divisions, settings_.bounces, caustics_ ? settings_.caustic_photons : 0u, r_min_, r_max_, scene_.embree->extent()};
}

std::string IrradianceCache::save(const std::string& path) const { return write_file_atomically(path, to_bytes()); }

std::string IrradianceCache::to_bytes() const { return encode_irradiance_cache(file_settings(), records_); }

std::string IrradianceCache::load(const std::string& path) {
    std::string error;
    auto data = read_input_file(path, error, kMaxDataInputBytes);  // a regular file, bounded
    return data ? load_bytes(*data, path) : error;
}

std::string IrradianceCache::load_bytes(const std::string& data, const std::string& path) {
    std::vector<IrradianceRecord> loaded;
    const double max_irradiance = brightest_irradiance(scene_.scene, settings_.ambient);
    if (std::string error = decode_irradiance_cache(data, path, file_settings(), max_irradiance, loaded); !error.empty()) return error;
    insert(loaded);  // all or nothing: a broken file loads no record
    return "";
}

std::function<void(const RayBatch&, size_t, size_t, std::vector<Vec3>&)> executor_hook(IcAnswerFn answer, const IcPixelSettings& pixels,
                                                                                      IcAnswerLog* log) {
    return [answer = std::move(answer), pixels, log](const RayBatch& rays, size_t begin, size_t end, std::vector<Vec3>& e) {
        std::vector<IcQuery> q(end - begin);
        for (size_t i = begin; i < end; ++i) {
            uint32_t p = rays.pixel[i];
            IcQuery& x = q[i - begin];
            x.position = {rays.ox[i], rays.oy[i], rays.oz[i]};
            x.normal = normalize_or_zero(Vec3{rays.dx[i], rays.dy[i], rays.dz[i]});
            x.accuracy = pixels.accuracy ? (*pixels.accuracy)[p] : static_cast<float>(pixels.aa);
            x.priority = pixels.priority ? (*pixels.priority)[p] : 0.0f;
            x.key = rays.path[i];
            x.divisions = pixels.divisions ? (*pixels.divisions)[p] : uint16_t{0};
        }
        answer(q, e);
        if (e.size() != q.size()) return;  // the cache was stopped (set_stop): nothing answered
        if (log)
            for (size_t i = begin; i < end; ++i) {
                const Vec3& irradiance = e[i - begin];
                log->push_back({rays.path[i], {rays.ox[i], rays.oy[i], rays.oz[i]}, {rays.dx[i], rays.dy[i], rays.dz[i]},
                                {rays.br[i], rays.bg[i], rays.bb[i]},
                                {static_cast<float>(irradiance.x), static_cast<float>(irradiance.y), static_cast<float>(irradiance.z)},
                                rays.pixel[i], q[i - begin].accuracy, rays.flags[i]});
            }
    };
}

}  // namespace crex
