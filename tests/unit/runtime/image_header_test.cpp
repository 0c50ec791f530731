// Image headers keep their types, and one-channel layers stay one channel, through a write
// and a read (EXR) and into an 8-bit file (PNG, grey).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

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

// OpenEXR's C++ library allocates an attribute's claimed size before reading it: an attribute
// larger than what its file has left is refused first (a 1.4 KB file that claimed 1.4 GB took
// 1.4 GB and 7.5 s to fail), for every reader, with the file and the attribute named.
TEST_F(ImageHeader, AnAttributeLargerThanItsFileIsRefused) {
    const std::string good = path("good.exr");
    ASSERT_EQ(write_image(good, 2, 1, {{"", {1, 2, 3, 4, 5, 6}}}, {{"crex:text", std::string("words")}}), "");
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // The first attribute: its name and type, null-terminated, then its size.
    const size_t name_end = bytes.find('\0', 8), type_end = bytes.find('\0', name_end + 1);
    const std::string name = bytes.substr(8, name_end - 8), type = bytes.substr(name_end + 1, type_end - name_end - 1);
    bytes.replace(type_end + 1, 4, std::string("\xff\xff\xff\x7f", 4));
    const std::string bad = path("bad.exr");
    std::ofstream(bad, std::ios::binary) << bytes;
    int w = 0, h = 0;
    std::vector<float> rgb;
    ImageMetadata header;
    const std::string want = "cannot read '" + bad + "': its header attribute '" + name + "' (" + type + ") claims 2147483647 bytes where the file has ";
    EXPECT_EQ(read_image(bad, w, h, rgb).rfind(want, 0), 0u) << read_image(bad, w, h, rgb);
    EXPECT_EQ(read_image_layer(bad, "D", w, h, rgb).rfind(want, 0), 0u);
    EXPECT_EQ(read_image_metadata(bad, w, h, header).rfind(want, 0), 0u);
    // An attribute no reader needs: refused too.
    std::ifstream again(good, std::ios::binary);
    const std::string sound((std::istreambuf_iterator<char>(again)), std::istreambuf_iterator<char>());
    std::string optional = sound;
    const std::string text_attribute("crex:text\0string\0", 17);
    const size_t text = optional.find(text_attribute);
    ASSERT_NE(text, std::string::npos);
    optional.replace(text + text_attribute.size(), 4, std::string("\x00\x00\x00\x70", 4));  // 1.9 GB
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << optional;
    EXPECT_EQ(read_image(bad, w, h, rgb).rfind("cannot read '" + bad + "': its header attribute 'crex:text' (string) claims 1879048192 bytes", 0), 0u)
        << read_image(bad, w, h, rgb);
    // Cut inside its attributes.
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << bytes.substr(0, type_end);
    EXPECT_EQ(read_image(bad, w, h, rgb).rfind("cannot read '" + bad + "': ", 0), 0u) << read_image(bad, w, h, rgb);
}

// An attribute whose value takes other than its declared size is refused: OpenEXR's C core
// reads the header by the declared sizes, the C++ library by the values, and where they differ
// the C++ library reads the rest out of step, as attributes the core never checked (a fuzzed
// 347-byte file whose channel list ran past its size made it allocate a 1 GB string).
TEST_F(ImageHeader, AnAttributeWhoseValueIsNotItsSizeIsRefused) {
    const std::string good = path("good.exr");
    ASSERT_EQ(write_image(good, 2, 1, {{"", {1, 2, 3, 4, 5, 6}}}, {{"crex:text", std::string("words")}}), "");
    std::ifstream in(good, std::ios::binary);
    const std::string sound((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string bad = path("bad.exr");
    int w = 0, h = 0;
    std::vector<float> rgb;
    auto refused = [&](const std::string& bytes, const std::string& why) {
        std::ofstream(bad, std::ios::binary | std::ios::trunc) << bytes;
        const std::string error = read_image(bad, w, h, rgb);
        EXPECT_EQ(error.rfind("cannot read '" + bad + "': " + why, 0), 0u) << error;
    };
    auto size_at = [&](const std::string& name_and_type) {
        const size_t at = sound.find(name_and_type);
        EXPECT_NE(at, std::string::npos) << name_and_type;
        return at + name_and_type.size();
    };
    // The channel list one byte shorter than its entries and their end: its last byte is then
    // the next attribute's first.
    std::string bytes = sound;
    const size_t chlist = size_at(std::string("channels\0chlist\0", 16));
    bytes[chlist] = static_cast<char>(bytes[chlist] - 1);
    refused(bytes, "its header attribute 'channels' (chlist) has no end within its size");
    // A fixed-size type declared larger: the C++ library would read 4 bytes and go on at the fifth.
    bytes = sound;
    const size_t ratio = size_at(std::string("pixelAspectRatio\0float\0", 23));
    bytes.replace(ratio, 4, std::string("\x08\x00\x00\x00", 4));
    refused(bytes, "its header attribute 'pixelAspectRatio' (float) claims 8 bytes where its value takes 4");
    // A string vector whose string claims more than the vector holds, and a preview whose
    // pixels do: each would be allocated as claimed.
    for (const auto& [type, value, why] : std::vector<std::tuple<std::string, std::string, std::string>>{
             {"stringvector", std::string("\xff\xff\xff\x0f", 4), "its header attribute 'crex:extra' (stringvector) holds a string of 268435455 bytes"},
             {"preview", std::string("\x00\x40\x00\x00\x00\x40\x00\x00", 8), "its header attribute 'crex:extra' (preview) claims 8 bytes where its value takes 1073741832"}}) {
        bytes = sound;
        const std::string attribute = "crex:extra" + std::string(1, '\0') + type + std::string(1, '\0') +
                                      std::string(1, static_cast<char>(value.size())) + std::string(3, '\0') + value;
        bytes.insert(8, attribute);
        refused(bytes, why);
    }
    // The sound file still reads.
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << sound;
    EXPECT_EQ(read_image(bad, w, h, rgb), "");
}

// A header that claims more pixels than its file could hold compressed is refused before the
// pixels' memory (400 MB of RGB at 2^25 pixels) is taken.
TEST_F(ImageHeader, AHeaderClaimingMorePixelsThanItsFileHoldsIsRefused) {
    const std::string good = path("small.exr");
    ASSERT_EQ(write_image(good, 2, 2, {{"", std::vector<float>(12, 0.5f)}}), "");
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const std::string window : {"dataWindow", "displayWindow"}) {  // box2i: xmin ymin xmax ymax, little-endian
        const size_t at = bytes.find(window + std::string("\0box2i\0", 7));
        ASSERT_NE(at, std::string::npos);
        const size_t value = at + window.size() + 7 + 4;
        bytes.replace(value + 8, 8, std::string("\xff\x0f\x00\x00\xff\x0f\x00\x00", 8));  // 4096 x 4096
    }
    bytes += std::string(4096, '\0');  // room for its line-offset table (256 chunks), which OpenEXR reads as it opens
    const std::string bad = path("claims.exr");
    std::ofstream(bad, std::ios::binary) << bytes;
    int w = 0, h = 0;
    std::vector<float> rgb;
    const std::string error = read_image(bad, w, h, rgb);
    EXPECT_NE(error.find("is too small for the 4096 x 4096 pixels its header claims"), std::string::npos) << error;
}

}  // namespace
}  // namespace crex
