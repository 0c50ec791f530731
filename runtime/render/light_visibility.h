/// \file light_visibility.h
/// How much of each distant source (the sun, a sky) the surfaces the camera sees can see. A sky
/// outweighs every lamp of a room by its solid angle, so direct lighting chose it for nearly
/// every shadow ray even where walls and an illum window block it all (RADIANCE's glass test
/// set: the window's light in scattered specks). Measured once per view, the fraction scales
/// the source's share of shadow rays; every source keeps a share, so the estimate stays unbiased.
#pragma once

#include <vector>

namespace crex {

struct RenderScene;

/// Per distant source (LightSampler's order): the fraction of shadow rays towards it, from the
/// first surfaces seen on a grid of camera rays across a width x height image, that reach it
/// (thin glass counted by what it lets through), with one success and one failure added (a
/// source no test reached keeps a small share; one that was never tested keeps 1/2).
std::vector<double> distant_visibility(const RenderScene& scene, int width, int height);

}  // namespace crex
