// RADIANCE's light sources, surfaces and views as crex renders them (issue 39), against closed
// forms: a wall with a hole joined by a seam lights exactly its area (not the hole's), the
// sun and gensky's CIE skies give a horizontal surface the illuminance of their published
// formulas, a spotlight lights only its cone, a glow of negative radius lights nothing, an
// illum lights as a lamp while rays see its alternate material, the anisotropic Ward lobe's
// samples agree with its evaluation, and shadow rays cross thin glass as RADIANCE's do.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/render/bsdf.h"
#include "runtime/render/light_visibility.h"
#include "runtime/render/render_scene.h"
#include "runtime/scene/sky_model.h"
#include "tests/support/scene_helpers.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

Scene load(const std::string& text) {
    auto r = testing::load_rad_text(text);
    if (!r.scene) throw std::runtime_error(r.diagnostics.empty() ? "no scene" : r.diagnostics[0].message);
    return *r.scene;
}

double channel_sum(const std::vector<float>& img, size_t c) {
    double s = 0;
    for (size_t i = c; i < img.size(); i += 3) s += img[i];
    return s;
}

TEST(RadianceSeamPolygon, LightsItsAreaNotItsHole) {
    // A 1 x 1 glowing wall with a 0.4 x 0.4 hole, written as RADIANCE writes holes: the outline,
    // a seam in, the hole the other way round, the seam out. A parallel view 1.25 wide: the
    // image's sum times a pixel's area is the lit area, 1 - 0.16 = 0.84 (the hole filled in, as
    // before crex read seams, would have given 1).
    Scene s = load(R"(#@crex view -vtl -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 1.25 -vv 1.25
void glow paint 0 0 4 1 1 1 0
paint polygon wall 0 0 30
  -.5 -.5 0   .5 -.5 0   .5 .5 0   -.5 .5 0   -.5 -.5 0
  -.2 -.2 0  -.2 .2 0    .2 .2 0    .2 -.2 0  -.2 -.2 0
)");
    const int n = 64;
    RunResult r = testing::render_crex(s, "", n, 16);
    std::vector<float> img = r.image();
    const double pixel_area = (1.25 / n) * (1.25 / n);
    EXPECT_NEAR(channel_sum(img, 1) * pixel_area, 0.84, 0.84 * 0.01);
    // The hole's centre is dark, the wall's corner region lit.
    EXPECT_EQ(img[3 * (n / 2 * n + n / 2) + 1], 0.0f);
    EXPECT_NEAR(img[3 * (n / 8 * n + n / 8) + 1], 1.0f, 1e-6);
}

// A white floor at z = 0 (albedo rho) seen from above through a narrow view, lit by what the
// text adds; the image is the floor's radiance rho E / pi.
std::string floor_scene(double rho, const std::string& lights) {
    return "#@crex view -vp 0 0 1 -vd 0 0 -1 -vu 0 1 0 -vh 2 -vv 2\n"
           "void plastic floor 0 0 5 " + std::to_string(rho) + " " + std::to_string(rho) + " " + std::to_string(rho) + " 0 0\n"
           "floor polygon ground 0 0 12 -100 -100 0 100 -100 0 100 100 0 -100 100 0\n" + lights;
}

double floor_irradiance(const std::string& lights, double rho, uint32_t shadow_rays = 16) {
    Scene s = load(floor_scene(rho, lights));
    RunResult r = testing::render_crex(s, "", 16, 16, 0, shadow_rays);
    return testing::mean_luminance(r.image()) * kPi / rho;
}

TEST(RadianceSky, TheSunGivesTheHorizontalIlluminanceOfItsSolidAngle) {
    // A sun of radiance L and 0.5 degree diameter at altitude 40: E = L * omega * sin(40),
    // omega = 2 pi (1 - cos 0.25 deg).
    const double L = 1000, alt = 40 * kPi / 180;
    const std::string sun = fmt::format("void light solar 0 0 3 {0} {0} {0}\nsolar source sun 0 0 4 0 {1} {2} 0.5\n", L, -std::cos(alt),
                                        std::sin(alt));
    const double omega = 2 * kPi * (1 - std::cos(0.25 * kPi / 180));
    EXPECT_NEAR(floor_irradiance(sun, 0.5) / (L * omega * std::sin(alt)), 1.0, 0.005);
}

