// Textures against closed forms (issue 33):
//  - a textured diffuse plane under a uniform white sky is the texture's filtered value times
//    the analytic irradiance (pi, so radiance = albedo), within 1 %, with and without the
//    irradiance cache (whose records hold irradiance, the texture applied at lookup);
//  - a checkerboard at grazing angles at 1 spp does not alias (the pixel footprint filters it),
//    and does without the footprint, so the bound means something;
//  - an alpha cut-out casts the shadow of its opaque part only, is seen through by camera
//    rays, and lets irradiance-cache rays through; its opacity mask reads what the backend does;
//  - a flat normal map changes nothing, bit for bit;
//  - a missing texture is magenta, not grey;
//  - an image without tiles larger than the cache is read through a tiled copy, as it is whole;
//  - averaged hits read a coarse copy that gives a linear ramp back under every wrap mode.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "runtime/io/image_io.h"
#include "runtime/texture/surface_textures.h"
#include "runtime/texture/tiled_copies.h"
#include "tests/support/float_map.h"
#include "tests/support/scene_helpers.h"
#include "tests/support/test_scenes.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

fs::path scratch() { return testing::scratch_folder("crex_texture_render_"); }

// Writes an RGB image (float EXR, or 8-bit PNG whose bytes are round(255 v)).
std::string write_texture(const std::string& name, int w, int h, const std::vector<float>& rgb) {
    const std::string path = (scratch() / name).string();
    ImageLayer layer;
    layer.rgb = rgb;
    layer.display_referred = true;  // 8-bit formats store the values as they are
    const std::string error = write_image(path, w, h, {layer});
    if (!error.empty()) throw std::runtime_error(error);
    return path;
}

// A quad mesh with texture coordinates: corners a b c d counter-clockwise seen from the side
// it faces, (u, v) = (0, 0) at d ... the image's top-left at d, so the image lies upright
// when a is the bottom-left corner.
Shape uv_quad(const std::string& material, Vec3 a, Vec3 b, Vec3 c, Vec3 d, double repeat = 1) {
    Shape s;
    s.type = ShapeType::kMesh;
    s.material = material;
    s.vertices = {a, b, c, d};
    s.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.uvs = {{0, repeat}, {repeat, repeat}, {repeat, 0}, {0, 0}};
    return s;
}

TextureRef texture(const std::string& file) {
    TextureRef t;
    t.file = file;
    return t;
}

// Four quadrants of 4 x 4 texels each (an 8 x 8 texture): top-left, top-right, bottom-left,
// bottom-right.
const Vec3 kQuadrant[4] = {{0.2, 0.4, 0.6}, {0.8, 0.1, 0.3}, {0.5, 0.5, 0.5}, {0.9, 0.7, 0.2}};

std::vector<float> quadrant_texels() {
    std::vector<float> rgb(8 * 8 * 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const Vec3& c = kQuadrant[(y >= 4 ? 2 : 0) + (x >= 4 ? 1 : 0)];
            for (int k = 0; k < 3; ++k) rgb[size_t((y * 8 + x) * 3 + k)] = static_cast<float>(c[k]);
        }
    return rgb;
}

// A diffuse plane z = 0 (x, y in [-1, 1]) textured by `tex`, facing the camera at z = 2 whose
// view it exactly fills, under a white sky (radiance 1) and nothing else.
Scene plane_under_sky(const TextureRef& tex) {
    Scene s;
    Material m = testing::make_material("plane", MaterialType::kPlastic, {0.5, 0.5, 0.5});
    m.textures.color = tex;
    s.materials.push_back(m);
    s.shapes.push_back(uv_quad("plane", {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}));
    s.background = {1, 1, 1};
    s.camera.position = {0, 0, 2};
    s.camera.direction = {0, 0, -1};
    s.camera.vfov_deg = 2 * std::atan(0.5) * 180 / kPi;
    return s;
}

Vec3 pixel(const std::vector<float>& img, int size, int x, int y) {
    const size_t i = 3 * (size_t(y) * size_t(size) + size_t(x));
    return {img[i], img[i + 1], img[i + 2]};
}

TEST(TexturedPlane, UnderAWhiteSkyIsTheFilteredTextureTimesTheIrradiance) {
    // Irradiance from a sky of radiance 1 over the hemisphere: pi; radiance = albedo E / pi.
    // Each D ray escapes to the sky: its weight is the albedo exactly, so 1 spp suffices.
    const Scene s = plane_under_sky(texture(write_texture("quadrants.exr", 8, 8, quadrant_texels())));
    const int n = 32;
    RunResult r = testing::render_crex(s, "D", n, 1);
    const std::vector<float> img = r.image();
    ASSERT_TRUE(testing::all_finite(img));
    ASSERT_TRUE(r.textures.has_value());
    EXPECT_GT(r.textures->lookups, 0u);
    // Pixels well inside each quadrant (the filter sees one colour there): the quadrant's.
    for (int q = 0; q < 4; ++q)
        for (int y = 6; y < 10; ++y)
            for (int x = 6; x < 10; ++x) {
                const Vec3 p = pixel(img, n, x + (q % 2) * 16, y + (q / 2) * 16);
                for (int k = 0; k < 3; ++k) ASSERT_NEAR(p[k] / kQuadrant[q][k], 1.0, 0.01) << "quadrant " << q << " pixel " << x << "," << y;
            }
}

