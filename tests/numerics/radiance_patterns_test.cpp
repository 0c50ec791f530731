// Patterns on RADIANCE's emitters (issue 39): a luminaire's distribution (brightfunc or
// brightdata over source.cal's coordinates) scales its light by direction and by nothing
// else, a sky picture (colorpict on a distant glow) is seen where its mapping puts it, and a
// BRTDfunc's specular parts follow its functions of the ray.
// Each against values worked out by hand; renders of 32x32 or less.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "runtime/base/sampling.h"
#include "runtime/io/image_io.h"
#include "runtime/scene/load_scene.h"
#include "tests/support/float_map.h"
#include "tests/support/scene_helpers.h"
#include "tests/support/scratch_folder.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

class RadiancePatterns : public testing::ScratchFolderTest {
protected:
    RadiancePatterns() : ScratchFolderTest("crex_radiance_patterns_") {}

public:
    Scene load_text(const std::string& name, const std::string& text) { return load(name, text); }

protected:
    Scene load(const std::string& name, const std::string& text) {
        std::ofstream(path(name)) << text;
        auto r = testing::load_path(path(name));
        if (!r.scene) throw std::runtime_error(r.diagnostics.empty() ? "no scene" : r.diagnostics[0].message);
        return *r.scene;
    }
};

// A grey floor at z = 0 seen from straight above through a parallel view 2 wide, lit by a
// lamp 0.04 on a side facing down at height 1 above the origin, with `modifier` (void: none).
std::string lamp_scene(const std::string& patterns, const std::string& modifier) {
    return "#@crex view -vtl -vp 0 0 0.5 -vd 0 0 -1 -vu 0 1 0 -vh 2 -vv 2\n"
           "void plastic floor 0 0 5 .5 .5 .5 0 0\n"
           "floor polygon ground 0 0 12 -10 -10 0 10 -10 0 10 10 0 -10 10 0\n" + patterns +
           modifier + " light lamp 0 0 3 1000 1000 1000\n"
           "lamp polygon bulb 0 0 12 -.02 -.02 1  -.02 .02 1  .02 .02 1  .02 -.02 1\n";
}

// Floor pixel (x, y) of an n x n image of lamp_scene: the angle at the lamp, in degrees, from
// straight down to the pixel's centre.
double theta_at(int x, int y, int n) {
    const double px = -1 + 2 * (x + 0.5) / n, py = 1 - 2 * (y + 0.5) / n;
    return std::atan(std::hypot(px, py)) * 180 / kPi;
}

// The ratio of the patterned to the plain image is the distribution's value towards each
// pixel: the lamp is small, and both renders draw the same points on it.
void expect_distribution(const Scene& patterned, const Scene& plain, double (*expected)(double theta)) {
    const int n = 16;
    const std::vector<float> a = testing::render_crex(patterned, "", n, 4, 0, 4).image();
    const std::vector<float> b = testing::render_crex(plain, "", n, 4, 0, 4).image();
    for (int y = 0; y < n; y += 3)
        for (int x = 0; x < n; x += 3) {
            const size_t i = 3 * (static_cast<size_t>(y) * n + static_cast<size_t>(x)) + 1;
            ASSERT_GT(b[i], 0.0f);
            EXPECT_NEAR(a[i] / b[i], expected(theta_at(x, y, n)), 0.02) << "pixel " << x << ", " << y;
        }
}

TEST_F(RadiancePatterns, ABrightfuncOfSourceCalsThetaScalesTheLampByDirection) {
    // 1 - theta / 90 (theta from straight down: source.cal's src_theta, crex's built-in copy).
    const Scene patterned = load("f.rad", lamp_scene("void brightfunc dist 2 1-src_theta/90 source.cal\n0\n0\n", "dist"));
    const Scene plain = load("p.rad", lamp_scene("", "void"));
    expect_distribution(patterned, plain, [](double theta) { return 1 - theta / 90; });
}

TEST_F(RadiancePatterns, ABrightdataTableInterpolatesBetweenItsAngles) {
    // A table over theta at 0, 30, 60 and 90 degrees, linear in between: 1, 0.5, 0.25, 0.
    std::ofstream(path("dist.dat")) << "# a luminaire's distribution\n1\n0 90 4\n1 .5 .25 0\n";
    const Scene patterned = load("d.rad", lamp_scene("void brightdata dist 4 noop dist.dat source.cal src_theta\n0\n0\n", "dist"));
    const Scene plain = load("p.rad", lamp_scene("", "void"));
    expect_distribution(patterned, plain, [](double theta) {
        return theta < 30 ? 1 - 0.5 * theta / 30 : theta < 60 ? 0.5 - 0.25 * (theta - 30) / 30 : 0.25 * (90 - theta) / 30;
    });
}