TEST(RadianceSky, GenskyOvercastSkyGivesSevenNinthsPiTimesItsZenith) {
    // CIE overcast sky (Moon and Spencer): L(theta) = Lz (1 + 2 cos theta) / 3, so a
    // horizontal surface receives E = 7 pi / 9 Lz. gensky -c -b 10: zenith radiance 10.
    const std::string sky = "!gensky 3 21 12 -c -b 10 -g 0\n"
                            "skyfunc glow sky_mat 0 0 4 1 1 1 0\nsky_mat source sky 0 0 4 0 0 1 180\n";
    EXPECT_NEAR(sky_horizontal_irradiance({SkyModel::Type::kOvercast, 10, 0, 1, {0, 0, 1}}) / (7 * kPi / 9 * 10), 1.0, 1e-4);
    EXPECT_NEAR(floor_irradiance(sky, 0.5) / (7 * kPi / 9 * 10), 1.0, 0.01);
}

TEST(RadianceSky, GenskyClearSkyMatchesItsPublishedHorizontalIlluminance) {
    // The CIE clear sky has no closed form; gensky's fit of its horizontal illuminance (a
    // polynomial in the sun's altitude) divided by its zenith normalisation F2 gives E / Lz.
    // crex's sky, integrated numerically and rendered, must agree with it.
    for (double alt_deg : {15.0, 30.0, 50.0, 70.0}) {
        const double alt = alt_deg * kPi / 180, x = (alt - kPi / 4) / (kPi / 4);
        const double fit = 2.766521 + x * (0.547665 + x * (-0.369832 + x * (0.009237 + x * 0.059229)));
        const Vec3 sun{0, -std::cos(alt), std::sin(alt)};
        SkyModel sky{SkyModel::Type::kClear, 1, 0, sky_normalization(SkyModel::Type::kClear, sun), sun};
        EXPECT_NEAR(sky_horizontal_irradiance(sky) / (fit / sky.normalization), 1.0, 0.005) << alt_deg;
    }
    // gensky -ang 50 0 -s -b 5: no sun, a clear sky of zenith radiance 5 at altitude 50.
    const double alt = 50 * kPi / 180, x = (alt - kPi / 4) / (kPi / 4);
    const double fit = 2.766521 + x * (0.547665 + x * (-0.369832 + x * (0.009237 + x * 0.059229)));
    const double f2 = sky_normalization(SkyModel::Type::kClear, {0, -std::cos(alt), std::sin(alt)});
    const std::string sky = "!gensky -ang 50 0 -s -b 5 -g 0\n"
                            "skyfunc glow sky_mat 0 0 4 1 1 1 0\nsky_mat source sky 0 0 4 0 0 1 180\n";
    EXPECT_NEAR(floor_irradiance(sky, 0.5) / (5 * fit / f2), 1.0, 0.02);
}

