/// \file irradiance_cache.h
/// A Ward irradiance cache for the D component (thesis 4.6, 6, 8.2), computed in batches:
/// the queries of a D step are looked up; the misses choose new record sites greedily (in
/// priority order, sparse first, denser each round), whose hemisphere rays are traced as one
/// batch through Embree and shaded in parallel; the records are inserted in site order and the
/// misses looked up again. Everything that decides a result happens in a fixed order, so
/// images do not depend on the thread count.
///
/// Each record holds E, the harmonic mean distance R (clamped to [r_min, r_max], never 0, and
/// gradient-limited),
/// rotation and translation gradients (Ward and Heckbert 1992), its bounce level and the
/// accuracy it was made for. A query at accuracy aa uses records of its level made for
/// aa' <= aa (never records of lower quality) whose Ward weight w exceeds 1/aa and that are not
/// in front of it, weighted by w - 1/aa (0 at the edge of a record's reach: no rings). Bounces: a level-k hemisphere ray sees emission (not `light` emitters: they
/// are direct light), one direct-light sample, and rho/pi E_{k+1} from level k+1 records
/// (made as needed) up to `bounces`; beyond, the ambient value av. Later levels use fewer
/// hemisphere rays (ad / 2^k, at least 16), as pbrt's irradiance cache does. Hemisphere rays
/// that reach a mirror, glass or a dielectric continue through it (one lobe by weight, up to
/// 8 interfaces), so light reflected or refracted by them reaches E; plastic's and metal's
/// ideal specular is not followed. A trans surface is seen through both its transmissions:
/// through its specular one by that lobe's share, and its diffuse one from a record of the
/// next bounce on its other side. Caustics proper - a `light` emitter seen through them - come
/// from a caustic photon map instead (caustic_photons.h): at the query point for the camera's
/// queries (sharp), at the record's site for deeper bounces.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "runtime/cache/caustic_photons.h"
#include "runtime/cache/irradiance_cache_file.h"
#include "runtime/cache/irradiance_record.h"
#include "runtime/cache/record_grid.h"
#include "runtime/render/hot_surfaces.h"
#include "runtime/render/ray_batch.h"
#include "runtime/render/render_scene.h"

