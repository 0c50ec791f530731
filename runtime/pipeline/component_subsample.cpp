#include "runtime/pipeline/component_subsample.h"

#include <algorithm>
#include <cmath>

namespace crex {
namespace {

bool some(const Vec3& v) { return max_component(v) > 0; }

// The standard error of the luminance of branch c's light at a pixel, from its two halves
// (even and odd camera samples): |mean(even) - mean(odd)| / 2, as Film::noise_image. 0 when a
// half is empty (one sample: nothing says it is noisy).
double standard_error(const Film& film, size_t c, uint32_t p) {
    const Vec3 run = film.first_bounce_run(c, p), run_odd = film.first_bounce_run_odd(c, p);
    const Vec3 found = film.branch_sum(c, p), found_odd = film.branch_odd_sum(c, p);
    const Vec3 run_even = run - run_odd;
    if (!some(run_odd) || !some(run_even)) return 0;
    const double odd = luminance(per_unit(found_odd, run_odd)), even = luminance(per_unit(found - found_odd, run_even));
    return std::isfinite(odd - even) ? std::fabs(odd - even) / 2 : 0;
}

}  // namespace

void ComponentSubsampling::set_surfaces(const PixelProbe& probe) { surfaces_ = probe; }

bool ComponentSubsampling::same_surface(uint32_t p, uint32_t q) const {
    if (surfaces_.shape.empty() || p == q) return true;
    if (surfaces_.shape[p] != surfaces_.shape[q] || surfaces_.shape[p] < 0) return false;
    if (dot(surfaces_.normal[p], surfaces_.normal[q]) < 0.9) return false;  // 25 degrees
    const double dp = surfaces_.distance[p], dq = surfaces_.distance[q];
    return std::fabs(dp - dq) <= 0.3 * std::max(dp, dq);
}

void ComponentSubsampling::build(Component c, int width, int height, std::vector<double> spacing, const Film& film) {
    const size_t ci = static_cast<size_t>(c);
    auto seen = [&](uint32_t p) { return some(film.first_bounce_run(ci, p)); };
    // Each split makes an orphan pixel a corner, so this ends; 16 rounds are far more than the
    // 10 halvings from the largest spacing (1024) to 1.
    for (int round = 0; round < 16; ++round) {
        SubsampleGrid grid(width, height, spacing);
        bool split = false;
        for (uint32_t p = 0; p < spacing.size(); ++p) {
            if (grid.rendered(p) || !seen(p)) continue;
            auto [x0, y0, x1, y1] = grid.square(p);
            auto at = [&](int x, int y) { return static_cast<uint32_t>(y * width + x); };
            bool from = false;
            for (uint32_t q : {at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1)}) from |= seen(q) && same_surface(p, q);
            if (!from) spacing[p] = 1, split = true;
        }
        if (!split) {
            grids_[ci] = std::move(grid);
            spacing_[ci] = std::move(spacing);
            mask_ = static_cast<uint8_t>(mask_ | (1u << ci));
            return;
        }
    }
    spacing_[ci].assign(spacing.size(), 1.0);  // every pixel a corner
    grids_[ci] = SubsampleGrid(width, height, spacing_[ci]);
    mask_ = static_cast<uint8_t>(mask_ | (1u << ci));
}

std::vector<uint8_t> ComponentSubsampling::refine(Component c, double threshold, const Film& film) {
    const size_t ci = static_cast<size_t>(c);
    if (!grids_[ci]) return {};
    const SubsampleGrid& grid = *grids_[ci];
    const int w = grid.width(), h = grid.height();
    std::vector<double> spacing = spacing_[ci];
    bool split = false;
    for (int y = 0; y + 1 < h; ++y)
        for (int x = 0; x + 1 < w; ++x) {
            // Each square once: through the pixel diagonally inside its top-left corner.
            auto [x0, y0, x1, y1] = grid.square(static_cast<uint32_t>((y + 1) * w + (x + 1)));
            if (x0 != x || y0 != y) continue;
            const int size = std::max(x1 - x0, y1 - y0);
            if (size < 2) continue;
            double lo = 1e300, hi = 0, sum = 0, se_lo = 0, se_hi = 0;
            int n = 0;
            for (int qy : {int(y0), int(y1)})
                for (int qx : {int(x0), int(x1)}) {
                    const uint32_t q = static_cast<uint32_t>(qy * w + qx);
                    const Vec3 run = film.first_bounce_run(ci, q);
                    if (!some(run)) continue;
                    const double l = luminance(per_unit(film.branch_sum(ci, q), run));
                    const double e = standard_error(film, ci, q);
                    if (l < lo) lo = l, se_lo = e;
                    if (l > hi) hi = l, se_hi = e;
                    sum += l, ++n;
                }
            // Corners that differ only as much as their own few paths do (twice the standard
            // error of the difference) are noise, not light to resolve: path-traced D at 16
            // paths a corner split 72 % of the Cornell box's pixels into corners without this.
            const double difference = hi - lo;
            if (n < 2 || !(difference > threshold * (sum / n)) || !(difference > 2 * std::hypot(se_lo, se_hi))) continue;
            // Its inside only: the edge pixels belong to the neighbouring squares too.
            for (int py = y0 + 1; py < y1; ++py)
                for (int px = x0 + 1; px < x1; ++px) {
                    double& s = spacing[static_cast<size_t>(py * w + px)];
                    s = std::min(s, std::max(1.0, size / 2.0));
                }
            split = true;
        }
    if (!split) return {};
    const SubsampleGrid before = grid;
    build(c, w, h, std::move(spacing), film);
    std::vector<uint8_t> added(film.pixel_count(), 0);
    bool any_added = false;
    for (uint32_t p = 0; p < added.size(); ++p)
        if (grids_[ci]->rendered(p) && !before.rendered(p)) added[p] = 1, any_added = true;
    return any_added ? added : std::vector<uint8_t>{};
}