TEST_F(RadiancePatterns, ASkyPictureIsSeenWhereItsMappingPutsIt) {
    // A 2 x 2 picture on a glow filling the sky: bottom row 1, 3; top row 5, 7 (grid points at
    // the picture's edges, linear between). u = (Dy + 1) / 2, v = (Dx + 1) / 2 through a
    // function file. A floor below keeps the scene from being empty.
    std::vector<float> rgb = {5, 5, 5, 7, 7, 7, 1, 1, 1, 3, 3, 3};  // the file's top row first
    ASSERT_EQ(write_image(path("sky.exr"), 2, 2, {ImageLayer{"", rgb}}, {}), "");
    std::ofstream(path("map.cal")) << "su = (Dy + 1) / 2; sv = (Dx + 1) / 2;\n";
    // The camera looks up, tilted by `tilt_deg` towards +x or +y.
    auto render_towards = [&](double tilt_deg, bool towards_x) {
        const double t = tilt_deg * kPi / 180;
        const std::string text = fmt::format(
            "#@crex view -vp 0 0 0 -vd {} {} {} -vu 0 0 1 -vh 1 -vv 1\n"
            "void colorpict pic 7 red green blue sky.exr map.cal su sv\n0\n0\n"
            "pic glow skyglow 0 0 4 1 1 1 0\n"
            "skyglow source sky 0 0 4 0 0 1 360\n"
            "void plastic grey 0 0 5 .5 .5 .5 0 0\n"
            "grey polygon floor 0 0 12 -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1\n",
            towards_x ? std::sin(t) : 0.0, towards_x ? 0.0 : std::sin(t), std::cos(t));
        const Scene s = load("sky.rad", text);
        const std::vector<float> img = testing::render_crex(s, "", 8, 1).image();
        return testing::mean_luminance(img);
    };
    // Nearly straight up: u = v = 0.5, the mean of the four corners.
    EXPECT_NEAR(render_towards(1, false), 4.0, 0.05);
    // Tilted towards +y by 30 degrees: Dy = 0.5, u = 0.75, v = 0.5: bottom row 1 + 2 * 0.75 =
    // 2.5, top row 6.5, between them 4.5.
    EXPECT_NEAR(render_towards(30, false), 4.5, 0.02);
    // Towards +x: v = 0.75, u = 0.5: the rows' means 2 and 6, three quarters up: 5 (the
    // picture's top row is v = 1).
    EXPECT_NEAR(render_towards(30, true), 5.0, 0.02);
}

// A float picture with a pixel that is not finite (a PFM written byte by byte: crex's own
// writer keeps images finite). Until 2026-12-07 it made every lookup interpolating it NaN, which
// the render then dropped without a word; now the pixel reads as the mean of its finite
// neighbours, as oiiotool --fixnan box3 repairs it, and W314 says so.
TEST_F(RadiancePatterns, ASkyPicturesNonFinitePixelReadsAsItsNeighboursMean) {
    // The 2 x 2 sky above with its bottom-right pixel (3) NaN in red, infinite in green and
    // blue: each channel reads (5 + 7 + 1) / 3 there. PFM rows go bottom up.
    const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
    const std::vector<float> rows = {1, 1, 1, nan, inf, inf, 5, 5, 5, 7, 7, 7};
    testing::write_pfm(path("sky.pfm"), 2, 2, rows);
    std::ofstream(path("map.cal")) << "su = (Dy + 1) / 2; sv = (Dx + 1) / 2;\n";
    const Scene s = load("sky.rad",
                         "#@crex view -vp 0 0 0 -vd 0 0.0175 0.9998 -vu 0 0 1 -vh 1 -vv 1\n"
                         "void colorpict pic 7 red green blue sky.pfm map.cal su sv\n0\n0\n"
                         "pic glow skyglow 0 0 4 1 1 1 0\nskyglow source sky 0 0 4 0 0 1 360\n"
                         "void plastic grey 0 0 5 .5 .5 .5 0 0\ngrey polygon floor 0 0 12 -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1\n");
    RunResult r = testing::render_crex(s, "", 8, 1);
    const std::vector<float> img = r.image();
    ASSERT_TRUE(testing::all_finite(img));
    // Nearly straight up: the mean of the four corners, (5 + 7 + 1 + 13 / 3) / 4.
    EXPECT_NEAR(testing::mean_luminance(img), (13.0 + 13.0 / 3) / 4, 0.05);
    const Diagnostic* said = nullptr;
    for (const Diagnostic& w : r.warnings)
        if (w.code == "W314") said = &w;
    ASSERT_TRUE(said) << (r.warnings.empty() ? "no warnings" : r.warnings[0].message);
    EXPECT_NE(said->where.find("sky.pfm"), std::string::npos) << said->where;
    EXPECT_NE(said->message.find("3 values that are not finite"), std::string::npos) << said->message;
}