namespace crex {

struct IcSettings {
    double accuracy = 0.15;     ///< aa: default accuracy (smaller is finer)
    double max_accuracy = 0;    ///< the coarsest aa any query will use (0: `accuracy`); sizes the index
    uint32_t divisions = 256;   ///< ad: hemisphere rays of a level-0 record
    uint32_t bounces = 8;       ///< ab; bounce k uses accuracy aa 2^k (capped at 1)
    double min_radius = 0;      ///< clamp of R (scene units); 0: the scene's extent / `resolution`
    /// RADIANCE's -ar: records are never closer than the scene's extent / ar, which caps their
    /// density in corners and at deeper bounces (0: extent / 2000, nearly no cap).
    double resolution = 128;
    double max_radius = 0;      ///< clamp of R; 0: 0.25 x the scene's extent
    Vec3 ambient{0, 0, 0};      ///< av, radiance beyond the last bounce
    uint64_t seed = 0;
    /// Photons aimed at the delta shapes for the caustic map (0: caustics from the hemisphere
    /// rays, a few of which happen to reach an emitter's image: noisy).
    uint32_t caustic_photons = 200000;
    /// Records sample the surfaces small lamps light from up close as lights (hot_surfaces.h);
    /// false: only their hemisphere rays find them.
    bool hot_surfaces = true;
    /// The records and their lookup grids stop growing at this many bytes (0: no limit); the
    /// queries that would make more take the ambient value, counted in IcStats::over_limit.
    /// A fine cache on a deep enough scene grows without end: --aa 0.001 --ar 1e6 on the
    /// Cornell box at 8x8 held 4.2 GB after 150 s, every hemisphere ray a record of its own.
    size_t max_bytes = 0;
};

struct IcQuery {
    Vec3 position, normal;  ///< local coordinates; unit normal on the side light arrives from
    float accuracy = 0.15f; ///< aa of this query's pixel
    float priority = 0;     ///< larger first (pixel importance)
    uint64_t key = 0;       ///< random-number key of the records it may create
    /// Hemisphere rays (ad) of the records it makes and accepts (`vary ic_rays`); 0: the
    /// cache's own, and any record is accepted.
    uint16_t divisions = 0;
};

struct IcStats {
    uint64_t lookups = 0, interpolated = 0, records = 0, hemisphere_rays = 0, rounds = 0;
    uint64_t caustic_photons = 0;  ///< stored in the caustic map
    uint64_t over_limit = 0;       ///< queries given the ambient value: the cache was full (IcSettings::max_bytes)
    uint64_t hot_triangles = 0;    ///< triangles of the hot surfaces records sample as lights (hot_surfaces.h)
    uint64_t hot_points = 0;       ///< points the records took on them
    double caustic_seconds = 0;    ///< building it
    /// Per bounce level: the luminance of the diffuse reflectance (times throughput) the
    /// hemisphere rays of its records met, summed, and those rays: the share of a record's
    /// light that comes from the next level, on average.
    std::vector<double> albedo_sum;
    std::vector<uint64_t> albedo_rays;
    /// The share of a camera query's light that would come from bounces past the last level
    /// (the product of the levels' mean albedos), which --ambient stands in for; 0 if unmeasured.
    double throughput_past_last_bounce() const;
    /// Where the first-bounce (level-0) queries' time goes (issue 32, what guidance can steer):
    /// interpolating from records, making the missing records (their hemisphere rays and every
    /// deeper bounce), adding the caustic map's estimate.
    double lookup_seconds = 0, record_seconds = 0, caustic_lookup_seconds = 0;
};

/// A cache's records and lookup grids, handed from one render to the next that starts from
/// them (a walk's frames): copying 100k carried records into fresh memory (page faults) and
/// filing them again were 2 to 5 % of a later frame. The grids are valid only for those
/// records in that order, under the same accuracy and cell sizes (IrradianceCache::insert
/// checks the last two and files the records again if they differ).
struct IcGrids;

class IrradianceCache {
public:
    /// `caustics`: a map built already for this scene, `settings.caustic_photons` and seed (a
    /// sequence's frames share one); null: the cache builds its own when the settings ask.
    IrradianceCache(const RenderScene& scene, const IcSettings& settings, std::shared_ptr<const CausticPhotons> caustics = nullptr);
    ~IrradianceCache();

    /// E at every query of `level`, creating the records that are missing. When set_stop()'s
    /// test says stop (asked at every level before each piece of records, each round's choice of
    /// sites and between parts of lookups), `out` comes back empty and the records of the pieces
    /// under way are dropped; those finished stay.
    void irradiance(const std::vector<IcQuery>& queries, uint32_t level, std::vector<Vec3>& out);
    /// Interpolation only: false if no record is valid at (x, n) for accuracy aa. With
    /// `divisions` (a pixel's `ic_rays`), records made with fewer hemisphere rays are not valid.
    bool lookup(const Vec3& x, const Vec3& n, double aa, uint32_t level, Vec3& e, uint16_t divisions = 0) const;

