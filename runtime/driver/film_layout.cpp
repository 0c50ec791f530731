#include "runtime/driver/film_layout.h"

#include "runtime/driver/guidance_phase.h"
#include "runtime/driver/run_settings.h"

namespace crex {

FilmLayout film_layout(const PipelinePlan& plan, const RunSettings& s) {
    const FilmLayout every;
    if (s.component_images) return every;  // the caller reads the film: all of it
    FilmLayout layout = FilmLayout::minimal();
    // Automatic stand-ins weigh each component's unexecuted rays by what its executed ones found.
    if (s.ambient_auto) layout.aovs = every.aovs;
    if (s.irradiance_cache) layout.aovs |= 1u << aov_of(Component::kD);
    if (plan.staged)
        for (const std::string& buffer : guidance_reads(plan)) {
            if (buffer == "noise") layout.noise = true;
            if (buffer == "emission") layout.emission = true;
            if (buffer == "direct") layout.emission = true, layout.aovs = every.aovs;  // the camera's own light
            for (size_t c = 0; c < kComponentCount; ++c)
                if (buffer.size() == 1 && buffer[0] == kComponentTable[c].letter) layout.aovs |= 1u << aov_of(static_cast<Component>(c));
        }
    return layout;
}

}  // namespace crex
