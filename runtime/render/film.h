/// \file film.h
/// Per-component image buffers (AOVs) and their composite. A contribution found by a ray of
/// bin X goes to AOV X; those found by camera rays (primary hits: direct light and emission
/// seen directly) go to the camera AOV. Sums are in double, added in a fixed order.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "base/components.h"
#include "runtime/render/ray_batch.h"
#include "runtime/base/vec3.h"

namespace crex {

/// AOV index: 0 = camera rays, 1 + component for D G S T R M.
inline constexpr size_t kAovCount = 1 + kComponentCount;
inline size_t aov_of(Component c) { return 1 + static_cast<size_t>(c); }
inline constexpr size_t kCameraAov = 0;
std::string aov_name(size_t aov);  ///< "camera", "D", ...

/// Which of the film's optional per-pixel buffers a render makes (issue 40: a 3840x2160 film
/// with all of them held 1.9 GB). What a buffer a run leaves out would have held goes where
/// the composite still counts it, so the final image is the same either way.
struct FilmLayout {
    /// Bit a: AOV a has a sum of its own (bit 0, the camera's, always). A contribution to an AOV
    /// without one is added to the camera's sum: then the camera AOV is "the rest".
    uint8_t aovs = (1u << kAovCount) - 1;
    bool emission = true;  ///< emitters seen directly (guidance's `emission` and `direct`)
    bool noise = true;     ///< the odd half-buffer and its counts (guidance's `noise`)
    /// Only what the composite, the sample counts and the rays picture need.
    static FilmLayout minimal() { return {1u, false, false}; }
    bool keeps(size_t aov) const { return (aovs >> aov & 1u) != 0; }
    bool keeps_every_aov() const { return aovs == (1u << kAovCount) - 1; }
};

class Film {
public:
    Film(int width, int height, FilmLayout layout = {});

    int width() const { return width_; }
    int height() const { return height_; }
    size_t pixel_count() const { return static_cast<size_t>(width_) * static_cast<size_t>(height_); }

    /// Adds a ray's contribution; `flags` are the ray's: from an odd camera sample it goes to
    /// the odd half-buffer too (the noise estimate), and to its branch's sum if that is tracked.
    void add(size_t aov, uint32_t pixel, const Vec3& value, uint8_t flags = 0) {
        add_to(sums_[layout_.keeps(aov) ? aov : kCameraAov], pixel, value);
        if ((flags & kRayOddSample) && layout_.noise) add_to(odd_, pixel, value);
        if (const unsigned b = (flags & kRayBranchMask) >> kRayBranchShift; b && (tracked_ >> (b - 1) & 1u)) {
            add_to(branch_[b - 1], pixel, value);
            if (flags & kRayOddSample) add_to(branch_odd_[b - 1], pixel, value);
        }
    }

    /// capict (thesis 7.4): for the components in `mask` (bit c: Component c), keep what each
    /// branch found (everything below a ray the camera hit spawned into that component) and
    /// the throughput of those first-bounce rays, executed or not, so that a branch can be
    /// interpolated between pixels without the material of the hit (branch / throughput).
    void track_branches(uint8_t mask);
    uint8_t tracked_branches() const { return tracked_; }
    /// A first-bounce ray of component c with throughput `beta` was spawned at a camera hit of
    /// `pixel`; `runs`: it goes on to be executed (else capict interpolates its branch).
    /// `replayed`: a sample already counted spawned it again, to run it now (capict's refinement).
    /// `odd`: it descends from an odd camera sample (the half-buffers of the branch's noise).
    void add_first_bounce(size_t c, uint32_t pixel, const Vec3& beta, bool runs, bool replayed = false, bool odd = false) {
        if (!replayed) add_to(first_all_[c], pixel, beta);
        if (runs) add_to(first_run_[c], pixel, beta);
        if (runs && odd) add_to(first_run_odd_[c], pixel, beta);
    }
    /// Sums over the pixel's samples (not divided): what branch c found, the throughput of its
    /// first-bounce rays that ran, and of all of them.
    Vec3 branch_sum(size_t c, uint32_t pixel) const { return sum_at(branch_[c], pixel); }
    Vec3 first_bounce_run(size_t c, uint32_t pixel) const { return sum_at(first_run_[c], pixel); }
    Vec3 first_bounce_all(size_t c, uint32_t pixel) const { return sum_at(first_all_[c], pixel); }
    /// The same over the odd camera samples only: with the sums above, the two halves of what
    /// the branch found, so how far its light at a pixel is from certain.
    Vec3 branch_odd_sum(size_t c, uint32_t pixel) const { return sum_at(branch_odd_[c], pixel); }
    Vec3 first_bounce_run_odd(size_t c, uint32_t pixel) const { return sum_at(first_run_odd_[c], pixel); }
    /// One camera sample of `pixel` was taken (odd: an odd sample index).
    void add_sample(uint32_t pixel, bool odd) {
        ++samples_[pixel];
        if (layout_.noise) odd_samples_[pixel] += odd ? 1 : 0;
    }
    /// For each i < n: add(aov, pixel[i], value[i], flags[i] & kRayOddSample) and
    /// count_ray(aov, pixel[i]). With `emission` the rays are camera rays, one per sample:
    /// add_emission(pixel[i], emission[i]) and add_sample too, so that a sample counts only once
    /// its camera ray is traced (a snapshot mid-pass sees no untraced, black samples). In
    /// parallel over pixel ranges, each pixel's values in ray order: the same sums at any
    /// thread count.
    void add_rays(size_t aov, const uint32_t* pixel, const uint8_t* flags, const Vec3* value, const Vec3* emission, size_t n);
    /// A ray of `aov` was executed for `pixel` (for the rays-per-pixel picture).
    void count_ray(size_t aov, uint32_t pixel) {
        ++rays_[pixel];
        components_[pixel] = static_cast<uint8_t>(components_[pixel] | (1u << aov));
    }
    uint32_t rays(uint32_t pixel) const { return rays_[pixel]; }
    /// Bit a set: the pixel received rays of AOV a (0 camera, 1 + component).
    uint8_t components(uint32_t pixel) const { return components_[pixel]; }
    /// Light seen directly by camera rays from emitters (a part of the camera AOV), for the
    /// guidance buffers `emission` and `direct` (= camera - emission).
    void add_emission(uint32_t pixel, const Vec3& value) {
        if (!layout_.emission) return;
        double* p = &emission_[3 * static_cast<size_t>(pixel)];
        p[0] += value.x, p[1] += value.y, p[2] += value.z;
    }
    std::vector<float> emission_image() const;
    /// Per pixel RGB, the standard error of the pixel's mean, from its two half-buffers (even
    /// and odd camera samples): |mean(even) - mean(odd)| / 2. 0 where a half is empty.
    std::vector<float> noise_image() const;
    uint32_t samples(uint32_t pixel) const { return samples_[pixel]; }