TEST(RadianceSky, GenskyPutsTheNoonSunAtNinetyDegreesLessTheLatitude) {
    // 21 March at solar noon ("+12"): the declination is about -0.4 degrees (gensky's fit),
    // so at latitude 40 the sun stands at 49.6 degrees, due south (-y).
    auto r = testing::load_rad_text("!gensky 3 21 +12 -a 40 -o 0 -m 0\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_EQ(r.scene->distant_lights.size(), 1u);  // the sun (the sky's brightfunc is used by no source)
    const Vec3 d = normalize_or_zero(r.scene->distant_lights[0].direction);
    EXPECT_NEAR(std::asin(d.z) * 180 / kPi, 90 - 40 - 0.404, 0.05);
    EXPECT_NEAR(d.x, 0, 1e-9);
    EXPECT_LT(d.y, 0);
}

TEST(RadianceLights, ASpotlightLightsItsConeOnly) {
    // A small disc (radius a = 0.05, radiance 100) 1 above the floor aiming straight down with
    // a 60 degree cone and its focus 0.001 behind it: under it E = pi L a^2 / (1 + a^2) for the
    // disc (its 48-gon has 0.99715 of the area), falling off as from the focus; a point 2 away
    // (63 degrees off the axis) is outside the cone and dark.
    const std::string spot = "void spotlight beam 0 0 7 100 100 100 60 0 0 -.001\nbeam ring lamp 0 0 8 0 0 1 0 0 -1 0 .05\n";
    const double a = 0.05, expected = kPi * 100 * a * a / (1 + a * a) * 0.99715 / (1.001 * 1.001);
    EXPECT_NEAR(floor_irradiance(spot, 0.5) / expected, 1.0, 0.01);
    Scene s = load(floor_scene(0.5, spot));
    s.camera.position = {2, 0, 1};
    RunResult r = testing::render_crex(s, "", 8, 4, 0, 4);
    EXPECT_EQ(testing::mean_luminance(r.image()), 0.0);
}

TEST(RadianceLights, ANegativeGlowIsSeenButLightsNothing) {
    // A bright bulb 0.3 above the floor, beside the narrow view: a glow of radius -1 lights
    // nothing (RADIANCE: "never contributes to scene illumination"), yet the camera sees it.
    const std::string glow = "void glow bulb_mat 0 0 4 5 5 5 -1\nbulb_mat sphere bulb 0 0 4 .5 0 .3 .1\n";
    EXPECT_EQ(floor_irradiance(glow, 0.5, 4), 0.0);
    Scene s = load(floor_scene(0.5, glow));
    s.camera.position = {.5, 0, 1};
    s.camera.vfov_deg = s.camera.hfov_deg = 1;  // looking down at the bulb itself
    RunResult r = testing::render_crex(s, "", 8, 4);
    EXPECT_NEAR(testing::mean_luminance(r.image()), 5.0, 1e-4);
}

TEST(RadianceLights, AnIllumLightsLikeALampAndShowsItsAlternate) {
    // An illum square (radiance 3, half side 0.5, height 1.5) with a glass alternate: the floor
    // receives the square's irradiance, though rays meet only glass there.
    const std::string illum = "void glass pane 0 0 3 .9 .9 .9\nvoid illum window 1 pane 0 3 3 3 3\n"
                              "window polygon w 0 0 12 -.5 -.5 1.5 -.5 .5 1.5 .5 .5 1.5 .5 -.5 1.5\n";
    const double expected = testing::irradiance_under_square(3, 0.5, 1.5);
    EXPECT_NEAR(floor_irradiance(illum, 0.5) / expected, 1.0, 0.01);
    auto r = testing::load_rad_text(floor_scene(0.5, illum));
    ASSERT_TRUE(r.scene);
    EXPECT_EQ(r.scene->find_material("window")->alternate, "pane");
}

TEST(RadianceLights, AnIllumWindowLightsOnceNotAgainThroughItsGlass) {
    // The same illum window under a sky of radiance 1 (a distant glow over the upper
    // hemisphere), rendered with one diffuse bounce and then a transmission: the floor gets
    // the illum's irradiance and the sky's except where the window hides it (shadow rays
    // stop at its glass). A bounce meeting the window from the front takes nothing (RADIANCE
    // discards it: the illum is the window's light); going on through the glass to the sky,
    // as it did, counted the window twice, 0.9 x 0.35 more here.
    const std::string lights = "void glass pane 0 0 3 .9 .9 .9\nvoid illum window 1 pane 0 3 3 3 3\n"
                               "window polygon w 0 0 12 -.5 -.5 1.5 -.5 .5 1.5 .5 .5 1.5 .5 -.5 1.5\n"
                               "void glow skyglow 0 0 4 1 1 1 0\nskyglow source sky 0 0 4 0 0 1 180\n";
    const double window = testing::irradiance_under_square(1, 0.5, 1.5);
    const double expected = testing::irradiance_under_square(3, 0.5, 1.5) + (kPi - window);
    Scene s = load(floor_scene(0.5, lights));
    RunResult r = testing::render_crex(s, "DT", 16, 16, 0, 16);
    EXPECT_NEAR(testing::mean_luminance(r.image()) * kPi / 0.5 / expected, 1.0, 0.02);
}

TEST(RadianceViews, EachProjectionMapsTheImageAsRadianceDefinesIt) {
    // Looking down -z, right is +x. At the middle of the right edge of an image whose field
    // across is 180 degrees, every fisheye looks 90 degrees off the axis; the cylinder of 360
    // looks straight back; a parallel view 4 wide starts its ray 2 to the right.
    auto ray = [](Projection p, double hfov, double vfov, double px, double py, Vec3& o, Vec3& d) {
        Camera c;
        c.position = {0, 0, 0};
        c.direction = {0, 0, -1};
        c.up = {0, 1, 0};
        c.projection = p;
        c.hfov_deg = hfov, c.vfov_deg = vfov;
        return CameraRays(c, 100, 100, {0, 0, 0}).generate(px, py, o, d);
    };
    Vec3 o, d;
    for (Projection p : {Projection::kAngular, Projection::kHemispherical, Projection::kStereographic}) {
        ASSERT_TRUE(ray(p, 180, 180, 100, 50, o, d));
        EXPECT_NEAR(d.x, 1, 1e-9);
        EXPECT_NEAR(d.z, 0, 1e-9);
        ASSERT_TRUE(ray(p, 180, 180, 50, 50, o, d));  // the centre looks along the view
        EXPECT_NEAR(d.z, -1, 1e-12);
    }
    // Half way out, each fisheye's own law: angle, sine and tangent of half the angle.
    ASSERT_TRUE(ray(Projection::kAngular, 180, 180, 75, 50, o, d));
    EXPECT_NEAR(std::acos(-d.z), kPi / 4, 1e-9);
    ASSERT_TRUE(ray(Projection::kHemispherical, 180, 180, 75, 50, o, d));
    EXPECT_NEAR(std::sin(std::acos(-d.z)), 0.5, 1e-9);
    ASSERT_TRUE(ray(Projection::kStereographic, 180, 180, 75, 50, o, d));
    EXPECT_NEAR(std::tan(std::acos(-d.z) / 2), 0.5, 1e-9);
    // A hemispherical fisheye has no ray beyond 90 degrees: its 180-degree image's corners;
    // an angular one has none beyond 180 (its corners when it spans 360), as RADIANCE's.
    EXPECT_FALSE(ray(Projection::kHemispherical, 180, 180, 100, 100, o, d));
    EXPECT_TRUE(ray(Projection::kAngular, 180, 180, 0, 0, o, d));
    EXPECT_NEAR(std::acos(-d.z), kPi / 2 * std::sqrt(2.0), 1e-9);
    EXPECT_FALSE(ray(Projection::kAngular, 360, 360, 0, 0, o, d));
    // A square image of a 360-degree panorama: tan(vfov / 2) = pi keeps its pixels square.
    ASSERT_TRUE(ray(Projection::kCylindrical, 360, 2 * std::atan(kPi) * 180 / kPi, 100, 50, o, d));
    EXPECT_NEAR(d.z, 1, 1e-9);
    ASSERT_TRUE(ray(Projection::kParallel, 4, 4, 100, 50, o, d));
    EXPECT_NEAR(o.x, 2, 1e-12);
    EXPECT_EQ(d, (Vec3{0, 0, -1}));
}

TEST(RadianceViews, PixelsOutsideAFisheyeAreBlack) {
    // A 180-degree hemispherical fisheye inside a glowing sphere: the circle is lit, the
    // corners are black, and the lit share of the image is the circle's, pi / 4.
    Scene s = load("#@crex view -vth -vp 0 0 0 -vd 0 0 -1 -vu 0 1 0 -vh 180 -vv 180\nvoid glow g 0 0 4 1 1 1 0\ng bubble b 0 0 4 0 0 0 10\n");
    RunResult r = testing::render_crex(s, "", 64, 16);
    std::vector<float> img = r.image();
    EXPECT_EQ(img[0], 0.0f);
    EXPECT_NEAR(channel_sum(img, 1) / (64 * 64), kPi / 4, 0.01);
}

TEST(RadianceViews, HiddenBackFacesLetTheViewInAndStillCastShadows) {
    // RADIANCE's -bv-: a roof over the left half of a floor, facing the floor, seen from above
    // by a parallel view, under a sun at the zenith (E = L omega). With back faces visible the
    // left half is the roof's top, lit by the sun: 0.1 E / pi. Hidden, the view goes through it
    // to the floor, which the roof still shades: dark but for light the floor sends back via
    // the roof's underside; the sunlit right half is 0.5 E / pi either way.
    const double L = 1000, omega = 2 * kPi * (1 - std::cos(0.25 * kPi / 180)), E = L * omega;
    std::string text = fmt::format(R"(#@crex view -vtl -vp 0 0 1 -vd 0 0 -1 -vu 0 1 0 -vh 2 -vv 2
void light solar 0 0 3 {0} {0} {0}
solar source sun 0 0 4 0 0 1 0.5
void plastic floor 0 0 5 .5 .5 .5 0 0
void plastic roof 0 0 5 .1 .1 .1 0 0
floor polygon ground 0 0 12 -100 -100 0 100 -100 0 100 100 0 -100 100 0
roof polygon cover 0 0 12 -100 -100 .5 -100 100 .5 0 100 .5 0 -100 .5
)", L);
    const int n = 32;
    auto halves = [&](bool visible) {
        Scene s = load(text);
        s.back_faces_visible = visible;
        const std::vector<float> img = testing::render_crex(s, "", n, 8, 0, 16).image();
        std::pair<double, double> sum{0, 0};  // quarters away from the shadow's edge
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n / 4; ++x) sum.first += img[3 * (y * n + x) + 1], sum.second += img[3 * (y * n + n - 1 - x) + 1];
        return std::pair<double, double>{sum.first / (n * n / 4), sum.second / (n * n / 4)};
    };
    const auto [roof_top, lit_floor] = halves(true);
    EXPECT_NEAR(roof_top / (0.1 * E / kPi), 1.0, 0.02);
    EXPECT_NEAR(lit_floor / (0.5 * E / kPi), 1.0, 0.03);
    const auto [shaded_floor, lit_floor_too] = halves(false);
    EXPECT_LT(shaded_floor, 0.05 * lit_floor_too);
    EXPECT_NEAR(lit_floor_too / (0.5 * E / kPi), 1.0, 0.03);
    // A BRTDfunc roof keeps its back (RADIANCE's m_brdf.c has no -bv test): its back's diffuse
    // reflectance .1 is seen either way.
    text.replace(text.find("void plastic roof 0 0 5 .1 .1 .1 0 0"), 36, "void BRTDfunc roof 10 0 0 0 0 0 0 0 0 0 . 0 9 .3 .3 .3 .1 .1 .1 0 0 0");
    EXPECT_NEAR(halves(false).first / (0.1 * E / kPi), 1.0, 0.02);
}

