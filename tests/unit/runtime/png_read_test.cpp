// PNG files read through libpng (runtime/io/image_io_png.cpp), whatever wrote them: every colour
// type and depth gives linear RGB (the sRGB curve undone, or a gAMA chunk's power; grey to all
// three channels, alpha over black), text chunks come back as the header, and damaged or
// oversized files are errors that name the file, found before anything large is allocated. The
// files are made here with libpng's own writer, so each value checked is known exactly.
#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/io/image_io.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

class PngRead : public testing::ScratchFolderTest {
protected:
    PngRead() : ScratchFolderTest("crex_png_read_") {}

    // A PNG of `width` x `height` with libpng's writer: `colour_type`, `bit_depth`, rows of
    // packed samples as PNG stores them (16-bit big-endian), an optional palette and tRNS.
    std::string write(const std::string& name, png_uint_32 width, png_uint_32 height, int colour_type, int bit_depth,
                      const std::vector<unsigned char>& samples, bool interlaced = false, const std::vector<png_color>& palette = {},
                      const std::vector<png_byte>& alpha_of_palette = {}, png_fixed_point gamma = 0) {
        const std::string file = path(name);
        FILE* f = std::fopen(file.c_str(), "wb");
        EXPECT_NE(f, nullptr);
        png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
        png_infop info = png_create_info_struct(png);
        png_init_io(png, f);
        png_set_IHDR(png, info, width, height, bit_depth, colour_type, interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        if (!palette.empty()) png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
        if (!alpha_of_palette.empty()) png_set_tRNS(png, info, alpha_of_palette.data(), static_cast<int>(alpha_of_palette.size()), nullptr);
        if (gamma > 0) png_set_gAMA_fixed(png, info, gamma);
        const size_t row = samples.size() / height;
        std::vector<png_bytep> rows(height);
        for (size_t y = 0; y < height; ++y) rows[y] = const_cast<png_bytep>(samples.data() + y * row);
        png_set_rows(png, info, rows.data());
        png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
        png_destroy_write_struct(&png, &info);
        std::fclose(f);
        return file;
    }
};

float linear(double encoded) { return static_cast<float>(srgb_decode(encoded)); }

TEST_F(PngRead, CrexsOwnPngsComeBackAsWritten) {
    // Display values in [0, 1] are stored as 8 bits; read back they are those 8 bits, linearised.
    const std::vector<float> display = {0, 0.25f, 0.5f, 0.75f, 1, 0.1f};
    const std::string file = path("own.png");
    ASSERT_EQ(write_image(file, 2, 1, {{"", display, true, 3}}, {{"crex:view", std::string("-vp 0 1 2")}, {"Software", std::string("crex")}}), "");
    int w = 0, h = 0;
    std::vector<float> rgb;
    bool display_referred = false;
    ASSERT_EQ(read_image(file, w, h, rgb, &display_referred), "");
    EXPECT_EQ(w, 2);
    EXPECT_EQ(h, 1);
    EXPECT_TRUE(display_referred);
    ASSERT_EQ(rgb.size(), 6u);
    for (size_t i = 0; i < 6; ++i) EXPECT_FLOAT_EQ(rgb[i], linear(std::lround(255 * display[i]) / 255.0)) << i;
    ImageMetadata header;
    ASSERT_EQ(read_image_metadata(file, w, h, header), "");
    EXPECT_EQ(attribute_text(header, "crex:view"), "-vp 0 1 2");
    EXPECT_EQ(attribute_text(header, "Software"), "crex");
}

TEST_F(PngRead, SixteenBitGreyGoesToAllThreeChannels) {
    const std::string file = write("grey16.png", 3, 1, PNG_COLOR_TYPE_GRAY, 16, {0x00, 0x00, 0x80, 0x00, 0xff, 0xff});
    int w = 0, h = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(file, w, h, rgb), "");
    const std::vector<float> want = {0, linear(0x8000 / 65535.0), 1};
    for (size_t p = 0; p < 3; ++p)
        for (size_t c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(rgb[3 * p + c], want[p]) << p << " " << c;
}

TEST_F(PngRead, AGammaChunkSaysHowValuesBecomeLight) {
    // gAMA alone is a pure power: 1.0 is linear light, 0.5 squares; 1/2.2 is taken for the sRGB
    // curve its writers meant. An sRGB chunk beside a gAMA wins (crex's own files carry both).
    const std::vector<unsigned char> samples = {0x00, 0x00, 0x40, 0x00, 0x80, 0x00, 0xff, 0xff};
    const std::vector<double> stored = {0, 0x4000 / 65535.0, 0x8000 / 65535.0, 1};
    int w = 0, h = 0;
    std::vector<float> rgb;
    auto expect = [&](const std::string& name, png_fixed_point gamma, auto light) {
        ASSERT_EQ(read_image(write(name, 4, 1, PNG_COLOR_TYPE_GRAY, 16, samples, false, {}, {}, gamma), w, h, rgb), "") << name;
        for (size_t p = 0; p < 4; ++p) EXPECT_FLOAT_EQ(rgb[3 * p + 1], static_cast<float>(light(stored[p]))) << name << " " << p;
    };
    expect("linear.png", 100000, [](double v) { return v; });
    expect("squared.png", 50000, [](double v) { return v * v; });
    expect("gamma22.png", 45455, [](double v) { return srgb_decode(v); });
    expect("untagged.png", 0, [](double v) { return srgb_decode(v); });
    // 8 bits through the byte table, linear.
    ASSERT_EQ(read_image(write("linear8.png", 2, 1, PNG_COLOR_TYPE_GRAY, 8, {51, 255}, false, {}, {}, 100000), w, h, rgb), "");
    EXPECT_FLOAT_EQ(rgb[0], static_cast<float>(51 / 255.0));
    EXPECT_FLOAT_EQ(rgb[3], 1.0f);
    // crex's own PNGs say sRGB and gAMA 45455: the sRGB curve.
    const std::string own = path("own_tags.png");
    ASSERT_EQ(write_image(own, 1, 1, {{"", {0.5f, 0.5f, 0.5f}, true, 3}}), "");
    ASSERT_EQ(read_image(own, w, h, rgb), "");
    EXPECT_FLOAT_EQ(rgb[0], linear(std::lround(255 * 0.5) / 255.0));
}

TEST_F(PngRead, AlphaCompositesOverBlack) {
    // Grey and alpha: 200 at half coverage, and 255 fully transparent. RGBA at 16 bits, interlaced.
    std::string file = write("grey_alpha.png", 2, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, {200, 128, 255, 0});
    int w = 0, h = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(file, w, h, rgb), "");
    for (size_t c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(rgb[c], static_cast<float>(srgb_decode(200 / 255.0) * (128 / 255.0)));
        EXPECT_EQ(rgb[3 + c], 0.0f);
    }
    std::vector<unsigned char> rgba;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x)
            for (int c = 0; c < 4; ++c) rgba.insert(rgba.end(), {static_cast<unsigned char>(c == 3 ? 0xff : 20 * x + 60 * y + c), 0});
    file = write("rgba16.png", 3, 3, PNG_COLOR_TYPE_RGB_ALPHA, 16, rgba, true);
    ASSERT_EQ(read_image(file, w, h, rgb), "");
    ASSERT_EQ(w, 3);
    ASSERT_EQ(h, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x)
            for (int c = 0; c < 3; ++c)
                EXPECT_FLOAT_EQ(rgb[static_cast<size_t>(3 * (3 * y + x) + c)],
                                static_cast<float>(srgb_decode((20 * x + 60 * y + c) * 256 / 65535.0) * (0xff00 / 65535.0)))
                    << x << " " << y << " " << c;
}