    const FilmLayout& layout() const { return layout_; }
    /// Linear RGB of one AOV (divided by the pixel's sample count), row-major, top row first;
    /// empty for an AOV the layout has no sum for.
    std::vector<float> aov_image(size_t aov) const;
    /// The composite: the sum of every AOV plus `ambient` (already per pixel, same scale).
    std::vector<float> composite(const std::vector<double>* ambient = nullptr) const;
    Vec3 pixel_value(size_t aov, uint32_t pixel) const;  ///< an AOV the layout keeps
    /// An AOV's sample sums over pixels [p0, p1) (not divided by sample counts); 0 for an AOV
    /// the layout has no sum for.
    Vec3 aov_total(size_t aov, uint32_t p0, uint32_t p1) const;
    /// An AOV's per-pixel RGB sample sums (3 per pixel), or null for an AOV the layout has no
    /// sum for: for passes that read several AOVs at once.
    const double* aov_sums(size_t aov) const { return layout_.keeps(aov) ? sums_[aov].data() : nullptr; }

    /// Bytes a pixel of a film holds (every buffer below), with the branches of the components
    /// in `tracked` (capict): what a render's memory model counts before the film exists.
    static size_t bytes_per_pixel(const FilmLayout& layout, uint8_t tracked = 0);
    /// Calls f(data, bytes per pixel) for every per-pixel buffer (row-major, so rows
    /// [r0, r1) are bytes [r0 w b, r1 w b) of each): how distributed rendering shares rows.
    /// Buffers the layout leaves out are not visited (every process of a group has one layout).
    template <typename F>
    void for_each_buffer(F&& f) {
        for (auto& s : sums_)
            if (!s.empty()) f(static_cast<void*>(s.data()), 3 * sizeof(double));
        f(static_cast<void*>(samples_.data()), sizeof(uint32_t));
        f(static_cast<void*>(rays_.data()), sizeof(uint32_t));
        f(static_cast<void*>(components_.data()), sizeof(uint8_t));
        if (layout_.emission) f(static_cast<void*>(emission_.data()), 3 * sizeof(double));
        if (layout_.noise) {
            f(static_cast<void*>(odd_.data()), 3 * sizeof(double));
            f(static_cast<void*>(odd_samples_.data()), sizeof(uint32_t));
        }
        for (size_t c = 0; c < kComponentCount; ++c)
            if (tracked_ >> c & 1u)
                for (auto* v : {&branch_[c], &first_run_[c], &first_all_[c], &branch_odd_[c], &first_run_odd_[c]})
                    f(static_cast<void*>(v->data()), 3 * sizeof(double));
    }

private:
    static void add_to(std::vector<double>& sums, uint32_t pixel, const Vec3& v) {
        double* p = &sums[3 * static_cast<size_t>(pixel)];
        p[0] += v.x, p[1] += v.y, p[2] += v.z;
    }
    static Vec3 sum_at(const std::vector<double>& sums, uint32_t pixel) {
        const double* p = &sums[3 * static_cast<size_t>(pixel)];
        return {p[0], p[1], p[2]};
    }
    int width_, height_;
    FilmLayout layout_;
    std::array<std::vector<double>, kAovCount> sums_;  // empty: the AOV's light is in the camera's
    std::vector<uint32_t> samples_;
    std::vector<uint32_t> rays_;
    std::vector<uint8_t> components_;
    std::vector<double> emission_;
    std::vector<double> odd_;            // every AOV's contributions of odd camera samples
    std::vector<uint32_t> odd_samples_;
    uint8_t tracked_ = 0;  // capict's components (bit c); their buffers are empty otherwise
    std::array<std::vector<double>, kComponentCount> branch_, first_run_, first_all_, branch_odd_, first_run_odd_;
};

}  // namespace crex