// Vertex colours (glTF's COLOR_0) multiply the material's colour, and its texture's where it
// has one: under the white sky each pixel is albedo times colour exactly (1 spp, as above).
TEST(VertexColours, MultiplyTheMaterialsColourAndItsTexture) {
    const Vec3 tint{0.9, 0.5, 0.25};
    const int n = 32;
    for (const bool textured : {false, true}) {
        Scene s = plane_under_sky(texture(write_texture("quadrants.exr", 8, 8, quadrant_texels())));
        if (!textured) s.materials[0].textures.color.reset();
        s.shapes[0].colors.assign(4, tint);
        const std::vector<float> img = testing::render_crex(s, "D", n, 1).image();
        ASSERT_TRUE(testing::all_finite(img));
        for (int q = 0; q < 4; ++q)
            for (int y = 6; y < 10; ++y)
                for (int x = 6; x < 10; ++x) {
                    const Vec3 p = pixel(img, n, x + (q % 2) * 16, y + (q / 2) * 16);
                    const Vec3 albedo = textured ? kQuadrant[q] : Vec3{0.5, 0.5, 0.5};
                    for (int k = 0; k < 3; ++k)
                        ASSERT_NEAR(p[k] / (albedo[k] * tint[k]), 1.0, 0.01) << (textured ? "textured" : "plain") << " quadrant " << q;
                }
    }
    // Colours that differ per vertex are interpolated across each triangle: black at one corner,
    // white at the others, the pixel beside the black corner is darker than the far one.
    Scene s = plane_under_sky(texture(""));
    s.materials[0].textures.color.reset();
    s.shapes[0].colors = {{0, 0, 0}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
    const std::vector<float> img = testing::render_crex(s, "D", n, 1).image();
    const double near_black = pixel(img, n, 0, n - 1)[1], far = pixel(img, n, n - 1, 0)[1];
    EXPECT_NEAR(far, 0.5, 0.01);
    EXPECT_LT(near_black, 0.05);
}

// A walk's frames are renders one after another in one process. Each render used to make and
// destroy a texture cache of its own, which crashed walks over textured scenes every few frames
// (inside OpenImageIO: the threads kept per-thread state of the cache they had used). Now
// their images share one cache for the process: the image is read once, later renders find its
// texels there and give the same image.
TEST(TextureCache, RendersOneAfterAnotherShareOneCacheAndReadEachImageOnce) {
    const Scene s = plane_under_sky(texture(write_texture("read_once.exr", 8, 8, quadrant_texels())));
    RunResult first = testing::render_crex(s, "D", 16, 1);
    ASSERT_TRUE(first.textures.has_value());
    EXPECT_GT(first.textures->cache.bytes_read, 0u);
    EXPECT_EQ(first.textures->cache.files, 1u);
    const std::vector<float> image = first.image();
    for (int frame = 1; frame < 12; ++frame) {
        RunResult r = testing::render_crex(s, "D", 16, 1);
        ASSERT_TRUE(r.textures.has_value());
        EXPECT_GT(r.textures->cache.queries, 0u) << frame;
        EXPECT_EQ(r.textures->cache.bytes_read, 0u) << frame;  // the texels were in the cache already
        EXPECT_EQ(r.textures->cache.files, 1u);
        ASSERT_EQ(r.image(), image) << frame;
    }
}

// A sequence builds its scene once and gives it to every frame (RunSettings::render_scene):
// the camera moves between frames, and the texture filter follows it (set_view() reads the
// camera again). A frame given the scene renders what a frame that builds its own does, bit for
// bit, and counts its own texture lookups only.
TEST(TextureCache, ARenderGivenASceneBuiltAlreadyIsTheRenderThatBuildsIt) {
    Scene s = plane_under_sky(texture(write_texture("shared_scene.exr", 8, 8, quadrant_texels())));
    const Camera near = s.camera;
    RunSettings o;
    o.width = o.height = 16;
    o.spp = 2;
    const sched::Program program = testing::lower_or_die("D");
    const RunResult own = render(s, program, o);
    s.camera.position = {0.3, -0.2, 3};  // the frame before, from elsewhere: another footprint
    RunSettings shared = o;
    shared.render_scene = std::make_shared<RenderScene>(s);
    const RunResult before = render(s, program, shared);
    s.camera = near;
    const RunResult given = render(s, program, shared);
    EXPECT_NE(before.image(), own.image());
    EXPECT_EQ(given.image(), own.image());
    ASSERT_TRUE(given.textures && own.textures);
    EXPECT_EQ(given.textures->lookups, own.textures->lookups) << "its own lookups, not the frame before's too";
    EXPECT_EQ(given.textures->cache.queries, own.textures->cache.queries);
    const Scene other = s;
    EXPECT_THROW(render(other, program, shared), std::logic_error) << "a scene built from another Scene object";
}

TEST(TexturedPlane, TheIrradianceCacheAppliesTheTextureAtLookup) {
    // Records hold irradiance; the texture multiplies it where each query is. A cache that
    // stored albedo times irradiance would blur the texture over each record's radius.
    const Scene s = plane_under_sky(texture(write_texture("quadrants_ic.exr", 8, 8, quadrant_texels())));
    const int n = 32;
    RunSettings o;
    o.width = o.height = n;
    o.spp = 1;
    RunResult without = render(s, testing::lower_or_die("D"), o);
    IcSettings ic;
    ic.divisions = 64;
    ic.caustic_photons = 0;
    o.irradiance_cache = ic;
    RunResult with = render(s, testing::lower_or_die("D"), o);
    ASSERT_GT(with.ic_stats.records, 0u);
    const std::vector<float> a = without.image(), b = with.image();
    // Every pixel, the quadrants' edges included.
    for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(b[i], a[i], 0.01 * a[i] + 1e-6) << "pixel " << i / 3;
}

TEST(TexturedPlane, EightBitColourTexturesAreDecodedFromSrgb) {
    // 188 / 255 in sRGB is 0.5029 linear (the sRGB curve undone for 8-bit colour textures).
    std::vector<float> rgb(4 * 4 * 3, 188.0f / 255.0f);
    const Scene s = plane_under_sky(texture(write_texture("grey188.png", 4, 4, rgb)));
    RunResult r = testing::render_crex(s, "D", 8, 1);
    const double expected = std::pow((188.0 / 255.0 + 0.055) / 1.055, 2.4);
    for (float v : r.image()) ASSERT_NEAR(v / expected, 1.0, 0.01);
}

// PNG's pieces, written by hand: a big-endian 32-bit number, and a chunk with its CRC.
std::string be32(uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

std::string png_chunk(const std::string& type, const std::string& data) {
    uint32_t c = 0xffffffffu;
    for (unsigned char b : type + data) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return be32(uint32_t(data.size())) + type + data + be32(c ^ 0xffffffffu);
}

// A 16-bit grey PNG of one value (stored deflate blocks: no zlib needed).
std::string write_png16(const std::string& name, int w, int h, uint16_t value) {
    std::string raw;
    for (int y = 0; y < h; ++y) {
        raw += '\0';  // no filter
        for (int x = 0; x < w; ++x) raw += char(value >> 8), raw += char(value & 0xff);
    }
    uint32_t a = 1, b = 0;  // Adler-32
    for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
    std::string deflate = "\x78\x01";
    for (size_t at = 0; at < raw.size(); at += 65535) {
        const size_t n = std::min<size_t>(65535, raw.size() - at);
        deflate += char(at + n == raw.size() ? 1 : 0);
        deflate += char(n & 0xff), deflate += char(n >> 8), deflate += char(~n & 0xff), deflate += char((~n >> 8) & 0xff);
        deflate += raw.substr(at, n);
    }
    deflate += be32((b << 16) | a);
    const std::string header = be32(uint32_t(w)) + be32(uint32_t(h)) + std::string{16, 0, 0, 0, 0};  // 16 bits, grey
    const std::string path = (scratch() / name).string();
    std::ofstream(path, std::ios::binary) << "\x89PNG\r\n\x1a\n" << png_chunk("IHDR", header) << png_chunk("IDAT", deflate) << png_chunk("IEND", "");
    return path;
}

// A PNG is sRGB-encoded at 16 bits as at 8 (the PNG spec; OpenImageIO says "sRGB"): a 16-bit
// colour texture used to be read as linear, 2.3 times too bright at half scale.
TEST(TexturedPlane, SixteenBitPngColourTexturesAreDecodedFromSrgbToo) {
    const Scene s = plane_under_sky(texture(write_png16("grey16.png", 4, 4, 32768)));
    std::vector<Diagnostic> warnings;
    SurfaceTextures textures(s, size_t{16} << 20, warnings);
    ASSERT_TRUE(warnings.empty()) << warnings[0].message;
    SurfacePoint p;
    p.u = p.v = 0.5;
    const double c = 32768.0 / 65535.0, expected = std::pow((c + 0.055) / 1.055, 2.4);
    EXPECT_NEAR(textures.values(0, p).color.x, expected, 1e-4);
}

// Every 8-bit value decodes to the sRGB curve's exact value (crex reads the curve's power
// from a table), read at its texel's centre.
TEST(TexturedPlane, EveryEightBitValueDecodesToTheSrgbCurve) {
    std::vector<float> rgb(256 * 3);
    for (int k = 0; k < 256; ++k) rgb[size_t(3 * k)] = rgb[size_t(3 * k + 1)] = rgb[size_t(3 * k + 2)] = float(k) / 255.0f;
    Scene s;
    Material m = testing::make_material("ramp", MaterialType::kPlastic, {0.5, 0.5, 0.5});
    m.textures.color = texture(write_texture("srgb_ramp.png", 256, 1, rgb));
    s.materials.push_back(m);
    std::vector<Diagnostic> warnings;
    SurfaceTextures textures(s, size_t{16} << 20, warnings);
    ASSERT_TRUE(warnings.empty());
    for (int k = 0; k < 256; ++k) {
        SurfacePoint p;
        p.u = (k + 0.5) / 256, p.v = 0.5;
        // The table's 1.0e-7 and the lookup's float arithmetic; a table one entry off errs by 1e-3.
        const double c = k / 255.0, exact = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        EXPECT_NEAR(textures.values(0, p).color.x, exact, 3e-7) << k;
    }
}

TEST(TexturedPlane, AMissingTextureIsMagentaNotGrey) {
    const Scene s = plane_under_sky(texture((scratch() / "no_such_texture.png").string()));
    RunResult r = testing::render_crex(s, "D", 8, 1);
    ASSERT_FALSE(r.warnings.empty());
    EXPECT_EQ(r.warnings[0].code, "W310");
    EXPECT_NE(r.warnings[0].where.find("no_such_texture.png"), std::string::npos) << r.warnings[0].where;
    EXPECT_NE(r.warnings[0].message.find("magenta"), std::string::npos) << r.warnings[0].message;
    const Vec3 p = pixel(r.image(), 8, 4, 4);
    EXPECT_NEAR(p.x, 1, 1e-6);
    EXPECT_NEAR(p.y, 0, 1e-6);
    EXPECT_NEAR(p.z, 1, 1e-6);
}

// A file whose header reads but whose texels do not (a PNG cut short) failed its lookups in
// silence, but for libpng's own line: the render says how many, and those pixels are magenta.
TEST(TexturedPlane, ATruncatedTextureSaysItsLookupsFailed) {
    std::vector<float> rgb(256 * 256 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = float((i * 7919) % 256) / 255.0f;  // incompressible enough
    const std::string file = write_texture("cut_short.png", 256, 256, rgb);
    fs::resize_file(file, fs::file_size(file) / 4);
    RunResult r = testing::render_crex(plane_under_sky(texture(file)), "D", 8, 1);
    const Diagnostic* failed = nullptr;
    for (const Diagnostic& w : r.warnings)
        if (w.code == "W310" && w.message.find("could not be read where") != std::string::npos) failed = &w;
    ASSERT_TRUE(failed) << (r.warnings.empty() ? "no warnings" : r.warnings[0].message);
    EXPECT_NE(failed->where.find("cut_short.png"), std::string::npos) << failed->where;
    ASSERT_TRUE(r.textures.has_value());
    ASSERT_EQ(r.textures->images.size(), 1u);
    EXPECT_GT(r.textures->images[0].failed_lookups, 0u);
    const Vec3 p = pixel(r.image(), 8, 4, 4);
    EXPECT_NEAR(p.x, 1, 1e-6);
    EXPECT_NEAR(p.y, 0, 1e-6);
}

// A float image with a NaN and an infinite texel (a PFM written byte by byte: crex's own writer
// keeps images finite). Until 2026-12-07 every filtered lookup whose footprint or coarser MIP
// level held one read as 0: the whole plane rendered black, without a word. Such a lookup now
// reads the nearest texel of the finest level (0 only on the bad texels themselves), the image
// stays finite, and the render says how many lookups met them (W314).
TEST(TexturedPlane, NonFiniteTexelsReadAsZeroAndAreSaid) {
    const int side = 16;
    std::vector<float> texels(size_t(side * side * 3), 0.5f);
    texels[0] = std::nanf("");                                 // red of the bottom-left texel (PFM rows go bottom up)
    texels[3 * (side + 1) + 1] = std::numeric_limits<float>::infinity();  // green of the next one up and right
    const std::string file = (scratch() / "non_finite.pfm").string();
    testing::write_pfm(file, side, side, texels);
    const int n = 16;
    RunResult r = testing::render_crex(plane_under_sky(texture(file)), "D", n, 1);
    const std::vector<float> img = r.image();
    ASSERT_TRUE(testing::all_finite(img));
    const Diagnostic* said = nullptr;
    for (const Diagnostic& w : r.warnings)
        if (w.code == "W314") said = &w;
    ASSERT_TRUE(said) << (r.warnings.empty() ? "no warnings" : r.warnings[0].message);
    EXPECT_NE(said->where.find("non_finite.pfm"), std::string::npos) << said->where;
    ASSERT_TRUE(r.textures.has_value());
    ASSERT_EQ(r.textures->images.size(), 1u);
    EXPECT_GT(r.textures->images[0].non_finite_lookups, 0u);
    EXPECT_LT(r.textures->images[0].non_finite_lookups, r.textures->lookups);
    // The top-right quarter is far from both texels: the texture's 0.5 there.
    for (int y = 1; y < n / 2 - 1; ++y)
        for (int x = n / 2 + 1; x < n - 1; ++x)
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(pixel(img, n, x, y)[k], 0.5, 0.01) << x << "," << y;
    // The bottom-left pixel sees the NaN texel's red: 0 there, not NaN.
    EXPECT_NEAR(pixel(img, n, 0, n - 1).x, 0.0, 0.01);
}

// KHR_texture_transform's rotation turns (u, v) to (c u + s v, c v - s u), as the extension's
// test model (TextureTransformTest: the arrow of its rotation quad points at the green marker,
// not at the red one, "applied in the opposite direction"), three.js and Cesium turn it. A
// quarter turn of the quadrant texture: (0.25, 0.25) reads (0.25, -0.25), repeated (0.25, 0.75),
// the bottom-left quadrant; (0.25, 0.75) reads the bottom-right one. crex turned the other way
// (top-right and top-left) until 2026-12-05.
TEST(TexturedPlane, AUvRotationTurnsAsTheGltfTestModelSays) {
    TextureRef t = texture(write_texture("quadrants_turned.exr", 8, 8, quadrant_texels()));
    t.uv_transform = uv_transform_of(0, 0, kPi / 2, 1, 1);
    std::vector<Diagnostic> warnings;
    const Scene scene = plane_under_sky(t);  // the textures keep a reference to it
    SurfaceTextures textures(scene, kDefaultTextureCacheBytes, warnings);
    SurfacePoint p;
    p.u = 0.25, p.v = 0.25;
    const Vec3 a = textures.values(0, p).color;
    p.v = 0.75;
    const Vec3 b = textures.values(0, p).color;
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(a[k], kQuadrant[2][k], 1e-5);
        EXPECT_NEAR(b[k], kQuadrant[3][k], 1e-5);
    }
}

// Points spread over a texture, on and between texels.
std::vector<SurfacePoint> spread_points() {
    std::vector<SurfacePoint> points;
    for (double u : {0.01, 0.26, 0.5, 0.73, 0.99})
        for (double v : {0.02, 0.31, 0.5, 0.88}) {
            SurfacePoint p;
            p.u = u, p.v = v;
            points.push_back(p);
        }
    return points;
}

// crex's cache folder set to a fresh one for the test's life.
class CacheFolder {
public:
    explicit CacheFolder(const std::string& name) : path_(scratch() / name) {
        fs::remove_all(path_);
        ::setenv("CREX_CACHE", path_.c_str(), 1);
    }
    ~CacheFolder() { ::unsetenv("CREX_CACHE"); }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

// An image without tiles is read whole, MIP levels and all, whatever the cache's limit (a
// 2.6 MB PNG of 30000x30000 texels held 6.9 GB): one larger than the cache may hold is read
// through a tiled copy made once in crex's cache folder (W312 says so when it is made), whose
// finest level holds the very texels: sharp lookups read what the image read whole gives.
TEST(TexturedPlane, AnImageWithoutTilesLargerThanTheCacheIsReadThroughATiledCopy) {
    const CacheFolder cache("tiled_copy_cache");
    // Large enough that a band of 64 of its rows, what making the copy holds, fits the cache.
    std::vector<float> rgb(512 * 384 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = float((i * 37) % 101) / 100.0f;  // no two neighbours alike
    const Scene s = plane_under_sky(texture(write_texture("untiled.exr", 512, 384, rgb)));
    const uint64_t bytes = uint64_t(512) * 384 * 3 * 4 * 4 / 3;  // float RGB with its MIP levels
    std::vector<Diagnostic> warnings;
    SurfaceTextures whole(s, bytes, warnings);
    EXPECT_TRUE(warnings.empty());
    EXPECT_TRUE(whole.stats().images[0].tiled_copy.empty());

    SurfaceTextures over(s, bytes - 1, warnings);
    ASSERT_EQ(warnings.size(), 1u) << warnings[0].message << "\n" << warnings.back().message;
    EXPECT_EQ(warnings[0].code, "W312");
    EXPECT_NE(warnings[0].message.find("512x384 texels without tiles"), std::string::npos) << warnings[0].message;
    const TextureImage made = over.stats().images[0];
    EXPECT_TRUE(made.tiled_copy_made);
    EXPECT_TRUE(made.info.tiled);
    EXPECT_EQ(made.info.mip_levels, 10);  // 512x384 down to 1x1
    EXPECT_EQ(fs::path(made.tiled_copy).parent_path(), cache.path() / "textures");
    EXPECT_TRUE(fs::is_regular_file(made.tiled_copy));
    for (const SurfacePoint& p : spread_points()) {
        const Vec3 a = over.values(0, p).color, b = whole.values(0, p).color;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-6) << "at " << p.u << ", " << p.v;
    }
    // Its coarsest level is about the whole image's mean (box averages of box averages over a
    // size that halves evenly down to 4x3, then rounds down): a lookup whose footprint is the
    // whole image reads about it.
    double mean = 0;
    for (size_t i = 0; i < rgb.size(); i += 3) mean += rgb[i];
    mean /= double(rgb.size() / 3);
    SurfacePoint all;
    all.u = all.v = 0.5;
    all.dudx = all.dvdy = 4;
    EXPECT_NEAR(over.values(0, all).color.x, mean, 0.03);

    // The next render finds the copy and says nothing.
    warnings.clear();
    SurfaceTextures again(s, bytes - 1, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings[0].message;
    EXPECT_EQ(again.stats().images[0].tiled_copy, made.tiled_copy);
    EXPECT_FALSE(again.stats().images[0].tiled_copy_made);
    EXPECT_EQ(again.values(0, spread_points()[7]).color, over.values(0, spread_points()[7]).color);

    // A render whose cache could not hold the band of rows that making it takes reads the copy
    // made: it is read tile by tile (it was refused, as if no copy could be made).
    warnings.clear();
    SurfaceTextures small(s, 64 << 10, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings[0].message;
    EXPECT_TRUE(small.stats().images[0].error.empty()) << small.stats().images[0].error;
    EXPECT_EQ(small.values(0, spread_points()[7]).color, over.values(0, spread_points()[7]).color);
}

// A copy in the cache folder that cannot be read (damaged, or another program's file under its
// name) used to make the texture magenta in every later render: it is made again, once.
TEST(TexturedPlane, ATiledCopyThatCannotBeReadIsMadeAgain) {
    const CacheFolder cache("damaged_copy_cache");
    std::vector<float> rgb(512 * 384 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = float((i * 53) % 97) / 96.0f;
    const Scene s = plane_under_sky(texture(write_texture("damaged_copy.exr", 512, 384, rgb)));
    const uint64_t bytes = uint64_t(512) * 384 * 3 * 4 * 4 / 3;
    const std::string copy = tiled_copy_path(s.materials[0].textures.color->file);
    fs::create_directories(fs::path(copy).parent_path());
    std::ofstream(copy, std::ios::binary) << "II*\0 a tiff cut short";
    std::vector<Diagnostic> warnings;
    SurfaceTextures over(s, bytes - 1, warnings);
    ASSERT_EQ(warnings.size(), 1u) << warnings.back().message;
    EXPECT_EQ(warnings[0].code, "W312");
    const TextureImage made = over.stats().images[0];
    EXPECT_TRUE(made.error.empty()) << made.error;
    EXPECT_TRUE(made.tiled_copy_made);
    EXPECT_EQ(made.tiled_copy, copy);
    SurfaceTextures whole(s, bytes, warnings);
    for (const SurfacePoint& p : spread_points()) {
        const Vec3 a = over.values(0, p).color, b = whole.values(0, p).color;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-6) << "at " << p.u << ", " << p.v;
    }
}

// An 8-bit RGBA image of odd sizes (a TGA, stored unassociated): the copy keeps its texels as
// stored (colour not multiplied by alpha), its sRGB, and its alpha.
TEST(TexturedPlane, ATiledCopyKeepsAnRgbaImagesTexelsAlphaAndColourSpace) {
    const CacheFolder cache("tiled_copy_rgba");
    const int w = 301, h = 333;
    const std::string path = (scratch() / "odd_rgba.tga").string();
    {
        const uint8_t header[18] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, uint8_t(w & 255), uint8_t(w >> 8), uint8_t(h & 255), uint8_t(h >> 8), 32, 8 | 0x20};
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(header), sizeof header);
        for (int i = 0; i < w * h * 4; ++i) out.put(static_cast<char>((i * 53 + i / 4 * 7) % 256));  // B, G, R, A
    }
    Scene s = plane_under_sky(texture(path));
    TextureRef opacity = texture(path);
    opacity.prefer_alpha = true;
    s.materials[0].textures.opacity = opacity;
    const uint64_t bytes = uint64_t(w) * h * 4 * 4 / 3;
    std::vector<Diagnostic> warnings;
    SurfaceTextures whole(s, bytes + 16, warnings);
    SurfaceTextures copy(s, bytes - 16, warnings);
    ASSERT_EQ(warnings.size(), 1u) << warnings[0].message << "\n" << warnings.back().message;
    EXPECT_EQ(warnings[0].code, "W312");
    EXPECT_TRUE(copy.stats().images[0].info.srgb);
    for (const SurfacePoint& p : spread_points()) {
        const Vec3 a = copy.values(0, p).color, b = whole.values(0, p).color;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-6) << "at " << p.u << ", " << p.v;
        EXPECT_NEAR(copy.opacity(0, p), whole.opacity(0, p), 1e-6) << "at " << p.u << ", " << p.v;
    }
}

// An image embedded in the scene's file (a .glb's PNG, named "scene.glb#image0") reads the texels
// the same image reads as a file: OpenImageIO picks its reader by the name's extension, and
// found none for such a name (every embedded image rendered magenta).
TEST(TexturedPlane, AnEmbeddedImageReadsAsTheSameFileDoes) {
    std::vector<float> rgb(16 * 16 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = float((i * 29) % 256) / 255.0f;
    const std::string path = write_texture("embedded_small.png", 16, 16, rgb);
    std::ifstream file(path, std::ios::binary);
    Scene embedded = plane_under_sky({});
    embedded.images.push_back({"scene.glb#image0", "image/png", std::string(std::istreambuf_iterator<char>(file), {})});
    embedded.materials[0].textures.color.emplace().image = "scene.glb#image0";
    std::vector<Diagnostic> warnings;
    const Scene file_scene = plane_under_sky(texture(path));  // the textures keep a reference to it
    SurfaceTextures from_bytes(embedded, kDefaultTextureCacheBytes, warnings), from_file(file_scene, kDefaultTextureCacheBytes, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings[0].message;
    for (const SurfacePoint& p : spread_points()) {
        const Vec3 a = from_bytes.values(0, p).color, b = from_file.values(0, p).color;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-6) << "at " << p.u << ", " << p.v;
    }
}

// An image embedded in the scene's file (a .glb's PNG) is copied as a file is, keyed by its bytes.
TEST(TexturedPlane, AnEmbeddedImageLargerThanTheCacheIsReadThroughATiledCopy) {
    const CacheFolder cache("embedded_copy");
    std::vector<float> rgb(300 * 400 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = float((i * 29) % 256) / 255.0f;
    std::ifstream file(write_texture("embedded.png", 300, 400, rgb), std::ios::binary);
    Scene s = plane_under_sky({});
    s.images.push_back({"scene.glb#image0", "image/png", std::string(std::istreambuf_iterator<char>(file), {})});
    s.materials[0].textures.color.emplace().image = "scene.glb#image0";
    const uint64_t bytes = uint64_t(300) * 400 * 3 * 4 / 3;
    std::vector<Diagnostic> warnings;
    SurfaceTextures whole(s, bytes, warnings);
    SurfaceTextures copy(s, bytes - 1, warnings);
    ASSERT_EQ(warnings.size(), 1u) << warnings.front().message;
    EXPECT_EQ(warnings[0].code, "W312");
    const TextureImage image = copy.stats().images[0];
    EXPECT_TRUE(image.tiled_copy_made);
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(cache.path() / "textures")) files.push_back(e.path().filename().string());
    EXPECT_EQ(files, std::vector<std::string>{fs::path(image.tiled_copy).filename().string()});  // the bytes' own file removed
    for (const SurfacePoint& p : spread_points()) {
        const Vec3 a = copy.values(0, p).color, b = whole.values(0, p).color;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-6) << "at " << p.u << ", " << p.v;
    }
}

// A process killed while making a copy leaves its temporary files (the coarser levels of a
// 30000x30000 PNG: 869 MB after 12 s); the next one to make that copy removes them, and not
// those of a maker that still runs.
TEST(TexturedPlane, AKilledCopysTemporaryFilesAreRemovedByTheNext) {
    const CacheFolder cache("stale");
    const fs::path folder = cache.path() / "textures";
    fs::create_directories(folder);
    const fs::path copy = folder / "wood-0123456789abcdef.tx";
    const std::string alive = std::to_string(::getpid());
    for (const std::string& name : std::vector<std::string>{"wood-0123456789abcdef.tx.999999999.level1", "wood-0123456789abcdef.tx.999999999.part",
                                   "wood-0123456789abcdef.tx." + alive + ".part", "other-0123456789abcdef.tx.999999999.part",
                                   "wood-0123456789abcdef.tx"})
        std::ofstream(folder / name) << "x";
    remove_stale_temporaries(copy.string());
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(folder)) left.push_back(e.path().filename().string());
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"other-0123456789abcdef.tx.999999999.part", "wood-0123456789abcdef.tx",
                                              "wood-0123456789abcdef.tx." + alive + ".part"}));
}

