// Image headers keep their types, and one-channel layers stay one channel, through a write
// and a read (EXR) and into an 8-bit file (PNG, grey).
#include <gtest/gtest.h>

#include <variant>

#include "runtime/io/image_io.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

class ImageHeader : public testing::ScratchFolderTest {
protected:
    ImageHeader() : ScratchFolderTest("crex_image_header_") {}
};

TEST_F(ImageHeader, AttributesKeepTheirTypes) {
    const std::string file = path("typed.exr");
    Matrix44 m;
    for (int i = 0; i < 16; ++i) m.m[static_cast<size_t>(i)] = 0.5f * static_cast<float>(i);
    const ImageMetadata written = {{"crex:text", "words"}, {"crex:count", 42}, {"crex:seconds", 1.25f},
                                   {"worldToCamera", m}, {"chromaticities", kRec709Chromaticities}};
    ASSERT_EQ(write_image(file, 2, 1, {{"", {1, 2, 3, 4, 5, 6}}}, written), "");
    int w = 0, h = 0;
    ImageMetadata read;
    ASSERT_EQ(read_image_metadata(file, w, h, read), "");
    for (const ImageAttribute& want : written) {
        const ImageAttribute* got = nullptr;
        for (const ImageAttribute& a : read)
            if (a.name == want.name) got = &a;
        ASSERT_TRUE(got) << want.name;
        EXPECT_EQ(got->value.index(), want.value.index()) << want.name << ": " << got->text();
        EXPECT_EQ(got->text(), want.text()) << want.name;
    }
    EXPECT_EQ(attribute_text(read, "crex:count"), "42");
    EXPECT_EQ(attribute_text(read, "crex:seconds"), "1.25");
    EXPECT_EQ(attribute_text(read, "no such"), "");
}

TEST_F(ImageHeader, OneChannelLayersAreOneChannel) {
    const std::vector<float> values = {0.0f, 0.25f, 0.5f, 1.0f};
    for (const char* name : {"map.exr", "map.png"}) {
        const std::string file = path(name);
        ASSERT_EQ(write_image(file, 2, 2, {{"task", values, true, 1}}), "") << name;
        int w = 0, h = 0;
        std::vector<float> rgb;
        bool display = false;
        ASSERT_EQ(read_image(file, w, h, rgb, &display), "") << name;
        ASSERT_EQ(rgb.size(), 12u);
        for (size_t p = 0; p < 4; ++p) {
            EXPECT_EQ(rgb[3 * p], rgb[3 * p + 1]) << name;  // grey: the one channel in each
            EXPECT_EQ(rgb[3 * p], rgb[3 * p + 2]) << name;
        }
        if (!display) {  // the EXR holds the values themselves
            for (size_t p = 0; p < 4; ++p) EXPECT_FLOAT_EQ(rgb[3 * p], values[p]);
        } else {  // the PNG holds them as 8-bit display values, read back linearised
            EXPECT_FLOAT_EQ(rgb[0], 0.0f);
            EXPECT_FLOAT_EQ(rgb[9], 1.0f);
        }
    }
}

}  // namespace
}  // namespace crex
