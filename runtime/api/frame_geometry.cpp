#include "runtime/api/frame_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "runtime/pipeline/pixel_probe.h"

namespace crex {

FrameGeometry frame_geometry(const RenderScene& scene, int width, int height) {
    FrameGeometry g;
    g.width = width, g.height = height;
    g.camera = scene.scene.camera;
    // The probe's centre rays, no mirror bounces: the point a pixel shows is where it is shaded.
    const PixelProbe probe = probe_pixels(scene, width, height, 0);
    const CameraRays rays(g.camera, width, height, scene.embree->origin_offset());
    const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
    g.point.assign(n, Vec3{});
    g.shape = probe.shape;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t p = r.begin(); p < r.end(); ++p) {
            Vec3 origin, dir;
            if (g.shape[p] < 0 || !std::isfinite(probe.distance[p]) ||
                !rays.generate(static_cast<double>(p % static_cast<size_t>(width)) + 0.5,
                               static_cast<double>(p / static_cast<size_t>(width)) + 0.5, origin, dir)) {
                g.shape[p] = -1;
                continue;
            }
            g.point[p] = origin + normalize_or_zero(dir) * static_cast<double>(probe.distance[p]);
        }
    });
    return g;
}

namespace {

// A pixel whose 3x3 neighbourhood's centres all see its shape: its value is that shape's
// light alone, not a blend across an edge.
bool interior(const FrameGeometry& g, int x, int y) {
    const int32_t shape = g.shape[static_cast<size_t>(y) * static_cast<size_t>(g.width) + static_cast<size_t>(x)];
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int qx = std::clamp(x + dx, 0, g.width - 1), qy = std::clamp(y + dy, 0, g.height - 1);
            if (g.shape[static_cast<size_t>(qy) * static_cast<size_t>(g.width) + static_cast<size_t>(qx)] != shape) return false;
        }
    return true;
}

// Projects points of `current` into `previous` and says whether a pixel of `previous` saw
// the same surface point: the same shape, within two pixel footprints of the point's
// distance from the previous camera (the nearest pixel's point is up to about one footprint
// away, more on surfaces seen at a slant), and at least 1 %.
class Reprojection {
public:
    Reprojection(const FrameGeometry& previous, const FrameGeometry& current, const Vec3& origin_offset)
        : previous_(previous), rays_(previous.camera, previous.width, previous.height, origin_offset) {
        ok_ = previous.width == current.width && previous.height == current.height && previous.point.size() == current.point.size() &&
              rays_.world_to_ndc(m_);
        eye_ = previous.camera.position - origin_offset;
        Vec3 o0, d0, o1, d1;
        double footprint = 0;
        if (rays_.generate(previous.width / 2 + 0.5, previous.height / 2 + 0.5, o0, d0) &&
            rays_.generate(previous.width / 2 + 0.5, previous.height / 2 + 1.5, o1, d1))
            footprint = length(normalize_or_zero(d0) - normalize_or_zero(d1));
        tolerance_ = std::max(0.01, 2 * footprint);
    }
    bool ok() const { return ok_; }
    // Where `x` falls in the previous frame, in pixels (centres at + 0.5); false: behind it.
    bool project(const Vec3& x, double& fx, double& fy) const {
        // Row vectors: (x, y, z, 1) M.
        const double u = x.x * m_[0] + x.y * m_[4] + x.z * m_[8] + m_[12], v = x.x * m_[1] + x.y * m_[5] + x.z * m_[9] + m_[13],
                     w = x.x * m_[3] + x.y * m_[7] + x.z * m_[11] + m_[15];
        if (!(w > 0)) return false;
        fx = u / w * previous_.width, fy = v / w * previous_.height;
        return std::isfinite(fx) && std::isfinite(fy);
    }
    bool saw(int px, int py, const Vec3& x, int32_t shape) const {
        if (!saw_shape(px, py, shape)) return false;
        const size_t q = static_cast<size_t>(py) * static_cast<size_t>(previous_.width) + static_cast<size_t>(px);
        return length(previous_.point[q] - x) <= tolerance_ * length(x - eye_);  // else hidden then, or another part of the shape
    }
    bool saw_shape(int px, int py, int32_t shape) const {
        return px >= 0 && py >= 0 && px < previous_.width && py < previous_.height &&
               previous_.shape[static_cast<size_t>(py) * static_cast<size_t>(previous_.width) + static_cast<size_t>(px)] == shape;
    }
    double depth(const Vec3& x) const { return length(x - eye_); }

private:
    const FrameGeometry& previous_;
    CameraRays rays_;
    std::array<double, 16> m_{};
    Vec3 eye_;
    double tolerance_ = 0.01;
    bool ok_ = false;
};

}  // namespace