// Where the copy cannot be made (the cache folder cannot be), the image is not read: W310 says
// why and what to do, and it renders magenta. `crex scene-info` (find only) makes no copy.
TEST(TexturedPlane, AnImageWhoseTiledCopyCannotBeMadeIsNotRead) {
    const fs::path blocker = scratch() / "not_a_folder";
    std::ofstream(blocker) << "a file where the cache folder would go";
    ::setenv("CREX_CACHE", (blocker / "cache").c_str(), 1);
    const Scene s = plane_under_sky(texture(write_texture("uncopied.exr", 256, 256, std::vector<float>(256 * 256 * 3, 0.5f))));
    const uint64_t bytes = uint64_t(256) * 256 * 3 * 4 * 4 / 3;
    std::vector<Diagnostic> warnings;
    SurfaceTextures over(s, bytes - 1, warnings);
    ::unsetenv("CREX_CACHE");
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].code, "W310");
    EXPECT_NE(warnings[0].message.find("could not be made"), std::string::npos) << warnings[0].message;
    EXPECT_NE(warnings[0].message.find("maketx"), std::string::npos) << warnings[0].message;
    SurfacePoint p;
    p.u = p.v = 0.5;
    EXPECT_EQ(over.values(0, p).color, (Vec3{1, 0, 1}));

    const CacheFolder cache("find_only");
    warnings.clear();
    SurfaceTextures info(s, bytes - 1, warnings, TiledCopies::kFindOnly);
    EXPECT_TRUE(warnings.empty());
    const TextureImage image = info.stats().images[0];
    EXPECT_FALSE(image.tiled_copy.empty());
    EXPECT_FALSE(image.tiled_copy_made);
    EXPECT_FALSE(image.info.tiled);
    EXPECT_FALSE(fs::exists(cache.path()));
}