TEST(RadianceMaterials, ADielectricsColourIsPerUnitLength) {
    // RADIANCE's dielectric (and interface) colours are transmissions per unit length: a slab
    // 0.5 thick of colour 0.25 (index 1, so no Fresnel loss) passes 0.25^0.5 = 0.5 of the glow
    // behind it, not 0.25 at each face.
    Scene s = load(R"(#@crex view -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 5 -vv 5
void glow back 0 0 4 1 1 1 0
back polygon wall 0 0 12 -9 -9 -5 9 -9 -5 9 9 -5 -9 9 -5
void dielectric tint 0 0 5 .25 .25 .25 1 0
!genbox tint slab 4 4 .5 | xform -t -2 -2 0
)");
    RunResult r = testing::render_crex(s, "(TR)*", 8, 4);
    EXPECT_NEAR(testing::mean_luminance(r.image()), 0.5, 1e-3);
}

TEST(RadianceMaterials, TheAnisotropicWardLobeSamplesWhatItEvaluates) {
    // The lobe's mean sampled weight (its albedo towards the view) against the integral of its
    // evaluation over the hemisphere: they estimate the same number, so they must agree.
    Material m;
    m.type = MaterialType::kMetal;
    m.color = {1, 1, 1};
    m.specularity = 1;
    m.roughness = 0.3;
    m.anisotropy = Anisotropy{{1, 0, 0}, 0.1};
    Bsdf b = Bsdf::of(m);
    ASSERT_TRUE(b.anisotropic);
    HitFrame f;
    f.normal = f.geometric = f.shading = {0, 0, 1};
    f.incoming = normalize_or_zero(Vec3{0.4, 0.3, -1});
    double sampled = 0;
    const int n = 200000;
    std::array<Lobe, kMaxLobes> lobes;
    for (int i = 0; i < n; ++i) {
        int k = scatter(b, f, HitRandom(static_cast<uint64_t>(i) * 7919u, 0), lobes);
        for (int l = 0; l < k; ++l)
            if (lobes[static_cast<size_t>(l)].component == Component::kG) sampled += lobes[static_cast<size_t>(l)].weight.x;
    }
    sampled /= n;
    // By quadrature of the evaluation: f cos over the hemisphere.
    double integral = 0;
    const int nt = 400, np = 800;
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j) {
            const double z = (i + 0.5) / nt, r = std::sqrt(1 - z * z), phi = 2 * kPi * (j + 0.5) / np;
            integral += eval_direct(b, f, {r * std::cos(phi), r * std::sin(phi), z}).x;
        }
    integral *= 2 * kPi / (nt * np);
    EXPECT_GT(sampled, 0.5);
    EXPECT_NEAR(sampled / integral, 1.0, 0.01);
}

