/// \file camera_samples.h
/// Camera samples: where sample k of pixel p lies (Halton per pixel, optionally through the
/// Gaussian pixel filter), its ray and its path id, and the ambient buffer that stands in for
/// rays left waiting in D. Every random number of a path is keyed by the path id, so a sample
/// traces the same path whichever pass, band or thread it is traced in.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/render/ray_batch.h"
#include "runtime/render/render_scene.h"

namespace crex {

/// How a pixel weighs the light around it. kBox: samples uniform over the pixel. kGaussian:
/// a Gaussian of standard deviation 0.5 pixel truncated at 1.5, by filter importance sampling
/// (pbrt-v4): sample offsets follow the filter, every sample weighs 1, so the progressive
/// Halton sequence and per-pixel sample counts work unchanged.
enum class PixelFilter { kBox, kGaussian };

/// The seeds of a camera sample: `path` keys every random number along its path, `position`
/// where in its pixel it lies. They differ only in a walk whose frames inherit light
/// (RunSettings::position_seed): a pixel that inherits nothing keeps its positions from frame
/// to frame while its light is drawn afresh.
struct CameraSeeds {
    uint64_t path = 0, position = 0;
    CameraSeeds(uint64_t seed) : path(seed), position(seed) {}  // NOLINT: one seed for both
    CameraSeeds(uint64_t path_seed, uint64_t position_seed) : path(path_seed), position(position_seed) {}
};

/// The camera ray of sample `sample` of `pixel`.
RayRecord camera_ray(const CameraRays& camera, CameraSeeds seeds, int width, uint32_t pixel, uint32_t sample,
                     PixelFilter filter = PixelFilter::kBox);
/// Appends the camera rays of samples [first, first + count) of `pixel`.
void append_camera_rays(const CameraRays& camera, CameraSeeds seeds, int width, uint32_t pixel, uint32_t first, uint32_t count,
                        RayBatch& rays, PixelFilter filter = PixelFilter::kBox);
/// Adds to `ambient` (per pixel RGB, sample-summed) av times the throughput of every ray
/// waiting in bin D: what stands in for D work that was never executed (spec §3).
void add_ambient(const RayBatch& d, const Vec3& av, std::vector<double>& ambient);

/// Path id of camera sample k of pixel p (shared with the oracle): the pixel's key (40 bits,
/// from the seed and the pixel) above the sample index (24 bits), so that shading a camera
/// hit can tell both (camera_pixel_key, camera_sample_index); everything drawn from a path id
/// hashes it first.
uint64_t camera_path_id(uint64_t seed, uint32_t pixel, uint32_t sample);
inline uint64_t camera_pixel_key(uint64_t camera_path) { return camera_path >> 24; }
inline uint32_t camera_sample_index(uint64_t camera_path) { return static_cast<uint32_t>(camera_path & 0xffffffu); }
/// Position within pixel of camera sample k: Halton (2, 3) rotated per pixel; with the
/// Gaussian filter the same points mapped through the filter's inverse distribution (so u, v
/// then lie in [-1, 2)).
void camera_sample_offset(uint64_t seed, uint32_t pixel, uint32_t sample, double& u, double& v,
                          PixelFilter filter = PixelFilter::kBox);
/// The truncated Gaussian's inverse distribution: [0, 1) -> [-1.5, 1.5) pixels from the centre.
double gaussian_filter_offset(double u);

}  // namespace crex