// A PNG whose header says it is a million texels a side (and holds none): its file could not
// hold that, so it is refused as it opens, before a copy is tried or a texel read; W310 at once.
TEST(TexturedPlane, APngThatSaysItIsAMillionTexelsWideIsNotCopied) {
    const CacheFolder cache("million");
    const std::string path = (scratch() / "million.png").string();
    std::ofstream(path, std::ios::binary) << std::string("\x89PNG\r\n\x1a\n", 8)
                                          << png_chunk("IHDR", be32(1000000) + be32(1000000) + std::string("\x08\x02\x00\x00\x00", 5))
                                          << png_chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) << png_chunk("IEND", "");
    std::vector<Diagnostic> warnings;
    const Scene scene = plane_under_sky(texture(path));  // the textures keep a reference to it
    SurfaceTextures textures(scene, texture_cache_bytes(size_t{1} << 30), warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].code, "W310") << warnings[0].message;
    EXPECT_NE(warnings[0].message.find("is too small for the 1000000 x 1000000 pixels its header claims"), std::string::npos)
        << warnings[0].message;
    EXPECT_FALSE(fs::exists(cache.path()));
}

// A checkerboard on a ground plane seen at grazing angles, as an emission (no lighting: the
// image is the filtered texture itself, no other noise). Checks of 4 texels: OpenImageIO's
// bicubic B-spline, what a lookup without a footprint reads, smooths single-texel checks
// to 0.5 +- 0.06 by itself.
Scene grazing_checkerboard() {
    const int n = 64;
    std::vector<float> rgb(size_t(n) * n * 3);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int k = 0; k < 3; ++k) rgb[size_t((y * n + x) * 3 + k)] = float((x / 4 + y / 4) % 2);
    Scene s;
    Material m = testing::make_material("ground", MaterialType::kPlastic, {0, 0, 0});
    m.textures.emission = texture(write_texture("checks.exr", n, n, rgb));
    s.materials.push_back(m);
    // 400 m x 400 m, the texture (16 checks across) repeated every 0.32 m: checks of 2 cm.
    const double w = 200, repeat = 2 * w / 0.32;
    s.shapes.push_back(uv_quad("ground", {-w, 0, w}, {w, 0, w}, {w, 0, -w}, {-w, 0, -w}, repeat));
    s.camera.position = {0, 1, 0};
    s.camera.direction = {0, -0.1, -1};
    s.camera.vfov_deg = 30;
    return s;
}