TEST_F(RadiancePatterns, ABrtdfuncsMirrorAndWindowFollowRdotOnEitherSide) {
    // A BRTDfunc pane at z = 0 in a sky of radiance 1 (a distant glow all round), no diffuse
    // parts: a pixel is the specular reflectance plus the specular transmittance. Reflectance
    // if(Rdot - .5, .2, .8), transmittance if(RdotP - .5, .3, 0): RADIANCE's Rdot is negative
    // on the back, RdotP is not.
    auto seen = [&](const std::string& view) {
        const std::string text = view +
                                 "void BRTDfunc pane_mat 10 if(Rdot-.5,.2,.8) if(Rdot-.5,.2,.8) if(Rdot-.5,.2,.8)\n"
                                 "  if(RdotP-.5,.3,0) if(RdotP-.5,.3,0) if(RdotP-.5,.3,0) 0 0 0 .\n0\n9 0 0 0 0 0 0 0 0 0\n"
                                 "pane_mat polygon pane 0 0 12 -10 -10 0 10 -10 0 10 10 0 -10 10 0\n"
                                 "void glow skyglow 0 0 4 1 1 1 0\nskyglow source sky 0 0 4 0 0 1 360\n";
        const Scene s = load("brtd.rad", text);
        return testing::mean_luminance(testing::render_crex(s, "[ST]", 8, 1).image());  // one specular bounce
    };
    // From the front along the normal: Rdot = 1: 0.2 + 0.3.
    EXPECT_NEAR(seen("#@crex view -vtl -vp 0 0 1 -vd 0 0 -1 -vu 0 1 0 -vh .1 -vv .1\n"), 0.5, 1e-4);
    // From the front at 70 degrees from the normal: Rdot = 0.34: 0.8 + 0.
    EXPECT_NEAR(seen("#@crex view -vtl -vp 0 -0.94 0.34 -vd 0 0.9397 -0.342 -vu 0 0 1 -vh .1 -vv .1\n"), 0.8, 1e-4);
    // From the back along the normal: Rdot = -1, RdotP = 1: 0.8 + 0.3.
    EXPECT_NEAR(seen("#@crex view -vtl -vp 0 0 -1 -vd 0 0 1 -vu 0 1 0 -vh .1 -vv .1\n"), 1.1, 1e-4);
}

TEST_F(RadiancePatterns, AMixfuncIsItsForegroundWhereItsCoefficientSays) {
    // Two glows (radiance 1 and 3) mixed on a plane seen from above: the foreground where the
    // coefficient is 1, the background where it is 0, and a share of each in between.
    auto seen = [&](const std::string& coefficient, int size, uint32_t spp) {
        const std::string text = "#@crex view -vtl -vp 0 0 1 -vd 0 0 -1 -vu 0 1 0 -vh 2 -vv 2\n"
                                 "void glow one 0 0 4 1 1 1 0\nvoid glow three 0 0 4 3 3 3 0\n"
                                 "void mixfunc both 4 one three " + coefficient + " .\n0\n0\n"
                                 "both polygon plane 0 0 12 -5 -5 0 5 -5 0 5 5 0 -5 5 0\n";
        return testing::render_crex(load("mix.rad", text), "", size, spp).image();
    };
    const int n = 8;
    const std::vector<float> halves = seen("if(Px,1,0)", n, 1);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) EXPECT_FLOAT_EQ(halves[3 * (static_cast<size_t>(y) * n + static_cast<size_t>(x))], x < n / 2 ? 3.0f : 1.0f);
    // A quarter foreground: 0.25 * 1 + 0.75 * 3 = 2.5 on average (each point one or the other:
    // variance 0.75 a sample, 16 x 16 pixels x 64 samples, standard error 0.007; 4 of them).
    EXPECT_NEAR(testing::mean_luminance(seen(".25", 16, 64)), 2.5, 0.03);
}