TEST_F(PngRead, PalettesAndTheirTransparencyExpand) {
    // 4-bit indices, two pixels a byte: 0 (red, opaque), 1 (blue, a quarter), 2 (white, none).
    const std::string file = write("palette.png", 3, 1, PNG_COLOR_TYPE_PALETTE, 4, {0x01, 0x20},
                                   false, {{255, 0, 0}, {0, 0, 255}, {255, 255, 255}}, {255, 64});
    int w = 0, h = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(file, w, h, rgb), "");
    const std::vector<float> want = {1, 0, 0, 0, 0, static_cast<float>(64 / 255.0), 1, 1, 1};
    for (size_t i = 0; i < want.size(); ++i) EXPECT_FLOAT_EQ(rgb[i], want[i]) << i;
}

TEST_F(PngRead, DamagedFilesAreErrorsThatNameThem) {
    const std::string good = path("good.png");
    ASSERT_EQ(write_image(good, 16, 16, {{"", std::vector<float>(16 * 16 * 3, 0.5f)}}), "");
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    int w = 0, h = 0;
    std::vector<float> rgb;
    ImageMetadata header;
    // Cut inside the pixels, and cut inside the header.
    for (size_t keep : {bytes.size() - 20, size_t{20}}) {
        const std::string cut = path("cut" + std::to_string(keep) + ".png");
        std::ofstream(cut, std::ios::binary) << bytes.substr(0, keep);
        const std::string error = read_image(cut, w, h, rgb);
        EXPECT_NE(error.find("cannot read '" + cut + "'"), std::string::npos) << error;
    }
    // A text chunk that claims 1.5 GB: refused before libpng allocates it.
    const std::string text = path("text.png");
    ASSERT_EQ(write_image(text, 2, 1, {{"", {1, 2, 3, 4, 5, 6}}}, {{"Software", std::string("crex")}}), "");
    std::ifstream t(text, std::ios::binary);
    std::string text_bytes((std::istreambuf_iterator<char>(t)), std::istreambuf_iterator<char>());
    const size_t chunk = text_bytes.find("tEXt") - 4;
    text_bytes.replace(chunk, 4, std::string("\x5e\x00\x00\x00", 4));
    std::ofstream(text, std::ios::binary | std::ios::trunc) << text_bytes;
    EXPECT_NE(read_image(text, w, h, rgb).find("its chunk 'tEXt' claims 1577058304 bytes"), std::string::npos) << read_image(text, w, h, rgb);
    EXPECT_NE(read_image_metadata(text, w, h, header).find("'tEXt'"), std::string::npos);
    // Headers that claim other sizes, their CRC mended: 65537 x 16 is refused by its width;
    // 4096 x 4096 by what the file could hold (deflate packs at most 1032 bytes into one), before
    // 64 MB are allocated for it.
    auto claiming = [&](uint32_t cw, uint32_t ch) {
        std::string b = bytes;
        for (int k = 0; k < 4; ++k) {
            b[16 + static_cast<size_t>(k)] = static_cast<char>(cw >> (24 - 8 * k) & 0xff);  // IHDR, big-endian
            b[20 + static_cast<size_t>(k)] = static_cast<char>(ch >> (24 - 8 * k) & 0xff);
        }
        const uLong crc = crc32(crc32(0, nullptr, 0), reinterpret_cast<const Bytef*>(b.data() + 12), 17);
        for (int k = 0; k < 4; ++k) b[29 + static_cast<size_t>(k)] = static_cast<char>(crc >> (24 - 8 * k) & 0xff);
        const std::string file = path("claims" + std::to_string(cw) + "x" + std::to_string(ch) + ".png");
        std::ofstream(file, std::ios::binary) << b;
        return file;
    };
    const std::string huge = claiming(65537, 16);
    const std::string error = read_image(huge, w, h, rgb);
    EXPECT_NE(error.find("cannot read '" + huge + "'"), std::string::npos) << error;
    EXPECT_NE(error.find("65537 x 16 pixels"), std::string::npos) << error;
    EXPECT_EQ(read_image_metadata(huge, w, h, header), error);
    const std::string claimed = claiming(4096, 4096);
    EXPECT_NE(read_image(claimed, w, h, rgb).find("is too small for the 4096 x 4096 pixels"), std::string::npos);
    // Its header alone is fine.
    ASSERT_EQ(read_image_metadata(claimed, w, h, header), "");
    EXPECT_EQ(w, 4096);
}

}  // namespace
}  // namespace crex