// Mean |pixel - 0.5| over the rows where each pixel spans several checks (the horizon is at
// about row 20 of 64; rows 22..40 are from 40 m to 4 m away, a pixel 3 to 30 checks wide).
double far_field_deviation(const std::vector<float>& img, int n) {
    double sum = 0;
    int count = 0;
    for (int y = 22; y <= 40; ++y)
        for (int x = 0; x < n; ++x) sum += std::fabs(pixel(img, n, x, y).x - 0.5), ++count;
    return sum / count;
}

TEST(GrazingCheckerboard, OneSamplePerPixelDoesNotAlias) {
    const Scene s = grazing_checkerboard();
    RunSettings o;
    o.width = o.height = 64;
    o.spp = 1;
    const std::vector<float> filtered = render(s, testing::lower_or_die(""), o).image();
    o.texture_filter_width = 0;  // the sharpest lookups: what point sampling gives
    const std::vector<float> sharp = render(s, testing::lower_or_die(""), o).image();
    // The bound: within 0.1 of the checks' mean 0.5 on average (a pixel of random 0s and 1s
    // deviates by 0.5). Without the footprint, the same pixels alias.
    const double dev_filtered = far_field_deviation(filtered, 64), dev_sharp = far_field_deviation(sharp, 64);
    EXPECT_LT(dev_filtered, 0.1) << "point sampling: " << dev_sharp;
    EXPECT_GT(dev_sharp, 0.3) << "the test must be able to fail";
}