    void insert(const IrradianceRecord& r);
    /// Many at once (a frame's carried records, a file's): room for them made first. With
    /// `handed`, its records come first, moved in, and (same settings, this cache still empty)
    /// its grids are taken over instead of filing them: the cells list the same entries in the
    /// same order as filing them all. `handed` is left with its count only.
    void insert(const std::vector<IrradianceRecord>& records, IcGrids* handed = nullptr);
    /// Called after each piece of records is made (from the thread that asked for them): a
    /// fine accuracy makes records for minutes inside one D step, which a progress line must show.
    void set_progress(std::function<void(const IcStats&)> progress) { progress_ = std::move(progress); }
    /// Asked between the steps of making records (from the thread that asked for them; see
    /// irradiance()): true stops the batch under way. A time budget's: one query's records can take far longer than the
    /// budget (--ad 16384 --ab 64 took 14.5 s for 17 queries of a 2 s budget).
    void set_stop(std::function<bool()> stop) { stop_ = std::move(stop); }
    const std::vector<IrradianceRecord>& records() const { return records_; }
    /// The records, moved out (a render's result): the cache is empty after. `grids`, when
    /// given, takes the lookup grids over them (IcGrids::records empty: the caller puts the
    /// returned records there to hand both to IrradianceCache::insert of a next render).
    std::vector<IrradianceRecord> take_records(std::shared_ptr<IcGrids>* grids = nullptr);
    const IcSettings& settings() const { return settings_; }
    const IcStats& stats() const { return stats_; }
    /// What the records and their lookup grids hold, in bytes (what IcSettings::max_bytes limits).
    size_t bytes() const;
    double min_radius() const { return r_min_; }
    double max_radius() const { return r_max_; }
    /// The caustic map it adds to D (null: none).
    const std::shared_ptr<const CausticPhotons>& caustic_map() const { return caustics_; }

    /// Persistence (reuse across frames and runs), in the format of irradiance_cache_file.h:
    /// load() refuses a file made with other settings or another scene extent, and damaged
    /// bytes, without loading any record.
    std::string save(const std::string& path) const;
    /// What save() writes, as bytes (distributed runs: sent to the process that writes it).
    std::string to_bytes() const;
    std::string load(const std::string& path);
    /// load() of a file's bytes already read; `name` is the file the messages name.
    std::string load_bytes(const std::string& data, const std::string& name);

    /// The settings a file of this cache's records carries and must match to be read.
    IcFileSettings file_settings() const;

private:
    /// Makes the records of `sites` at `level` (record_hemispheres.cpp), in four phases over
    /// the whole batch; the third asks irradiance() for the next level.
    std::vector<IrradianceRecord> compute(const std::vector<IcQuery>& sites, uint32_t level);
    struct Hemispheres;
    Hemispheres cast_hemispheres(const std::vector<IcQuery>& sites, uint32_t level);
    void pass_specular_interfaces(Hemispheres& h, const std::vector<IcQuery>& sites, uint32_t level);
    void shade_hemispheres(Hemispheres& h, const std::vector<IcQuery>& sites, uint32_t level);
    void add_next_bounce(Hemispheres& h, uint32_t level);
    void add_hot_surfaces(Hemispheres& h, const std::vector<IcQuery>& sites, uint32_t level);
    std::vector<IrradianceRecord> records_from(const Hemispheres& h, const std::vector<IcQuery>& sites, uint32_t level) const;
    uint64_t cell_key(int x, int y, int z) const;
    /// At IcSettings::max_bytes: no more records are made.
    bool full() const;
    /// Whether set_stop()'s test has said stop during this batch (asked now if not yet).
    bool stopping();
    /// The grids of bounce `level`, made when missing.
    void make_grids(uint32_t level);
    /// Record `index` into the cells of its level's grids that its largest validity radius reaches.
    void file(uint32_t index);
    double level_accuracy(double aa, uint32_t level) const;
    /// The level-0 hemisphere rays a query's or record's `divisions` stands for.
    uint32_t divisions_of(uint16_t divisions) const { return divisions ? divisions : settings_.divisions; }

    /// Grid levels at most: halving from 2 r_max, 24 levels span radii over a factor 2^23
    /// (smaller records sit in the finest); lookup() sizes its per-level arrays by it.
    static constexpr size_t kMaxGridLevels = 24;

