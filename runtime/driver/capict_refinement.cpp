#include "runtime/driver/capict_refinement.h"

namespace crex {

std::optional<Refinement> next_refinement(const PipelinePlan& plan, ComponentSubsampling& subsampling, const Film& film,
                                          uint32_t preview_spp) {
    const size_t pixels = film.pixel_count();
    Refinement r;
    r.runs.assign(pixels, 0);
    for (const PlanVariable& v : plan.variables) {
        if (v.variable != pipeline::SelectiveVariable::kSubsample || !v.component || !v.refine) continue;
        std::vector<uint8_t> added = subsampling.refine(*v.component, *v.refine, film);
        if (added.empty()) continue;
        const unsigned bit = 1u << static_cast<unsigned>(*v.component);
        r.replay = static_cast<uint8_t>(r.replay | bit);
        for (size_t p = 0; p < pixels; ++p)
            if (added[p]) r.runs[p] = static_cast<uint8_t>(r.runs[p] | bit);
    }
    if (!r.replay) return std::nullopt;
    r.ranges.start_of.assign(pixels, 0);
    r.ranges.end_of.assign(pixels, 0);
    for (size_t p = 0; p < pixels; ++p)
        if (r.runs[p]) r.ranges.start_of[p] = preview_spp, r.ranges.end_of[p] = film.samples(static_cast<uint32_t>(p));
    return r;
}

}  // namespace crex
