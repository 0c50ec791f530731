/// \file render.h
/// render(): a scene and a lowered crex to an image. Camera rays first (all samples, Halton
/// per pixel), then the pre-selective program, then the selective one, with bins carried over;
/// rays left in bins at the end are dropped, and the ambient value stands in for those in D.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "compiler/sched/program.h"
#include "runtime/cache/irradiance_cache.h"
#include "runtime/render/executor.h"
#include "runtime/render/film.h"
#include "runtime/render/render_scene.h"
#include "runtime/report/checkpoints.h"
#include "runtime/scene/scene.h"

namespace crex {

/// How a pixel weighs the light around it. kBox: samples uniform over the pixel. kGaussian:
/// a Gaussian of standard deviation 0.5 pixel truncated at 1.5, by filter importance sampling
/// (pbrt-v4): sample offsets follow the filter, every sample weighs 1, so the progressive
/// Halton sequence and per-pixel sample counts work unchanged.
enum class PixelFilter { kBox, kGaussian };

struct RenderOptions {
    int width = 128;
    int height = 128;
    uint32_t spp = 1;
    uint32_t first_sample = 0;  ///< render samples [first_sample, first_sample + spp)
    uint64_t seed = 0;
    PixelFilter filter = PixelFilter::kBox;
    Vec3 ambient{0, 0, 0};      ///< `av`: radiance standing in for unexecuted D work
    ExecutorOptions executor;
    CheckpointRecorder* recorder = nullptr;  ///< reports: image snapshots during the render
    std::optional<IcSettings> irradiance_cache;  ///< D through a Ward irradiance cache
    std::vector<IrradianceRecord> ic_records;    ///< records to start from (a saved cache)
};

struct RenderResult {
    RenderResult(int width, int height) : film(width, height) {}
    Film film;
    std::vector<double> ambient;   ///< the ambient buffer at the end (per pixel RGB, sample-summed)
    ExecutorStats stats;
    std::vector<std::string> warnings;
    double setup_seconds = 0;      ///< scene load into Embree and BVH build
    double render_seconds = 0;     ///< from the first camera ray
    std::array<size_t, kComponentCount> rays_left{};  ///< dropped at the end, per bin
    std::vector<IrradianceRecord> ic_records;  ///< the cache at the end (with an irradiance cache)
    IcStats ic_stats;

    std::vector<float> image() const { return film.composite(&ambient); }
};

RenderResult render(const Scene& scene, const sched::Program& program, const RenderOptions& options);

/// The camera ray of sample `sample` of `pixel`.
RayRecord camera_ray(const CameraRays& camera, uint64_t seed, int width, uint32_t pixel, uint32_t sample,
                     PixelFilter filter = PixelFilter::kBox);
/// Appends the camera rays of samples [first, first + count) of `pixel`.
void append_camera_rays(const CameraRays& camera, uint64_t seed, int width, uint32_t pixel, uint32_t first, uint32_t count,
                        RayBatch& rays, PixelFilter filter = PixelFilter::kBox);
/// The ambient buffer: av times the throughput of every ray waiting in bin D (spec §3),
/// per pixel RGB, sample-summed.
std::vector<double> ambient_buffer(const RayBatch& d, const Vec3& av, size_t pixels);

/// Path id of camera sample k of pixel p (shared with the oracle).
uint64_t camera_path_id(uint64_t seed, uint32_t pixel, uint32_t sample);
/// Position within pixel of camera sample k: Halton (2, 3) rotated per pixel; with the
/// Gaussian filter the same points mapped through the filter's inverse distribution (so u, v
/// then lie in [-1, 2)).
void camera_sample_offset(uint64_t seed, uint32_t pixel, uint32_t sample, double& u, double& v,
                          PixelFilter filter = PixelFilter::kBox);
/// The truncated Gaussian's inverse distribution: [0, 1) -> [-1.5, 1.5) pixels from the centre.
double gaussian_filter_offset(double u);

}  // namespace crex
