/// \file film_layout.h
/// Which per-pixel buffers a render's film makes: only those something reads (issue 40).
#pragma once

#include "compiler/plan/pipeline_plan.h"
#include "runtime/render/film.h"

namespace crex {

struct RunSettings;

/// Every buffer when the caller wants the component images (RunSettings::component_images:
/// it reads the film). Else a component's own sum where the render reads it (guidance's
/// buffers, automatic ambient stand-ins, the cache's estimate of the light it cuts), emission
/// and the noise half-buffer where guidance reads them; nothing else.
FilmLayout film_layout(const PipelinePlan& plan, const RunSettings& settings);

}  // namespace crex