// Stripes 4 texels wide across s (constant along t), read at a stripe's centre through a
// footprint half the texture long across them (8 stripes) and 0.001 wide along them. A seen
// hit's anisotropic filter averages along the long axis: the stripes' mean, 0.5. An unseen
// hit's (SurfacePoint::indirect: a bounce, the cache's hemisphere rays) is isotropic over the
// same area, 0.022 across, a texel and a half: it reads the white stripe, nearly whole.
TEST(TextureFilter, UnseenHitsReadARoundFootprintOfTheSameAreaSeenOnesTheAnisotropicOne) {
    const int n = 64;
    std::vector<float> rgb(size_t(n) * n * 3);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int k = 0; k < 3; ++k) rgb[size_t((y * n + x) * 3 + k)] = float((x / 4) % 2);
    Scene s;
    Material m = testing::make_material("stripes", MaterialType::kPlastic, {0, 0, 0});
    m.textures.color = texture(write_texture("stripes.exr", n, n, rgb));
    s.materials.push_back(m);
    std::vector<Diagnostic> warnings;
    SurfaceTextures textures(s, size_t{16} << 20, warnings);
    ASSERT_TRUE(warnings.empty());
    SurfacePoint p;
    p.u = 6.0 / n, p.v = 0.5;  // the centre of the second stripe, texels 4..7: white
    p.dudx = 0.5, p.dvdy = 0.001;
    const double seen = textures.values(0, p).color.x;
    p.indirect = true;
    const double unseen = textures.values(0, p).color.x;
    EXPECT_NEAR(seen, 0.5, 0.1);
    EXPECT_GT(unseen, 0.8) << "seen: " << seen;
}

// A texture whose filter is "nearest" (glTF's magFilter NEAREST) reads the texel a point falls
// in, with or without a footprint smaller than a texel, and its opacity mask does too; a smooth
// one blends the texels around the point. A 2 x 2 checker of 0 and 1, read at s = 0.45 (in
// texel 0, nearer texel 1's centre than a bilinear lookup's weights ignore).
TEST(TextureFilter, NearestReadsTheTexelThePointFallsIn) {
    const std::vector<float> rgb = {0, 0, 0, 1, 1, 1, 1, 1, 1, 0, 0, 0};
    const std::string file = write_texture("checker.exr", 2, 2, rgb);
    Scene s;
    for (TextureFilter filter : {TextureFilter::kSmooth, TextureFilter::kNearest}) {
        Material m = testing::make_material(std::string(texture_filter_name(filter)), MaterialType::kPlastic, {0, 0, 0});
        m.textures.color = texture(file);
        m.textures.color->filter = filter;
        m.textures.opacity = texture(file);
        m.textures.opacity->filter = filter;
        s.materials.push_back(m);
    }
    std::vector<Diagnostic> warnings;
    SurfaceTextures textures(s, size_t{16} << 20, warnings);
    ASSERT_TRUE(warnings.empty());
    for (const double footprint : {0.0, 0.01}) {
        SurfacePoint p;
        p.u = 0.45, p.v = 0.25;
        p.dudx = p.dvdy = footprint;
        const MaterialValues smooth = textures.values(0, p), nearest = textures.values(1, p);
        EXPECT_EQ(nearest.color.x, 0.0) << "footprint " << footprint;
        EXPECT_GT(smooth.color.x, 0.2) << "footprint " << footprint;
        p.u = 0.55;  // in texel 1
        EXPECT_EQ(textures.values(1, p).color.x, 1.0) << "footprint " << footprint;
    }
    SurfacePoint p;  // the opacity mask's own reader (no footprint)
    p.u = 0.45, p.v = 0.25;
    EXPECT_EQ(textures.opacity(1, p), 0.0);
    EXPECT_GT(textures.opacity(0, p), 0.2);
    p.u = 0.05, p.v = 0.95;  // texel (0, 1): 1
    EXPECT_EQ(textures.opacity(1, p), 1.0);
}

// A hit whose light is averaged (an irradiance record's hemisphere ray, a photon) reads a
// coarse copy of the image, bilinearly, under the texture's wrap modes; such lookups are
// counted apart from the TextureSystem's. A ramp r = s, g = t over 512 x 256 texels: the copy
// (128 x 64 texels, each the filtered lookup over its footprint) gives the ramp back wherever
// it is linear.
TEST(TextureFilter, AveragedHitsReadTheImagesCoarseCopyUnderItsWrapModes) {
    const int w = 512, h = 256;
    std::vector<float> rgb(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* t = &rgb[size_t((y * w + x) * 3)];
            t[0] = (float(x) + 0.5f) / float(w), t[1] = (float(y) + 0.5f) / float(h), t[2] = 0.25f;
        }
    const std::string file = write_texture("ramp.exr", w, h, rgb);
    Scene s;
    for (TextureWrap wrap : {TextureWrap::kRepeat, TextureWrap::kClamp, TextureWrap::kMirror, TextureWrap::kBlack}) {
        Material m = testing::make_material("ramp" + std::to_string(int(wrap)), MaterialType::kPlastic, {0, 0, 0});
        m.textures.color = texture(file);
        m.textures.color->wrap_s = m.textures.color->wrap_t = wrap;
        s.materials.push_back(m);
    }
    std::vector<Diagnostic> warnings;
    SurfaceTextures textures(s, size_t{16} << 20, warnings);
    ASSERT_TRUE(warnings.empty());
    auto at = [&](uint32_t material, double u, double v) {
        SurfacePoint p;
        p.u = u, p.v = v;
        p.indirect = p.coarse = true;
        return textures.values(material, p).color;
    };
    for (double u : {0.1, 0.33, 0.5, 0.77, 0.9})
        for (double v : {0.2, 0.5, 0.8}) {
            const Vec3 c = at(0, u, v);
            EXPECT_NEAR(c.x, u, 2e-3) << u << ", " << v;
            EXPECT_NEAR(c.y, v, 2e-3) << u << ", " << v;
            EXPECT_NEAR(c.z, 0.25, 1e-6);
        }
    EXPECT_NEAR(at(0, 1.3, 0.5).x, 0.3, 2e-3);   // repeat
    EXPECT_NEAR(at(1, 1.5, 0.5).x, 1 - 0.5 / 128, 2e-3);  // clamp: the last texel of the copy
    EXPECT_NEAR(at(2, 1.3, 0.5).x, 0.7, 2e-3);   // mirror
    EXPECT_EQ(at(3, 1.5, 0.5).x, 0.0);           // black
    EXPECT_EQ(at(3, -0.5, 0.5).y, 0.0);
    const TextureStats stats = textures.stats();
    EXPECT_EQ(stats.coarse_lookups, 15u + 5u);
    EXPECT_EQ(stats.lookups, 0u);  // the copy's own making is the backend's, not crex's lookups
    // Without `coarse` the same point goes through the TextureSystem.
    SurfacePoint p;
    p.u = 0.5, p.v = 0.5, p.indirect = true;
    EXPECT_NEAR(textures.values(0, p).color.x, 0.5, 2e-3);
    EXPECT_EQ(textures.stats().lookups, 1u);
}