std::vector<int32_t> previous_pixels(const FrameGeometry& previous, const FrameGeometry& current, const Vec3& origin_offset) {
    const size_t n = current.point.size();
    std::vector<int32_t> out(n, -1);
    const Reprojection r(previous, current, origin_offset);
    if (!r.ok()) return out;
    for (size_t p = 0; p < n; ++p) {
        double fx = 0, fy = 0;
        if (current.shape[p] < 0 || !r.project(current.point[p], fx, fy)) continue;
        if (!(fx >= 0 && fy >= 0 && fx < previous.width && fy < previous.height)) continue;
        const int px = static_cast<int>(fx), py = static_cast<int>(fy);
        if (r.saw(px, py, current.point[p], current.shape[p])) out[p] = py * previous.width + px;
    }
    return out;
}

std::vector<PixelTaps> previous_taps(const FrameGeometry& previous, const FrameGeometry& current, const Vec3& origin_offset) {
    const size_t n = current.point.size();
    std::vector<PixelTaps> out(n);
    const Reprojection r(previous, current, origin_offset);
    if (!r.ok()) return out;
    // Pixels in parallel: each writes only its own taps.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 12), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t p = range.begin(); p < range.end(); ++p) {
            double fx = 0, fy = 0;
            if (current.shape[p] < 0 || !r.project(current.point[p], fx, fy)) continue;
            // The four pixel centres around the point, weighted bilinearly, every one of them
            // inside the same shape (as the pixel is here): where a pixel's light is a blend
            // across an edge, the blend moves with the camera and is not inherited.
            if (!interior(current, static_cast<int>(p % static_cast<size_t>(current.width)), static_cast<int>(p / static_cast<size_t>(current.width))))
                continue;
            const double cx = fx - 0.5, cy = fy - 0.5;
            const double x0 = std::floor(cx), y0 = std::floor(cy);
            if (!(x0 >= -1 && y0 >= -1 && x0 < previous.width && y0 < previous.height)) continue;
            const double tx = cx - x0, ty = cy - y0;
            PixelTaps taps;
            double total = 0, depth = 0, nearest = 1e300, farthest = 0;
            size_t k = 0;
            bool every_tap = true;
            for (int dy = 0; dy < 2 && every_tap; ++dy)
                for (int dx = 0; dx < 2 && every_tap; ++dx) {
                    const int px = static_cast<int>(x0) + dx, py = static_cast<int>(y0) + dy;
                    const double w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty);
                    if (!(w > 1e-6)) continue;
                    every_tap = r.saw_shape(px, py, current.shape[p]) && interior(previous, px, py);
                    // A tap off the frame (a point within half a pixel of its border) has no
                    // pixel to read: its index would fall before or past the frame's arrays.
                    if (!every_tap) break;
                    const int32_t q = py * previous.width + px;
                    const double d = r.depth(previous.point[static_cast<size_t>(q)]);
                    taps.pixel[k] = q;
                    taps.weight[k] = static_cast<float>(w);
                    total += w, depth += w * d, ++k;
                    nearest = std::min(nearest, d), farthest = std::max(farthest, d);
                }
            if (!every_tap || k == 0) continue;
            // The point's distance from the previous eye where the taps' distances, interpolated,
            // put it: within their spread (a surface seen at a slant spans much depth between
            // pixels) and 1 %; else the point was hidden then by another part of the shape.
            const double d = r.depth(current.point[p]);
            if (!(std::fabs(d - depth / total) <= 0.01 * d + (farthest - nearest))) continue;
            for (size_t i = 0; i < k; ++i) taps.weight[i] = static_cast<float>(taps.weight[i] / total);
            out[p] = taps;
        }
    });
    return out;
}

}  // namespace crex