TEST(RadianceMaterials, GlassIsAThinPaneWithItsPublishedTransmittance) {
    // glass.c: transmissivity 0.96 is "standard 88% transmittance glass" at normal incidence;
    // the ray leaves in the direction it came, at any angle.
    Scene s = load(R"(void glass pane 0 0 3 .96 .96 .96
pane polygon p 0 0 12 -1 -1 0 1 -1 0 1 1 0 -1 1 0
)");
    ASSERT_FALSE(s.materials.empty());
    const Material& m = s.materials.back();
    ASSERT_EQ(m.type, MaterialType::kGlass);
    EXPECT_TRUE(m.thin_glass);
    Bsdf b = Bsdf::of(m);
    std::array<Lobe, kMaxLobes> lobes;
    for (const Vec3 incoming : {Vec3{0, 0, -1}, normalize_or_zero(Vec3{0.8, 0.3, -0.5})}) {
        HitFrame f;
        f.normal = f.geometric = f.shading = {0, 0, 1};
        f.incoming = incoming;
        const int k = scatter(b, f, HitRandom(1, 0), lobes);
        double transmitted = -1, reflected = -1;
        for (int l = 0; l < k; ++l) {
            const Lobe& lobe = lobes[static_cast<size_t>(l)];
            if (lobe.component == Component::kT) {
                transmitted = lobe.weight.x;
                EXPECT_NEAR(length(lobe.direction - incoming), 0, 1e-12) << "a pane does not bend the ray";
            } else if (lobe.component == Component::kR) {
                reflected = lobe.weight.y;
                EXPECT_NEAR(dot(lobe.direction, f.normal), -dot(incoming, f.normal), 1e-12);
            }
        }
        if (incoming.z == -1) {
            // (1-r)^2 t / (1 - r^2 t^2) with r = ((1.52-1)/(1.52+1))^2, t = 0.96; reflection
            // r (1 + (1-2r) t^2) / (1 - r^2 t^2).
            const double r = std::pow(0.52 / 2.52, 2), t = 0.96;
            EXPECT_NEAR(transmitted, (1 - r) * (1 - r) * t / (1 - r * r * t * t), 1e-12);
            EXPECT_NEAR(transmitted, 0.88, 0.002);
            EXPECT_NEAR(reflected, r * (1 + (1 - 2 * r) * t * t) / (1 - r * r * t * t), 1e-12);
        } else {
            EXPECT_GT(transmitted, 0.5);
            EXPECT_LT(transmitted + reflected, 0.96 + 1e-9);  // the pane absorbs more along a slant
        }
    }
}

