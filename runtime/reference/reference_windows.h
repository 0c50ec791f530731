/// \file reference_windows.h
/// Which windows of a frame a windowed reference covers (issue 32), by a rule stated once and
/// applied alike to every scene, so that nobody picks the windows where a pipeline looks good.
/// Windows are squares of one size, chosen in this order, each where the rule puts it among
/// the places that overlap no window chosen before (candidates on a grid of a quarter of the
/// size, inside the frame):
///  1. task:       where the window sees the most pixels of tagged task objects (tag task
///                 > 0), the objects the viewer works on;
///  2. distractor: likewise for a tagged on-screen distractor;
///  3. lamp:       nearest the point of a visible emitter's outline closest to that emitter's
///                 centroid (the emitter covering most pixels; seen directly, else in a
///                 mirror), so the window holds the lamp's edge and what it lights;
///  4. caustic:    where the caustic photon map's irradiance on the surfaces the camera sees,
///                 averaged over the window, is largest (light focused by mirrors and glass);
///  5. salient:    where the whole frame's saliency, averaged over the window, is largest,
///                 among windows that show no emitter (the lamp has its own) and no black
///                 pixel (black against black says nothing of a render);
///  6. plain:      where it is smallest, likewise (a region the eye passes over).
/// A kind the scene lacks (no tags, no emitter in view, no caustic) is left out and said so.
#pragma once

#include <string>
#include <vector>

#include "runtime/driver/sample_passes.h"
#include "runtime/reference/reference_render.h"
#include "runtime/scene/scene.h"

namespace crex {

struct ChosenWindow {
    std::string kind;     ///< task, distractor, lamp, caustic, salient, plain
    PixelWindow window;   ///< width 0 when the scene has none of this kind
    std::string why;      ///< where the rule put it, or why there is none
};

/// The rule above for a frame of context.width x context.height, windows of size x size pixels.
std::vector<ChosenWindow> choose_reference_windows(const Scene& scene, const FrameContext& context, int size, uint64_t seed);

}  // namespace crex
