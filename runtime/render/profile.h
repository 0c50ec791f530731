/// \file profile.h
/// The profiler of time-constrained rendering (thesis 5.4, spec/crex.md §3): measured cost per
/// ray of each component (and of camera rays), kept as an average weighted by rays that decays
/// with a half-life of kHalfLifeRays rays, so it follows changes during a render (e.g. while a
/// cache fills) without letting the last small step of a loop (a few rays, mostly overhead)
/// decide it: halving per measurement made a saved profile 2-8x too dear. A profile can be saved and
/// loaded (a profile cache reused across frames of an animation and across runs).
#pragma once

#include <array>
#include <cstdint>
#include <cmath>
#include <optional>
#include <string>

#include "base/components.h"

namespace crex {

/// What a pipeline's fixed stages cost in the render a profile was saved from (issue 34): a
/// budget schedules them too, so the preview is sized and a budget below the pipeline's floor
/// refused from these. Zeros: unknown (a plain crex, or an older profile).
struct StageCosts {
    double preview_seconds = 0;    ///< the pre-selective stage
    uint64_t preview_samples = 0;  ///< its camera samples
    double guidance_seconds = 0;   ///< every round's maps
    uint64_t pixels = 0;           ///< of the frame guidance ran on
    // With an irradiance cache (else 0): what a sparse preview pays that a full one spreads
    // over all its samples. The cache's caustic map is built on the clock, once; and a sample
    // far from the others makes a record of its own.
    double preview_fixed_seconds = 0;   ///< the cache's caustic map
    uint64_t preview_records = 0;       ///< cache records the preview made
    double preview_record_seconds = 0;  ///< making them (their hemispheres and deeper bounces)
    /// The render's end, after its last stage (the stand-ins of rays left unexecuted, the
    /// warnings): on the clock, so a budget keeps it back (0 in a profile saved before it).
    double end_seconds = 0;
    /// A preview at every 8th pixel's work per pixel of the frame rather than per sample (grid,
    /// sample ranges, composite, fill), timed in the full render (0: not timed).
    double strided_preview_seconds = 0;
    bool known() const { return preview_samples > 0 && pixels > 0; }
};

class Profile {
public:
    /// Seconds per ray of component c, if measured or loaded.
    std::optional<double> cost(Component c) const { return cost_[static_cast<size_t>(c)].cost; }
    std::optional<double> camera_cost() const { return camera_.cost; }
    static constexpr double kHalfLifeRays = 65536;

    /// Folds in a measurement of `rays` rays taking `seconds`.
    void record(Component c, uint64_t rays, double seconds) { fold(cost_[static_cast<size_t>(c)], rays, seconds); }
    void record_camera(uint64_t rays, double seconds) { fold(camera_, rays, seconds); }

    /// JSON text of the profile; from_json_text reads it back. Returns "" on success, else why
    /// not, located ("p.json:3:26: ...") in a file named `name`. A saved profile may also hold
    /// the time of the full render it came from (budgets in %): into `full_render_seconds`
    /// (0 when it holds none); and a pipeline's stage costs ("stages"): into `stages`.
    std::string to_json_text() const;
    static std::string from_json_text(const std::string& text, Profile& out, double* full_render_seconds = nullptr,
                                      const std::string& name = "<profile>", StageCosts* stages = nullptr);
    /// The largest full_render_seconds a profile may hold (11.6 days, the longest budget).
    static constexpr double kMaxFullRenderSeconds = 1e6;
    /// Seconds per ray above this are no measurement (a ray of crex takes microseconds).
    static constexpr double kMaxSecondsPerRay = 1e3;

private:
    struct Slot {
        std::optional<double> cost;
        double rays = 0;  ///< weight of `cost`: rays measured, decayed
    };
    static void fold(Slot& slot, uint64_t rays, double seconds) {
        if (rays == 0 || !(seconds >= 0)) return;
        const double n = static_cast<double>(rays);
        const double kept = slot.cost ? slot.rays * std::exp2(-n / kHalfLifeRays) : 0.0;
        slot.cost = ((slot.cost ? *slot.cost * kept : 0.0) + seconds) / (kept + n);
        slot.rays = kept + n;
    }
    // A loaded cost weighs as one half-life of rays: a render's own measurements soon lead.
    static void load(Slot& slot, double cost) { slot = {cost, kHalfLifeRays}; }
    std::array<Slot, kComponentCount> cost_{};
    Slot camera_;
};

/// What this render's latest rays of each component cost, with a half-life of a few batches.
/// Under a budget the Profile's figure lags: it weighs a loaded cost as 65,536 rays, and a
/// saved profile's cost of D is its full render's, where the cache's records were spread over
/// every ray. A budgeted render's later D rays make the fine records its important pixels ask
/// for: on the room (prog_tc, 384x288, 0.5 s) they cost 16-52 us a ray against the profile's
/// 5 us, and the last batch admitted on the profile's figure ran 34 ms for 5.5 predicted.
class RecentCosts {
public:
    static constexpr double kHalfLifeRays = 1024;
    static constexpr double kMinRays = 64;  ///< fewer measured: their overhead, not a cost per ray

    void record(Component c, uint64_t rays, double seconds) {
        if (rays == 0 || !(seconds >= 0)) return;
        Slot& s = slots_[static_cast<size_t>(c)];
        const double n = static_cast<double>(rays), kept = std::exp2(-n / kHalfLifeRays);
        s.rays = s.rays * kept + n;
        s.seconds = s.seconds * kept + seconds;
    }
    std::optional<double> cost(Component c) const {
        const Slot& s = slots_[static_cast<size_t>(c)];
        if (s.rays < kMinRays) return std::nullopt;
        return s.seconds / s.rays;
    }

private:
    struct Slot {
        double rays = 0, seconds = 0;  // decayed alike
    };
    std::array<Slot, kComponentCount> slots_{};
};

}  // namespace crex