TEST(RadianceMaterials, ThingsBehindAGlassPaneStayWhereTheyAre) {
    // A small bright patch behind a pane tilted 45 degrees to the view: RADIANCE's glass lets
    // the camera see it where it is (a refracting surface would shift it sideways).
    const std::string behind = R"(#@crex view -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 20 -vv 20
void glow bright 0 0 4 10 10 10 0
bright polygon patch 0 0 12 -.2 -.2 -3 .2 -.2 -3 .2 .2 -3 -.2 .2 -3
)";
    const std::string pane = "void glass pane 0 0 3 .96 .96 .96\npane polygon p 0 0 12 -1 -1 -1 1 -1 1 1 1 1 -1 1 -1\n";
    RunResult open = testing::render_crex(load(behind), "(TR)*", 32, 1);
    RunResult glazed = testing::render_crex(load(behind + pane), "(TR)*", 32, 1);
    auto centroid_x = [](const std::vector<float>& rgb) {
        double sum = 0, at = 0;
        for (size_t p = 0; p < rgb.size() / 3; ++p)
            if (rgb[3 * p + 1] > 1) sum += 1, at += double(p % 32);
        return sum > 0 ? at / sum : -1.0;
    };
    const double x_open = centroid_x(open.image()), x_glazed = centroid_x(glazed.image());
    ASSERT_GT(x_open, 0);
    EXPECT_NEAR(x_glazed, x_open, 0.25) << "the patch moved by " << x_glazed - x_open << " pixels";
}