TEST_F(RadiancePatterns, APatternOnASurfaceScalesItsColourWhereItSays) {
    // A grey plastic (0.5) under a sky of radiance 1 reflects 0.5; a colorfunc of the hit point
    // makes it a quarter of that where x < 0. The same on a compiled mesh by its texture
    // coordinates (Lu: quad.rtm's u is its x, the mesh scaled to [-1, 1]).
    auto halves = [&](const std::string& surface) {
        const std::string text = "#@crex view -vtl -vp 0 0 1 -vd 0 0 -1 -vu 0 1 0 -vh 2 -vv 2\n"
                                 "void glow skyglow 0 0 4 1 1 1 0\nskyglow source sky 0 0 4 0 0 1 180\n" + surface;
        const int n = 8;
        const std::vector<float> img = testing::render_crex(load("s.rad", text), "", n, 16, 0, 16).image();
        double left = 0, right = 0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) (x < n / 2 ? left : right) += img[3 * (static_cast<size_t>(y) * n + static_cast<size_t>(x)) + 1];
        return std::pair{left / (n * n / 2), right / (n * n / 2)};
    };
    auto [l1, r1] = halves("void colorfunc pat 4 if(Px,1,.25) if(Px,1,.25) if(Px,1,.25) .\n0\n0\n"
                           "pat plastic grey 0 0 5 .5 .5 .5 0 0\ngrey polygon floor 0 0 12 -5 -5 0 5 -5 0 5 5 0 -5 5 0\n");
    EXPECT_NEAR(r1, 0.5, 0.01);
    EXPECT_NEAR(l1, 0.125, 0.0025);
    const std::string quad = std::string(CREX_SOURCE_DIR) + "/tests/data/radiance/quad.rtm";
    auto [l2, r2] = halves("void colorfunc pat 4 if(Lu-.5,1,.25) if(Lu-.5,1,.25) if(Lu-.5,1,.25) .\n0\n0\n"
                           "pat plastic grey 0 0 5 .5 .5 .5 0 0\ngrey mesh m 7 " + quad + " -t -.5 -.5 0 -s 2\n0\n0\n");
    EXPECT_NEAR(r2, 0.5, 0.01);
    EXPECT_NEAR(l2, 0.125, 0.0025);
}

TEST_F(RadiancePatterns, PlasfuncAndTransfuncAnswerALampByTheirFunctionOfItsDirection) {
    // A floor at z = 0 lit by the small lamp of lamp_scene, seen straight along its normal
    // (Idz = 1); its function sees the direction l to the lamp in its coordinates and in
    // RADIANCE's local frame (Ldz: the cosine). Against a plain plastic of colour .5 seen the
    // same way (direct light .5 / pi cos), pixel by pixel:
    //   plasfunc .5 grey, specularity .5, f = (lx^2 + Ldz Idz) / pi:
    //     (.25 / pi + .5 f) / (.5 / pi) = .5 + lx^2 + lz
    //   transfunc .5 grey, transmitting all (tspec .5), seen from below, f = lx^2 + 1:
    //     (.25 / pi + .5 .5 f) / (.5 / pi) = .5 + pi (lx^2 + 1) / 2
    std::ofstream(path("fn.cal")) << "front(x,y,z) = (x*x + Ldz(x,y,z)*Idz)/PI;\nback(x,y,z,w) = x*x + 1;\n";
    auto scene = [&](const std::string& material, double eye_z) {
        return fmt::format("#@crex view -vtl -vp 0 0 {} -vd 0 0 {} -vu 0 1 0 -vh 2 -vv 2\n{}\n"
                           "floor polygon ground 0 0 12 -10 -10 0 10 -10 0 10 10 0 -10 10 0\n"
                           "void light lamp 0 0 3 1000 1000 1000\n"
                           "lamp polygon bulb 0 0 12 -.02 -.02 1  -.02 .02 1  .02 .02 1  .02 -.02 1\n",
                           eye_z, eye_z > 0 ? -1 : 1, material);
    };
    const Scene plain = load("p.rad", scene("void plastic floor 0 0 5 .5 .5 .5 0 0", .5));
    const Scene front = load("f.rad", scene("void plasfunc floor 2 front fn.cal 0 7 .5 .5 .5 .5 0 1 0", .5));
    const Scene back = load("b.rad", scene("void transfunc floor 2 back fn.cal 0 9 .5 .5 .5 0 1 .5 0 1 0", -.5));
    const int n = 16;
    const std::vector<float> a = testing::render_crex(front, "", n, 4, 0, 4).image();
    const std::vector<float> b = testing::render_crex(back, "", n, 4, 0, 4).image();
    const std::vector<float> ref = testing::render_crex(plain, "", n, 4, 0, 4).image();
    for (int y = 0; y < n; y += 3)
        for (int x = 0; x < n; x += 3) {
            const size_t i = 3 * (static_cast<size_t>(y) * n + static_cast<size_t>(x)) + 1;
            const double px = -1 + 2 * (x + 0.5) / n, py = 1 - 2 * (y + 0.5) / n;
            const double d = std::sqrt(px * px + py * py + 1), lx = px / d, lz = 1 / d;
            ASSERT_GT(ref[i], 0.0f);
            EXPECT_NEAR(a[i] / ref[i], .5 + lx * lx + lz, 0.02) << "plasfunc, pixel " << x << ", " << y;
            EXPECT_NEAR(b[i] / ref[i], .5 + kPi * (lx * lx + 1) / 2, 0.03) << "transfunc, pixel " << x << ", " << y;
        }
}