// A diffuse floor under a small square lamp, an occluder between them whose left half is
// opaque and right half a hole (an opacity texture), the camera under the occluder looking down.
Scene cutout_shadow(const std::optional<TextureRef>& opacity, bool occluder) {
    Scene s;
    s.materials.push_back(testing::make_material("floor", MaterialType::kPlastic, {0.5, 0.5, 0.5}));
    s.materials.push_back(testing::make_material("lamp", MaterialType::kLight, {20, 20, 20}));
    Material leaf = testing::make_material("leaf", MaterialType::kPlastic, {0.5, 0.5, 0.5});
    leaf.textures.opacity = opacity;
    s.materials.push_back(leaf);
    s.shapes.push_back(testing::quad("floor", {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, {-5, 0, -5}));
    s.shapes.push_back(testing::quad("lamp", {-0.1, 2, -0.1}, {0.1, 2, -0.1}, {0.1, 2, 0.1}, {-0.1, 2, 0.1}));
    if (occluder) s.shapes.push_back(uv_quad("leaf", {-1, 1, 1}, {1, 1, 1}, {1, 1, -1}, {-1, 1, -1}));
    s.camera.position = {0, 0.5, 0};
    s.camera.direction = {0, -1, 0};
    s.camera.up = {0, 0, -1};
    s.camera.vfov_deg = 90;  // the floor x in [-0.5, 0.5]
    return s;
}

std::vector<float> opacity_left_half() {
    std::vector<float> rgb(16 * 16 * 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x)
            for (int k = 0; k < 3; ++k) rgb[size_t((y * 16 + x) * 3 + k)] = x < 8 ? 1.0f : 0.0f;
    return rgb;
}

// A cut-out's opacity is read from a mask held in memory (a cut-out is tested at every
// candidate hit, and the backend's lookup cost ~700 ns): it must read what the backend reads
// for a lookup without a footprint (bilinear on the finest level), under every wrap mode, for
// 8-bit and float images alike; a mask over its share of the cache leaves the backend to it.
TEST(AlphaCutout, TheOpacityMaskReadsWhatTheBackendReads) {
    const int w = 37, h = 23;  // odd sizes: no texel centre falls on a power of two
    std::vector<float> rgb(size_t(w) * h * 3);
    uint64_t state = 12345;
    for (float& v : rgb) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        v = static_cast<float>(state >> 40) / float(1 << 24);
    }
    for (const std::string& file : {write_texture("mask.png", w, h, rgb), write_texture("mask.exr", w, h, rgb)}) {
        Scene s;
        for (TextureWrap wrap : {TextureWrap::kRepeat, TextureWrap::kClamp, TextureWrap::kMirror, TextureWrap::kBlack}) {
            Material m = testing::make_material("leaf" + std::to_string(int(wrap)), MaterialType::kPlastic, {0.5, 0.5, 0.5});
            m.textures.opacity = texture(file);
            m.textures.opacity->channel = 1;
            m.textures.opacity->wrap_s = m.textures.opacity->wrap_t = wrap;
            s.materials.push_back(m);
        }
        std::vector<Diagnostic> warnings;
        SurfaceTextures masked(s, size_t{16} << 20, warnings);
        // A cache that holds the image (PNG 3,404 bytes with its MIP levels, EXR 13,616) but
        // not its mask in its eighth (PNG 851 bytes, EXR 3,404).
        SurfaceTextures unmasked(s, file.ends_with(".png") ? 5000 : 20000, warnings);
        ASSERT_TRUE(warnings.empty());
        EXPECT_EQ(masked.stats().mask_bytes, uint64_t(w) * h * (file.ends_with(".png") ? 1 : 4));
        EXPECT_EQ(unmasked.stats().mask_bytes, 0u);
        int tested = 0;
        double largest = 0;
        for (uint32_t m = 0; m < 4; ++m)
            for (double u = -1.3; u < 2.3; u += 0.0371)
                for (double v = -1.1; v < 2.1; v += 0.0533) {
                    SurfacePoint p;
                    p.u = u, p.v = v;
                    const double a = masked.opacity(m, p), b = unmasked.opacity(m, p);
                    // OpenImageIO wraps (s, t) in float, the mask in double: weights differ by
                    // float rounding at |u| near 2 (up to 3.5e-6 seen), far under an 8-bit step.
                    EXPECT_NEAR(a, b, 1e-5) << file << " wrap " << m << " at " << u << ", " << v;
                    largest = std::max(largest, b);
                    ++tested;
                }
        EXPECT_GT(largest, 0.5);  // the texture's values, not a constant
        EXPECT_EQ(masked.stats().mask_lookups, uint64_t(tested));
        EXPECT_EQ(masked.stats().lookups, 0u);
        EXPECT_EQ(unmasked.stats().mask_lookups, 0u);
        EXPECT_EQ(unmasked.stats().lookups, uint64_t(tested));
    }
}

TEST(AlphaCutout, CastsTheShadowOfItsOpaquePartOnly) {
    const TextureRef half = texture(write_texture("left_half.exr", 16, 16, opacity_left_half()));
    const int n = 32;
    RunSettings o;
    o.width = o.height = n;
    o.spp = 4;
    o.executor.shade.shadow_rays = 4;
    // Camera rays only: the image is the direct light on the floor.
    const std::vector<float> cut = render(cutout_shadow(half, true), testing::lower_or_die(""), o).image();
    const std::vector<float> open = render(cutout_shadow(std::nullopt, false), testing::lower_or_die(""), o).image();
    const std::vector<float> solid = render(cutout_shadow(std::nullopt, true), testing::lower_or_die(""), o).image();
    // The penumbra of a 0.2 m lamp 1 m above the occluder's edge (x = 0) is 0.2 m wide on the
    // floor: columns 10 and 21 (x = -0.17, +0.17) are clear of it.
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x <= 10; ++x) {  // under the opaque half: the solid occluder's shadow
            const Vec3 c = pixel(cut, n, x, y), s = pixel(solid, n, x, y);
            ASSERT_EQ(c.x, s.x) << x << "," << y;
            ASSERT_EQ(c.x, 0.0f) << x << "," << y;
        }
        for (int x = 21; x < n; ++x)  // under the hole: as lit as with no occluder at all
            ASSERT_EQ(pixel(cut, n, x, y).x, pixel(open, n, x, y).x) << x << "," << y;
    }
    EXPECT_GT(pixel(open, n, 25, 16).x, 0.01f);  // rho / pi x E, E about L A / d^2 = 0.2
}

TEST(AlphaCutout, CameraRaysSeeThroughItsHoles) {
    // The camera above the occluder: over its hole it sees the lit floor, over its opaque half
    // the (unlit, its back to the lamp) occluder... seen from above, the occluder's top faces
    // the lamp: it is lit too, but brighter than the floor one metre further down.
    const TextureRef half = texture(write_texture("left_half_cam.exr", 16, 16, opacity_left_half()));
    Scene s = cutout_shadow(half, true);
    s.camera.position = {0, 1.5, 0};
    s.camera.vfov_deg = 30;  // sees x in [-0.13, 0.13] on the occluder
    Scene open = s;
    open.shapes.pop_back();
    const int n = 16;
    RunSettings o;
    o.width = o.height = n;
    o.spp = 2;
    const std::vector<float> cut = render(s, testing::lower_or_die(""), o).image();
    const std::vector<float> floor = render(open, testing::lower_or_die(""), o).image();
    for (int y = 0; y < n; ++y)
        for (int x = 10; x < n; ++x) ASSERT_EQ(pixel(cut, n, x, y).x, pixel(floor, n, x, y).x) << x << "," << y;
    EXPECT_GT(pixel(cut, n, 2, 8).x, 2 * pixel(floor, n, 2, 8).x);  // the occluder itself, nearer the lamp
}

