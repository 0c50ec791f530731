#include "runtime/api/frame_flicker.h"

#include <algorithm>
#include <array>
#include <cmath>

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
    for (size_t p = 0; p < n; ++p) {
        Vec3 origin, dir;
        if (g.shape[p] < 0 || !std::isfinite(probe.distance[p]) ||
            !rays.generate(static_cast<double>(p % static_cast<size_t>(width)) + 0.5, static_cast<double>(p / static_cast<size_t>(width)) + 0.5,
                           origin, dir)) {
            g.shape[p] = -1;
            continue;
        }
        g.point[p] = origin + normalize_or_zero(dir) * static_cast<double>(probe.distance[p]);
    }
    return g;
}

std::optional<FrameFlicker> frame_flicker(const FrameGeometry& previous, const std::vector<float>& previous_image,
                                          const FrameGeometry& current, const std::vector<float>& image, const Vec3& origin_offset) {
    const size_t n = current.point.size();
    if (previous.width != current.width || previous.height != current.height || image.size() != 3 * n || previous_image.size() != 3 * n)
        return std::nullopt;
    const CameraRays before(previous.camera, previous.width, previous.height, origin_offset);
    std::array<double, 16> m;
    if (!before.world_to_ndc(m)) return std::nullopt;
    const Vec3 eye = previous.camera.position - origin_offset;
    // How far apart neighbouring pixel centres' points are, per unit of distance (the angle
    // between two central rays): the nearest pixel's point is up to about one footprint away,
    // more on surfaces seen at a slant, so a match may be two footprints off, and at least 1 %.
    Vec3 o0, d0, o1, d1;
    double footprint = 0;
    if (before.generate(previous.width / 2 + 0.5, previous.height / 2 + 0.5, o0, d0) &&
        before.generate(previous.width / 2 + 0.5, previous.height / 2 + 1.5, o1, d1))
        footprint = length(normalize_or_zero(d0) - normalize_or_zero(d1));
    const double tolerance = std::max(0.01, 2 * footprint);
    double sum = 0;
    size_t matched = 0;
    for (size_t p = 0; p < n; ++p) {
        if (current.shape[p] < 0) continue;
        const Vec3& x = current.point[p];
        // Row vectors: (x, y, z, 1) M.
        const double u = x.x * m[0] + x.y * m[4] + x.z * m[8] + m[12], v = x.x * m[1] + x.y * m[5] + x.z * m[9] + m[13],
                     w = x.x * m[3] + x.y * m[7] + x.z * m[11] + m[15];
        if (!(w > 0)) continue;
        const double fx = u / w * previous.width, fy = v / w * previous.height;
        if (!(fx >= 0 && fy >= 0 && fx < previous.width && fy < previous.height)) continue;
        const size_t q = static_cast<size_t>(fy) * static_cast<size_t>(previous.width) + static_cast<size_t>(fx);
        if (previous.shape[q] != current.shape[p]) continue;
        const double reach = tolerance * length(x - eye);
        if (!(length(previous.point[q] - x) <= reach)) continue;  // hidden then, or another part of the shape
        for (size_t c = 0; c < 3; ++c) {
            const double a = image[3 * p + c], b = previous_image[3 * q + c];
            if (std::isfinite(a) && std::isfinite(b)) sum += std::fabs(a - b);
        }
        ++matched;
    }
    if (matched == 0) return std::nullopt;
    return FrameFlicker{sum / (3.0 * static_cast<double>(matched)), static_cast<double>(matched) / static_cast<double>(n)};
}

}  // namespace crex