TEST_F(RadiancePatterns, AFuncMaterialTakesASkysLightAsRadianceDoesWithoutItsFunction) {
    // RADIANCE never samples a sky (a glow source) for direct light, so its light reaches a
    // plasfunc only as indirect light, weighted by the colour (less what it transmits), not
    // shaped by the function (m_brdf.c). A floor of plasfunc .5 grey, specularity .5, whose
    // function is 0, under a sky of radiance 1 over the upper hemisphere: E = pi, so the floor
    // shows .5 (the function alone would have left .25: the diffuse part 1 - .5).
    std::ofstream(path("zero.cal")) << "zero(x,y,z) = 0;\n";
    const Scene s = load("z.rad", "#@crex view -vtl -vp 0 0 .5 -vd 0 0 -1 -vu 0 1 0 -vh 2 -vv 2\n"
                                  "void plasfunc floor 2 zero zero.cal 0 4 .5 .5 .5 .5\n"
                                  "floor polygon ground 0 0 12 -10 -10 0 10 -10 0 10 10 0 -10 10 0\n"
                                  "void glow skyglow 0 0 4 1 1 1 0\nskyglow source sky 0 0 4 0 0 1 180\n");
    EXPECT_NEAR(testing::mean_luminance(testing::render_crex(s, "", 16, 16, 0, 4).image()), 0.5, 0.005);
}

// A glow floor of radiance 1 at z = -1 (facing up) under a surface at z = 0 of `material`,
// seen straight down through a parallel view 2 wide; the image's pixels.
std::vector<float> over_glow_floor(RadiancePatterns& t, const std::string& material, int n) {
    return testing::render_crex(t.load_text("g.rad", "#@crex view -vtl -vp 0 0 1 -vd 0 0 -1 -vu 0 1 0 -vh 2 -vv 2\n"
                                            "void glow floorglow 0 0 4 1 1 1 0\n"
                                            "floorglow polygon floor 0 0 12 -10 -10 -1 10 -10 -1 10 10 -1 -10 10 -1\n" + material +
                                            "\nsurf polygon plane 0 0 12 -5 -5 0 5 -5 0 5 5 0 -5 5 0\n"),
                                "T", n, 4)  // one step through the surface
        .image();
}

TEST_F(RadiancePatterns, APrismSendsEveryRayWhereItsFunctionsSay) {
    // prism1: the ray goes on down with .5 of its weight (the floor: .5), or up (nothing
    // there: 0); a coefficient of the ray (.7 |Dz|, straight down: .7); prism2 sums its two
    // redirections (.3 down, .2 up: .3).
    const std::pair<const char*, float> cases[] = {{"void prism1 surf 5 .5 0 0 -1 . 0 0", 0.5f},
                                                   {"void prism1 surf 5 .5 0 0 1 . 0 0", 0.0f},
                                                   {"void prism1 surf 5 .7*abs(Dz) Dx Dy Dz . 0 0", 0.7f},
                                                   {"void prism2 surf 9 .3 0 0 -1 .2 0 0 1 . 0 0", 0.3f}};
    for (const auto& [material, want] : cases) {
        const std::vector<float> img = over_glow_floor(*this, material, 4);
        for (size_t i = 0; i < img.size(); ++i) EXPECT_NEAR(img[i], want, 1e-5) << material << ", value " << i;
    }
}