TEST(AlphaCutout, CacheRaysPassThroughHolesToo) {
    // A white floor under a sky of radiance 1, a fully transparent sheet 1 cm above it: the
    // irradiance cache's hemisphere rays must see the sky through it (E = pi, radiance =
    // albedo); stopped by the sheet, they would see its (unlit) underside.
    Scene s;
    s.materials.push_back(testing::make_material("floor", MaterialType::kPlastic, {0.5, 0.5, 0.5}));
    Material sheet = testing::make_material("sheet", MaterialType::kPlastic, {0.5, 0.5, 0.5});
    sheet.opacity = 0;  // a constant opacity below the cutoff: all hole
    s.materials.push_back(sheet);
    s.shapes.push_back(testing::quad("floor", {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, {-5, 0, -5}));
    s.shapes.push_back(testing::quad("sheet", {-5, 0.01, 5}, {5, 0.01, 5}, {5, 0.01, -5}, {-5, 0.01, -5}));
    s.background = {1, 1, 1};
    s.camera.position = {0, 1, 0};
    s.camera.direction = {0, -1, 0};
    s.camera.up = {0, 0, -1};
    s.camera.vfov_deg = 40;
    RunSettings o;
    o.width = o.height = 8;
    o.spp = 1;
    IcSettings ic;
    ic.divisions = 64;
    ic.caustic_photons = 0;
    o.irradiance_cache = ic;
    RunResult r = render(s, testing::lower_or_die("D"), o);
    ASSERT_GT(r.ic_stats.records, 0u);
    for (float v : r.image()) ASSERT_NEAR(v, 0.5, 0.005);
}

TEST(NormalMap, AFlatNormalMapChangesNothingBitForBit) {
    // An 8-bit "flat" normal map (128, 128, 255): 2 v - 1 is 1/255, not 0, which crex reads
    // as flat. The images with and without it must be the same bytes.
    std::vector<float> rgb(8 * 8 * 3);
    for (size_t i = 0; i < rgb.size(); i += 3) rgb[i] = rgb[i + 1] = 128.0f / 255.0f, rgb[i + 2] = 1.0f;
    const TextureRef flat = texture(write_texture("flat_normal.png", 8, 8, rgb));
    auto scene = [&](bool mapped) {
        Scene s = testing::square_light_over_plane(0.6, 3.0, 0.5, 1.0);
        s.shapes[0] = uv_quad("floor", {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, 100);
        s.shapes[0].normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
        Material& floor = s.materials[0];
        floor.specularity = 0.2, floor.roughness = 0.3;  // a glossy lobe too: both lobes use the normal
        if (mapped) floor.textures.normal = flat;
        s.camera.vfov_deg = 60;
        return s;
    };
    RunSettings o;
    o.width = o.height = 16;
    o.spp = 2;
    const std::vector<float> with = render(scene(true), testing::lower_or_die("(DG)2"), o).image();
    const std::vector<float> without = render(scene(false), testing::lower_or_die("(DG)2"), o).image();
    ASSERT_EQ(with.size(), without.size());
    EXPECT_EQ(std::memcmp(with.data(), without.data(), with.size() * sizeof(float)), 0);
    // A tilted normal map does change it (the comparison can fail).
    for (size_t i = 0; i < rgb.size(); i += 3) rgb[i] = 0.8f;
    const TextureRef tilted = texture(write_texture("tilted_normal.png", 8, 8, rgb));
    Scene t = scene(false);
    t.materials[0].textures.normal = tilted;
    const std::vector<float> bent = render(t, testing::lower_or_die("(DG)2"), o).image();
    EXPECT_NE(std::memcmp(bent.data(), without.data(), bent.size() * sizeof(float)), 0);
}

// A surface whose emission is an image lights the scene through direct lighting's samples,
// each reading the image where it falls (TexturedEmission), and rays that hit it from a
// diffuse or glossy lobe no longer count it: the same light, without the grain of finding it
// by chance. `texels(x, y)` of a 64 x 64 image, times L; the quad is square_light_over_plane's
// lamp (u along +x).
Scene floor_under_textured_emission(double rho, double L, double half, double h, const std::function<float(int, int)>& texels,
                                    const std::string& name) {
    Scene s = testing::square_light_over_plane(rho, L, half, h);
    std::vector<float> rgb(64 * 64 * 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            for (int k = 0; k < 3; ++k) rgb[size_t((y * 64 + x) * 3 + k)] = texels(x, y);
    Material screen = testing::make_material("lamp", MaterialType::kPlastic, {0, 0, 0});
    screen.textures.emission = texture(write_texture(name, 64, 64, rgb));
    screen.textures.emission->scale = {L, L, L};
    s.materials[1] = screen;
    s.shapes[1] = uv_quad("lamp", {-half, h, -half}, {half, h, -half}, {half, h, half}, {-half, h, half});
    return s;
}

TEST(TexturedEmission, LightsTheFloorAsALampOfItsRadianceDoesAndAsQuietly) {
    const double rho = 0.5, L = 2, half = 0.5, h = 1;
    const Scene s = floor_under_textured_emission(rho, L, half, h, [](int, int) { return 1.0f; }, "white.exr");
    const int n = 16;
    const std::vector<float> img = testing::render_crex(s, "(TTMRSGD)*", n, 16, 3).image();
    ASSERT_TRUE(testing::all_finite(img));
    // The point under the lamp's centre: rho E / pi (the lamp reflects nothing back).
    const double expected = rho * testing::irradiance_under_square(L, half, h) / kPi;
    EXPECT_NEAR(testing::mean_luminance(img) / expected, 1.0, 0.02);
    // Its noise, the pixels' spread about their mean: sampled, a few percent; with only the
    // diffuse rays that happen to hit it (a chance of 0.24 each), about ten times as much.
    auto spread = [](const std::vector<float>& image) {
        double sum = 0, squares = 0;
        for (size_t i = 0; i < image.size(); i += 3) sum += image[i], squares += double(image[i]) * image[i];
        const double count = double(image.size() / 3), mean = sum / count;
        return std::sqrt(std::fmax(squares / count - mean * mean, 0.0)) / mean;
    };
    EXPECT_LT(spread(img), 0.05);  // 0.017 when written
    // A material that says it is no lamp (`emission_sampled` false, glTF's unlit) is left to
    // the rays: the same light, with the rays' spread.
    Scene unsampled = s;
    unsampled.materials[1].emission_sampled = false;
    const std::vector<float> by_rays = testing::render_crex(unsampled, "(TTMRSGD)*", n, 16, 3).image();
    EXPECT_NEAR(testing::mean_luminance(by_rays) / expected, 1.0, 0.06);
    EXPECT_GT(spread(by_rays), 0.08);  // 0.157 when written
    // Wound the other way, the quad faces up: direct lighting samples that side, and the floor
    // sees its back, whose emission the rays that hit it still count (unsampled, so noisier).
    Scene flipped = s;
    std::swap(flipped.shapes[1].vertices[1], flipped.shapes[1].vertices[3]);
    std::swap(flipped.shapes[1].uvs[1], flipped.shapes[1].uvs[3]);
    EXPECT_NEAR(testing::mean_luminance(testing::render_crex(flipped, "(TTMRSGD)*", n, 64, 3).image()) / expected, 1.0, 0.05);
}

TEST(TexturedEmission, EachSampleReadsTheTexelItFallsOn) {
    // Only the half at +x glows (u >= 0.5): at a point under that half, the light of a `light`
    // over that half alone, not half of the whole quad's (what the image's mean would give).
    const double rho = 0.5, L = 2, half = 0.5, h = 1;
    Scene s = floor_under_textured_emission(rho, L, half, h, [](int x, int) { return x >= 32 ? 1.0f : 0.0f; }, "half.exr");
    Scene lamp = testing::square_light_over_plane(rho, L, half, h);
    lamp.shapes[1] = build::quad("lamp", {0, h, -half}, {half, h, -half}, {half, h, half}, {0, h, half});
    for (Scene* scene : {&s, &lamp}) scene->camera.position = {0.25, h / 2, 0};
    const double textured = testing::mean_luminance(testing::render_crex(s, "(TTMRSGD)*", 16, 64, 3).image());
    const double reference = testing::mean_luminance(testing::render_crex(lamp, "(TTMRSGD)*", 16, 64, 3).image());
    EXPECT_NEAR(textured / reference, 1.0, 0.02);
    s.camera.position = lamp.camera.position = {-0.25, h / 2, 0};  // under the dark half: less
    EXPECT_NEAR(testing::mean_luminance(testing::render_crex(s, "(TTMRSGD)*", 16, 64, 3).image()) /
                    testing::mean_luminance(testing::render_crex(lamp, "(TTMRSGD)*", 16, 64, 3).image()),
                1.0, 0.02);
}

}  // namespace
}  // namespace crex