// A sun of radiance 1000 and 0.5 degree diameter straight overhead, and a 100 x 100 pane of
// standard glass (transmissivity 0.96) at height 2, above the view.
const std::string kZenithSun = "void light solar 0 0 3 1000 1000 1000\nsolar source sun 0 0 4 0 0 1 0.5\n";
const std::string kHighPane = "void glass pane 0 0 3 .96 .96 .96\npane polygon p 0 0 12 -50 -50 2 50 -50 2 50 50 2 -50 50 2\n";
const double kSunIrradiance = 1000 * 2 * kPi * (1 - std::cos(0.25 * kPi / 180));
// glass.c's transmittance at normal incidence: (1-r)^2 t / (1 - r^2 t^2), r = (0.52/2.52)^2, t = 0.96.
const double kPaneAtNormal = std::pow(1 - std::pow(0.52 / 2.52, 2), 2) * 0.96 / (1 - std::pow(0.52 / 2.52, 4) * 0.96 * 0.96);

TEST(RadianceGlassShadows, TheSunLightsTheFloorThroughAPaneByItsTransmittance) {
    // RADIANCE's glass passes shadow rays (glass.c): the sun through the pane gives the floor
    // E T. Before, a pane blocked every shadow ray and the sun reached the floor only along
    // paths that found it by chance (a sharp sun patch became scattered fireflies).
    EXPECT_NEAR(floor_irradiance(kZenithSun, 0.5) / kSunIrradiance, 1.0, 0.005);
    EXPECT_NEAR(floor_irradiance(kZenithSun + kHighPane, 0.5) / (kSunIrradiance * kPaneAtNormal), 1.0, 0.005);
}

TEST(RadianceGlassShadows, AClearTransScreenPassesTheSunARoughOneDoesNot) {
    // normal.c passes shadow rays through a trans surface's specular transmission only when it
    // is pure (roughness 0): a screen transmitting half the light specularly gives the floor
    // E / 2 when clear, and no direct sun when rough (its light then comes by sampled rays;
    // before, a rough screen passed the sun too, as a sharp patch RADIANCE does not show).
    auto screen = [](double roughness) {
        return fmt::format("void trans screen 0 0 7 1 1 1 0 {} .5 1\nscreen polygon s 0 0 12 -50 -50 2 50 -50 2 50 50 2 -50 50 2\n", roughness);
    };
    EXPECT_NEAR(floor_irradiance(kZenithSun + screen(0), 0.5) / (kSunIrradiance * 0.5), 1.0, 0.005);
    // (A shadow ray exactly along the screen's diagonal, between its two triangles, may slip
    // through: Embree's traversal is not watertight by default.)
    EXPECT_LT(floor_irradiance(kZenithSun + screen(0.1), 0.5), 1e-3 * kSunIrradiance);
}

TEST(RadianceGlassShadows, ABounceGoingOnThroughThePaneDoesNotCountTheSunAgain) {
    // With D and T rays: a diffuse bounce from the floor that goes on through the pane and
    // escapes would meet the sun direct lighting already brought through the pane. It must
    // see the sun as its diffuse parent does (not at all), so the floor stays at E T (R rays,
    // the pane's reflection back down, are not run).
    Scene s = load(floor_scene(0.5, kZenithSun + kHighPane));
    RunResult r = testing::render_crex(s, "(DT)*", 16, 16, 0, 4);
    EXPECT_NEAR(testing::mean_luminance(r.image()) * kPi / 0.5 / (kSunIrradiance * kPaneAtNormal), 1.0, 0.01);
}

