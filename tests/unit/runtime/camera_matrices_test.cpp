// The view written into EXR headers (worldToCamera, worldToNDC) is the camera that made the
// rays: a point seen through a pixel's centre projects back to that pixel.
#include <gtest/gtest.h>

#include <array>

#include "runtime/render/render_scene.h"

namespace crex {
namespace {

std::array<double, 4> times(const std::array<double, 3>& p, const std::array<double, 16>& m) {  // row vector p M
    std::array<double, 4> out{};
    for (int j = 0; j < 4; ++j) out[j] = p[0] * m[j] + p[1] * m[4 + j] + p[2] * m[8 + j] + m[12 + j];
    return out;
}

Camera tilted(Projection projection) {
    Camera c;
    c.position = {1.5, -2, 3};
    c.direction = {-0.3, 0.4, -1};
    c.up = {0.1, 1, 0.2};
    c.vfov_deg = projection == Projection::kParallel ? 4 : 50;
    c.hfov_deg = projection == Projection::kParallel ? 7 : 0;
    c.projection = projection;
    return c;
}

TEST(CameraMatrices, APointThroughAPixelProjectsBackToIt) {
    const int width = 64, height = 40;
    for (Projection projection : {Projection::kPerspective, Projection::kParallel}) {
        const CameraRays rays(tilted(projection), width, height, Vec3{});
        std::array<double, 16> to_camera{}, to_ndc{};
        ASSERT_TRUE(rays.world_to_camera(to_camera));
        ASSERT_TRUE(rays.world_to_ndc(to_ndc));
        for (auto [px, py] : {std::pair{0.5, 0.5}, std::pair{63.5, 0.5}, std::pair{10.25, 39.5}, std::pair{32.0, 20.0}}) {
            Vec3 origin, direction;
            ASSERT_TRUE(rays.generate(px, py, origin, direction));
            for (double t : {0.5, 3.0, 40.0}) {
                const Vec3 p = origin + direction * t;
                const auto ndc = times({p.x, p.y, p.z}, to_ndc);
                ASSERT_GT(ndc[3], 0);
                EXPECT_NEAR(ndc[0] / ndc[3], px / width, 1e-9) << static_cast<int>(projection);
                EXPECT_NEAR(ndc[1] / ndc[3], py / height, 1e-9) << static_cast<int>(projection);
                const auto cam = times({p.x, p.y, p.z}, to_camera);
                EXPECT_GT(cam[2], 0);  // in front of the camera: +z along the view
                EXPECT_NEAR(cam[3], 1, 1e-12);
                if (projection == Projection::kPerspective) {
                    EXPECT_NEAR(cam[2], ndc[3], 1e-9);  // w is the depth
                }
            }
        }
        // Right of centre is +x, above is +y.
        Vec3 o, d;
        rays.generate(60, 2, o, d);
        const Vec3 p = o + d * 5;
        const auto cam = times({p.x, p.y, p.z}, to_camera);
        EXPECT_GT(cam[0], 0);
        EXPECT_GT(cam[1], 0);
    }
}

TEST(CameraMatrices, FisheyesHaveNoProjectionMatrix) {
    const CameraRays rays(tilted(Projection::kAngular), 32, 32, Vec3{});
    std::array<double, 16> m{};
    EXPECT_TRUE(rays.world_to_camera(m));
    EXPECT_FALSE(rays.world_to_ndc(m));
}

}  // namespace
}  // namespace crex
