#include "runtime/render/camera_samples.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/render/render_scene.h"

namespace crex {

uint64_t camera_path_id(uint64_t seed, uint32_t pixel, uint32_t sample) {
    const uint64_t pixel_key = (mix64(seed) + pixel) & ((uint64_t{1} << 40) - 1);  // distinct for every pixel
    return (pixel_key << 24) | (sample & 0xffffffu);
}

double gaussian_filter_offset(double u) {
    // Inverse of the distribution of a Gaussian (sigma 0.5) truncated to [-1.5, 1.5], tabulated
    // once at 4096 points and interpolated.
    static const std::vector<double> table = [] {
        constexpr int n = 4096;
        constexpr double sigma = 0.5, r = 1.5;
        auto cdf = [&](double x) { return 0.5 * (1 + std::erf(x / (sigma * std::sqrt(2.0)))); };
        double lo = cdf(-r), hi = cdf(r);
        std::vector<double> t(n + 1);
        for (int i = 0; i <= n; ++i) {
            double target = lo + (hi - lo) * i / n, a = -r, b = r;
            for (int k = 0; k < 60; ++k) {
                double m = 0.5 * (a + b);
                (cdf(m) < target ? a : b) = m;
            }
            t[static_cast<size_t>(i)] = 0.5 * (a + b);
        }
        return t;
    }();
    double x = std::clamp(u, 0.0, 1.0) * 4096;
    size_t i = std::min<size_t>(static_cast<size_t>(x), 4095);
    double f = x - static_cast<double>(i);
    return table[i] * (1 - f) + table[i + 1] * f;
}

void camera_sample_offset(uint64_t seed, uint32_t pixel, uint32_t sample, double& u, double& v, PixelFilter filter) {
    uint64_t h = hash_combine(seed ^ 0x5bd1e995ull, pixel);
    rotated_halton(sample, to_unit(h), to_unit(mix64(h)), u, v);
    if (filter == PixelFilter::kGaussian) {
        u = 0.5 + gaussian_filter_offset(u);
        v = 0.5 + gaussian_filter_offset(v);
    }
}

RayRecord camera_ray(const CameraRays& camera, CameraSeeds seeds, int width, uint32_t pixel, uint32_t sample, PixelFilter filter) {
    uint32_t x = pixel % static_cast<uint32_t>(width), y = pixel / static_cast<uint32_t>(width);
    double u, v;
    camera_sample_offset(seeds.position, pixel, sample, u, v, filter);
    RayRecord r;
    // Outside a fisheye's circle there is no ray: a weightless one along the view keeps the
    // sample (and its pixel's count) while adding no light.
    const bool valid = camera.generate(x + u, y + v, r.origin, r.direction);
    r.beta = valid ? Vec3{1, 1, 1} : Vec3{};
    r.pixel = pixel;
    r.path = camera_path_id(seeds.path, pixel, sample);
    r.flags = (sample & 1) ? kRayOddSample : 0;
    return r;
}

void append_camera_rays(const CameraRays& camera, CameraSeeds seeds, int width, uint32_t pixel, uint32_t first, uint32_t count,
                        RayBatch& rays, PixelFilter filter) {
    std::array<RayRecord, 16> buffer;  // appended in bulk, not ray by ray
    size_t buffered = 0;
    for (uint32_t k = first; k < first + count; ++k) {
        buffer[buffered++] = camera_ray(camera, seeds, width, pixel, k, filter);
        if (buffered == buffer.size()) rays.append(buffer.data(), buffered), buffered = 0;
    }
    rays.append(buffer.data(), buffered);
}

void add_ambient(const RayBatch& d, const Vec3& av, std::vector<double>& ambient) {
    if (!(max_component(av) > 0)) return;
    for (size_t i = 0; i < d.size(); ++i) {
        double* a = &ambient[3 * static_cast<size_t>(d.pixel[i])];
        a[0] += av.x * d.br[i];
        a[1] += av.y * d.bg[i];
        a[2] += av.z * d.bb[i];
    }
}

}  // namespace crex