TEST_F(RadiancePatterns, AMixtextsVoidPartIsSeenThrough) {
    // A glow of radiance 2 inside the letter, void (the floor's 1 seen through) outside: one
    // 'I' 5 wide, its bar (font x 100..150 of 255) at x -0.539..0.441, over all of the view's y.
    std::ofstream(path("test.fnt")) << "73 4  100 48  150 48  150 200  100 200\n";
    const int n = 16;
    const std::vector<float> img = over_glow_floor(*this, "void glow two 0 0 4 2 2 2 0\n"
                                                   "void mixtext surf 5 two void test.fnt . I 0 9 -2.5 2.5 0  5 0 0  0 -5 0", n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float v = img[3 * (static_cast<size_t>(y) * n + static_cast<size_t>(x))];
            if (x >= 4 && x <= 10) {
                EXPECT_NEAR(v, 2.0f, 1e-5) << x << ", " << y;
            } else if (x <= 2 || x >= 12) {
                EXPECT_NEAR(v, 1.0f, 1e-5) << x << ", " << y;
            }
        }
    // The text (font, lines, layout) travels in crex's JSON.
    const Scene s = load("t.rad", "void glow two 0 0 4 2 2 2 0\nvoid mixtext surf 5 two void test.fnt . I 0 9 -2.5 2.5 0  5 0 0  0 -5 0\n"
                                  "surf polygon plane 0 0 12 -5 -5 0 5 -5 0 5 5 0 -5 5 0\n");
    auto back = testing::load_json_text(scene_to_json(s).dump());
    std::string why;
    for (const auto& d : back.diagnostics) why += d.code + " " + d.message + "\n";
    ASSERT_TRUE(back.scene) << why;
    const Material* m = s.find_material("surf");
    ASSERT_TRUE(m && m->mixture);
    EXPECT_EQ(m->mixture->coefficient.text, std::vector<std::string>{"I"});
    EXPECT_EQ(back.scene->find_material("surf")->mixture, m->mixture);
}

TEST_F(RadiancePatterns, AnAntimattersSolidCutsAHoleThroughTheMaterialsItNames) {
    // A slab of glow 3 (4 x 4, 0.5 thick) over a floor of glow 1, seen from above through a
    // parallel view 4 wide; an antimatter cylinder of radius 1 through the slab removes the
    // slab inside it, its own surfaces unseen: the floor shows through a disk of area pi, the
    // image's mean 3 - 2 pi / 16.
    const std::string text = "#@crex view -vtl -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 4 -vv 4\n"
                             "void glow floorglow 0 0 4 1 1 1 0\n"
                             "floorglow polygon floor 0 0 12 -10 -10 -1 10 -10 -1 10 10 -1 -10 10 -1\n"
                             "void glow wall 0 0 4 3 3 3 0\n!genbox wall slab 4 4 .5 | xform -t -2 -2 0\n"
                             "void antimatter hole 1 wall 0 0\nhole cylinder bore 0 0 7 0 0 -.2 0 0 .7 1\n"
                             "hole ring top 0 0 8 0 0 .7 0 0 1 0 1\nhole ring bottom 0 0 8 0 0 -.2 0 0 -1 0 1\n";
    const int n = 32;
    const std::vector<float> img = testing::render_crex(load("am.rad", text), "", n, 4).image();
    EXPECT_NEAR(testing::mean_luminance(img), 3 - 2 * kPi / 16, 0.01);
    EXPECT_FLOAT_EQ(img[3 * (static_cast<size_t>(n / 2) * n + n / 2)], 1.0f);  // the middle: the floor
    EXPECT_FLOAT_EQ(img[0], 3.0f);                                             // a corner: the slab
    // The antimatter travels in crex's JSON with the names of what it clips.
    auto back = testing::load_json_text(scene_to_json(load("am.rad", text)).dump());
    ASSERT_TRUE(back.scene);
    ASSERT_TRUE(back.scene->find_material("hole"));
    EXPECT_EQ(back.scene->find_material("hole")->clips, std::vector<std::string>{"wall"});
}

}  // namespace
}  // namespace crex