    const RenderScene& scene_;
    IcSettings settings_;
    /// The scene's hot surfaces (hot_surfaces.h), sampled as lights of their own by every
    /// record; null when there are none or the settings turn them off.
    const HotSurfaces* hot_ = nullptr;
    double r_min_, r_max_, max_aa_;
    float position_slack_;  ///< bounds the float rounding of GridEntry positions (local coordinates)
    std::vector<IrradianceRecord> records_;
    /// Each record's normal in floats, by index: a lookup asks it before the record itself.
    /// On the textured living room (sel_quiet, 192x192) 12.8 records a lookup were within
    /// reach and only 2.7 of them passed Ward's weight, the rest facing another way (a chair's
    /// legs, leaves, a wall at a corner), each a 232-byte record fetched and weighed; these 12
    /// bytes a record stay in the caches. (In the grid's entries they cost a fifth more memory
    /// at the peak: most cells hold a block of eight lanes for one or two entries.)
    std::vector<std::array<float, 3>> normals_;
    /// Appends the normals of the records normals_ does not have yet.
    void sync_normals();
    // A hierarchy of uniform grids: level L has cells of 2 rho_max / 2^L; a record sits in the
    // level whose cells are at least twice its largest validity radius (<= 8 cells of it).
    std::vector<double> cell_size_;
    // One hierarchy per bounce level: a lookup never scans another bounce's records.
    std::vector<std::vector<CellTable>> grids_;
    IcStats stats_;
    std::shared_ptr<const CausticPhotons> caustics_;  ///< null when off or the scene has no caustics
    std::function<void(const IcStats&)> progress_;
    std::function<bool()> stop_;
    bool stopped_ = false;  ///< the batch under way was stopped (set_stop)
};

struct IcGrids {
    std::vector<IrradianceRecord> records;  ///< the records handed on (moved out by insert)
    size_t handed = 0;                      ///< how many they were (kept after insert)
    size_t filed = 0;                       ///< the grids file the first `filed` of them
    double max_aa = 0;
    std::vector<double> cell_size;
    std::vector<std::vector<CellTable>> grids;
};

/// A D query as it was answered (for the progressive cache: the same samples are answered
/// again at a finer accuracy in the selective stage).
struct IcAnswer {
    // The query's ray as the ray batch holds it, and its answer, in floats (72 bytes an answer
    // where a RayRecord of doubles made it 120; a preview at 960x540 logs three million of them).
    uint64_t path = 0;
    std::array<float, 3> origin, direction, beta, irradiance;
    uint32_t pixel = 0;
    float accuracy = 0;
    uint8_t flags = 0;
};

/// The preview's answers, in blocks: a vector's growth held its old and new arrays at once,
/// three times the log (738 MB of a 1.27 GB peak at 960x540), and the log shrinks from its
/// tail once guidance has said which answers are asked again.
using IcAnswerLog = std::deque<IcAnswer>;

/// E at a batch of queries (bounce level 0): IrradianceCache::irradiance, or another process
/// answering them (distributed rendering, --ic-share component).
using IcAnswerFn = std::function<void(const std::vector<IcQuery>& queries, std::vector<Vec3>& irradiance)>;

/// What each pixel's D queries ask of the cache (null: the same for every pixel).
struct IcPixelSettings {
    double aa = 0.15;                                 ///< accuracy where `accuracy` is null
    const std::vector<float>* accuracy = nullptr;     ///< `vary ic_radius`
    const std::vector<float>* priority = nullptr;     ///< higher first (pixel importance)
    const std::vector<uint16_t>* divisions = nullptr; ///< `vary ic_rays`; else the cache's ad
};

/// The executor's D hook with the queries answered by `answer`, each as its pixel asks; answers
/// are appended to `log` when given.
std::function<void(const RayBatch&, size_t, size_t, std::vector<Vec3>&)> executor_hook(IcAnswerFn answer, const IcPixelSettings& pixels,
                                                                                      IcAnswerLog* log = nullptr);

}  // namespace crex