TEST(RadianceGlassShadows, AnIllumLetsTheSunThroughButNotTheSky) {
    // RADIANCE's illumblock: an illum stands for the light of what lies behind it, so it blocks
    // shadow rays aimed at glows (the sky) and lets those aimed at a `light` (the sun) through
    // as its alternate glass. Under a 4000 x 4000 illum (of radiance 0, so that only what it
    // lets through is seen; 2 above the floor, it leaves the sky below 0.06 degrees of the
    // horizon, under 1e-4 of the sun) the floor gets the sun through the glass and no sky (a sky of
    // radiance 1 would add pi, 50 times the sun).
    const std::string window = "void glass pane 0 0 3 .96 .96 .96\nvoid illum window 1 pane 0 3 0 0 0\n"
                               "window polygon w 0 0 12 -2000 -2000 2 -2000 2000 2 2000 2000 2 2000 -2000 2\n"
                               "void glow skyglow 0 0 4 1 1 1 0\nskyglow source sky 0 0 4 0 0 1 180\n";
    EXPECT_NEAR(floor_irradiance(kZenithSun + window, 0.5) / (kSunIrradiance * kPaneAtNormal), 1.0, 0.005);
}

TEST(RadianceGlassShadows, ASkyNoSurfaceInViewCanSeeTakesFewShadowRays) {
    // Inside a closed room, a sky outside reaches none of the surfaces in view: its share of
    // shadow rays falls from nearly all (its solid angle outweighs the lamp's) to almost none.
    // The room's floor, lit by a 0.4 x 0.4 lamp of radiance 10 on its ceiling, then renders
    // as it does without the sky (before: about 1 shadow ray in 40 went to the lamp, and the
    // floor was grain). Under the open sky, the fraction is about 1.
    const std::string sky = "void glow skyglow 0 0 4 1 1 1 0\nskyglow source sky 0 0 4 0 0 1 180\n";
    const std::string room = R"(#@crex view -vp 0 0 1 -vd 0 0 -1 -vu 0 1 0 -vh 60 -vv 60
void plastic wall 0 0 5 .5 .5 .5 0 0
wall polygon floor 0 0 12 -2 -2 0 2 -2 0 2 2 0 -2 2 0
wall polygon ceiling 0 0 12 -2 -2 2 -2 2 2 2 2 2 2 -2 2
wall polygon w1 0 0 12 -2 -2 0 -2 2 0 -2 2 2 -2 -2 2
wall polygon w2 0 0 12 2 -2 0 2 -2 2 2 2 2 2 2 0
wall polygon w3 0 0 12 -2 -2 0 -2 -2 2 2 -2 2 2 -2 0
wall polygon w4 0 0 12 -2 2 0 2 2 0 2 2 2 -2 2 2
void light lamp 0 0 3 10 10 10
lamp polygon l 0 0 12 -.2 -.2 1.99 -.2 .2 1.99 .2 .2 1.99 .2 -.2 1.99
)";
    Scene closed = load(room + sky);
    RenderScene rs(closed);
    const std::vector<double> inside = distant_visibility(rs, 32, 32);
    ASSERT_EQ(inside.size(), 1u);
    EXPECT_LT(inside[0], 0.01);
    const Scene open_scene = load(floor_scene(0.5, sky));  // RenderScene keeps a reference to it
    RenderScene open(open_scene);
    const std::vector<double> outside = distant_visibility(open, 32, 32);
    ASSERT_EQ(outside.size(), 1u);
    EXPECT_GT(outside[0], 0.95);
    const double with_sky = testing::mean_luminance(testing::render_crex(closed, "", 32, 4, 0, 1).image());
    const double without = testing::mean_luminance(testing::render_crex(load(room), "", 32, 4, 0, 1).image());
    EXPECT_NEAR(with_sky / without, 1.0, 0.03);
}

}  // namespace
}  // namespace crex
