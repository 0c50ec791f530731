#include "runtime/render/film.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

#include "base/check.h"

namespace crex {

std::string aov_name(size_t aov) {
    if (aov == kCameraAov) return "camera";
    return std::string(1, kComponentTable[aov - 1].letter);
}

Film::Film(int width, int height, FilmLayout layout) : width_(width), height_(height), layout_(layout) {
    layout_.aovs |= 1u;  // the camera's sum holds what has no sum of its own
    for (size_t a = 0; a < kAovCount; ++a)
        if (layout_.keeps(a)) sums_[a].assign(3 * pixel_count(), 0.0);
    samples_.assign(pixel_count(), 0);
    rays_.assign(pixel_count(), 0);
    components_.assign(pixel_count(), 0);
    if (layout_.emission) emission_.assign(3 * pixel_count(), 0.0);
    if (layout_.noise) {
        odd_.assign(3 * pixel_count(), 0.0);
        odd_samples_.assign(pixel_count(), 0);
    }
}

void Film::add_rays(size_t aov, const uint32_t* pixel, const uint8_t* flags, const Vec3* value, const Vec3* emission, size_t n) {
    // Each part owns a range of pixels and scans every ray: a few parts only, since each
    // scan reads all n pixel indices. From 1,024 rays: most steps of a crex's loop hand over
    // a few thousand, and adding those alone left the other threads waiting (render_bench,
    // two threads: the worker idle 8.0 -> 6.3 % of its time with 1,024 instead of 4,096).
    const size_t pixels = pixel_count();
    const size_t parts = n < 1024 ? 1 : std::min<size_t>(static_cast<size_t>(std::max(1, tbb::this_task_arena::max_concurrency())), 4);
    tbb::parallel_for(size_t{0}, parts, [&](size_t part) {
        const size_t lo = pixels * part / parts, hi = pixels * (part + 1) / parts;
        for (size_t i = 0; i < n; ++i) {
            if (pixel[i] < lo || pixel[i] >= hi) continue;
            add(aov, pixel[i], value[i], flags[i]);
            count_ray(aov, pixel[i]);
            if (emission) add_emission(pixel[i], emission[i]), add_sample(pixel[i], flags[i] & kRayOddSample);
        }
    });
}

size_t Film::bytes_per_pixel(const FilmLayout& layout, uint8_t tracked) {
    constexpr size_t rgb = 3 * sizeof(double);
    size_t bytes = rgb;  // the camera's sum
    for (size_t a = 1; a < kAovCount; ++a)
        if (layout.keeps(a)) bytes += rgb;
    bytes += 2 * sizeof(uint32_t) + sizeof(uint8_t);  // sample and ray counts, component bits
    if (layout.emission) bytes += rgb;
    if (layout.noise) bytes += rgb + sizeof(uint32_t);
    for (size_t c = 0; c < kComponentCount; ++c)
        if (tracked >> c & 1u) bytes += 5 * rgb;
    return bytes;
}

void Film::track_branches(uint8_t mask) {
    tracked_ = mask;
    for (size_t c = 0; c < kComponentCount; ++c) {
        const size_t n = (mask >> c & 1u) ? 3 * pixel_count() : 0;
        for (auto* v : {&branch_[c], &first_run_[c], &first_all_[c], &branch_odd_[c], &first_run_odd_[c]}) v->assign(n, 0.0);
    }
}

Vec3 Film::pixel_value(size_t aov, uint32_t pixel) const {
    CREX_CHECK(layout_.keeps(aov));
    double n = samples_[pixel];
    if (n <= 0) return {};
    const double* p = &sums_[aov][3 * static_cast<size_t>(pixel)];
    return {p[0] / n, p[1] / n, p[2] / n};
}

Vec3 Film::aov_total(size_t aov, uint32_t p0, uint32_t p1) const {
    if (!layout_.keeps(aov)) return {};
    const std::vector<double>& sums = sums_[aov];
    double total[3] = {0, 0, 0};
    for (size_t i = 3 * static_cast<size_t>(p0); i < 3 * static_cast<size_t>(p1); i += 3)
        total[0] += sums[i], total[1] += sums[i + 1], total[2] += sums[i + 2];
    return {total[0], total[1], total[2]};
}

namespace {

// The image never carries NaN or Inf: a non-finite value (which shading guards against) would
// otherwise poison every metric and tone map downstream.
float finite_or_zero(double v) {
    float f = static_cast<float>(v);
    return std::isfinite(f) ? f : 0.0f;
}

}  // namespace

std::vector<float> Film::aov_image(size_t aov) const {
    if (!layout_.keeps(aov)) return {};
    std::vector<float> out(3 * pixel_count());
    for (uint32_t p = 0; p < pixel_count(); ++p) {
        Vec3 v = pixel_value(aov, p);
        out[3 * p] = finite_or_zero(v.x);
        out[3 * p + 1] = finite_or_zero(v.y);
        out[3 * p + 2] = finite_or_zero(v.z);
    }
    return out;
}

std::vector<float> Film::emission_image() const {
    CREX_CHECK(layout_.emission);
    std::vector<float> out(3 * pixel_count());
    for (uint32_t p = 0; p < pixel_count(); ++p) {
        double n = samples_[p];
        if (n <= 0) continue;
        for (size_t c = 0; c < 3; ++c) out[3 * p + c] = finite_or_zero(emission_[3 * p + c] / n);
    }
    return out;
}

std::vector<float> Film::noise_image() const {
    CREX_CHECK(layout_.noise);
    std::vector<float> out(3 * pixel_count(), 0.0f);
    for (uint32_t p = 0; p < pixel_count(); ++p) {
        double odd = odd_samples_[p], even = double(samples_[p]) - odd;
        if (odd <= 0 || even <= 0) continue;
        for (size_t c = 0; c < 3; ++c) {
            double total = 0;
            for (const auto& s : sums_)
                if (!s.empty()) total += s[3 * p + c];
            double o = odd_[3 * p + c];
            out[3 * p + c] = finite_or_zero(std::fabs((total - o) / even - o / odd) / 2);
        }
    }
    return out;
}

std::vector<float> Film::composite(const std::vector<double>* ambient) const {
    std::vector<float> out(3 * pixel_count());
    for (uint32_t p = 0; p < pixel_count(); ++p) {
        double n = samples_[p];
        if (n <= 0) continue;
        for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (const auto& s : sums_)
                if (!s.empty()) sum += s[3 * p + static_cast<size_t>(c)];
            if (ambient && !ambient->empty()) sum += (*ambient)[3 * p + static_cast<size_t>(c)];
            out[3 * p + static_cast<size_t>(c)] = finite_or_zero(sum / n);
        }
    }
    return out;
}

}  // namespace crex