void ComponentSubsampling::add_stand_ins(const Film& film, std::vector<double>& sums) const {
    if (!any()) return;
    const std::vector<double> add = stand_ins(film);
    if (sums.empty()) sums.assign(add.size(), 0.0);  // a render without ambient stand-ins
    for (size_t i = 0; i < sums.size() && i < add.size(); ++i) sums[i] += add[i];
}

std::vector<uint8_t> ComponentSubsampling::first_bounce_runs(size_t pixels) const {
    std::vector<uint8_t> runs(pixels, 0x3f);
    for (size_t c = 0; c < kComponentCount; ++c)
        if (grids_[c])
            for (uint32_t p = 0; p < pixels; ++p)
                if (!grids_[c]->rendered(p)) runs[p] = static_cast<uint8_t>(runs[p] & ~(1u << c));
    return runs;
}

std::vector<double> ComponentSubsampling::stand_ins(const Film& film, std::optional<Component> only) const {
    const size_t pixels = film.pixel_count();
    const int w = film.width(), h = film.height();
    std::vector<double> out(3 * pixels, 0.0);
    for (size_t c = 0; c < kComponentCount; ++c) {
        if (!grids_[c] || (only && static_cast<size_t>(*only) != c)) continue;
        const SubsampleGrid& grid = *grids_[c];
        if (grid.width() != w || grid.height() != h) continue;
        // Each corner's radiance per unit throughput, once; where no corner and not the pixel
        // itself ever ran c, the image's average stands in.
        // has: the pixel ran c; complete: in all its samples, so it may lend its light to
        // others (a corner being rendered again by refinement has only a few samples done).
        std::vector<Vec3> radiance(pixels);
        std::vector<uint8_t> has(pixels, 0), complete(pixels, 0);
        Vec3 found_all, run_all;
        for (uint32_t p = 0; p < pixels; ++p) {
            const Vec3 run = film.first_bounce_run(c, p), found = film.branch_sum(c, p);
            found_all = found_all + found, run_all = run_all + run;
            if (some(run)) radiance[p] = per_unit(found, run), has[p] = 1;
            const Vec3 all = film.first_bounce_all(c, p);
            complete[p] = has[p] && !(luminance(all - run) > 1e-9 * luminance(all));
        }
        const Vec3 mean = per_unit(found_all, run_all);
        // The pixel's branch becomes `estimate`: what changes is estimate - what the film holds.
        auto add = [&](uint32_t p, const Vec3& estimate) {
            const Vec3 delta = estimate - film.branch_sum(c, p);
            if (is_finite(delta)) out[3 * p] += delta.x, out[3 * p + 1] += delta.y, out[3 * p + 2] += delta.z;
        };
        // Indirect diffuse light is smooth (what an irradiance cache relies on): where the grid
        // is coarser than a pixel its tent is twice as wide and covers the corners too, so no
        // corner keeps the noise of its own few paths (Cornell 128x128, spacing 8: FLIP 0.185
        // with the square's corners only, 0.155 so). Sharp components (reflections,
        // refractions) take their square's corners only. Where every pixel is a corner
        // (spacing 1, `--uniform max`) nothing is interpolated.
        const bool diffuse = c == static_cast<size_t>(Component::kD);
        for (uint32_t p = 0; p < pixels; ++p) {
            auto [x0, y0, x1, y1] = grid.square(p);
            const int size = std::max({1, x1 - x0, y1 - y0});
            const Vec3 all = film.first_bounce_all(c, p);
            if (!some(all)) continue;
            if (grid.rendered(p) && !(diffuse && size > 1)) {
                // A corner keeps its own light; while its skipped samples are still being
                // rendered again (refinement) the ones done stand in for all of them, so a
                // report's snapshot does not see it darken.
                if (has[p] && !complete[p]) add(p, all * radiance[p]);
                continue;
            }
            // A tent over the corners around the pixel, as wide as its square: the bilinear
            // interpolation of the square's corners where they all see the pixel's surface,
            // and finer corners next to it count too. Squares wider than 16 pixels take their
            // four corners only (a window that wide would cost r^2 per pixel).
            const int x = static_cast<int>(p) % w, y = static_cast<int>(p) / w;
            const int r = diffuse && size > 1 && size <= 8 ? 2 * size : size;
            Vec3 sum;
            double weight = 0;
            auto take = [&](int qx, int qy) {
                const uint32_t q = static_cast<uint32_t>(qy * w + qx);
                if (!grid.rendered(q) || !complete[q] || !same_surface(p, q)) return;  // p itself if a corner
                const double wq = (1.0 - std::abs(qx - x) / double(r)) * (1.0 - std::abs(qy - y) / double(r));
                if (!(wq > 0)) return;
                sum = sum + radiance[q] * wq;
                weight += wq;
            };
            if (r <= 16) {
                for (int qy = std::max(0, y - r + 1); qy <= std::min(h - 1, y + r - 1); ++qy)
                    for (int qx = std::max(0, x - r + 1); qx <= std::min(w - 1, x + r - 1); ++qx) take(qx, qy);
            } else {
                for (int qy : {int(y0), int(y1)})
                    for (int qx : {int(x0), int(x1)}) take(qx, qy);
            }
            add(p, all * (weight > 0 ? sum / weight : has[p] ? radiance[p] : mean));
        }
    }
    return out;
}

}  // namespace crex
