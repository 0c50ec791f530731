// RADIANCE's text patterns (issue 39): a font file read, and points inside and outside its
// letters where RADIANCE's layout puts them, worked out by hand for a two-letter font: 'I' a
// bar (x 100..150, y 48..200) and 'O' a square ring (50..200, hole 100..150, joined to the
// outline by a doubled edge, as RADIANCE's fonts join strokes).
#include <gtest/gtest.h>

#include "runtime/scene/text_pattern.h"

namespace crex {
namespace {

const char* kFont =
    "# a test font\n"
    "73 4  100 48  150 48  150 200  100 200\n"
    "79 10  50 48  200 48  200 200  50 200  50 48   100 100  100 150  150 150  150 100  100 100\n";

Font font() {
    Font f;
    std::string error;
    EXPECT_TRUE(parse_font(kFont, f, error)) << error;
    return f;
}

// A point `x` character widths along the line and `y` lines down (right = +x, down = -y).
bool at(const TextLayout& t, double x, double y) { return t.inside({x, -y, 0}); }

TEST(TextPattern, ReadsAFontAndItsMeanWidth) {
    const Font f = font();
    ASSERT_TRUE(f.glyph('I') && f.glyph('O'));
    EXPECT_FALSE(f.glyph('A'));
    EXPECT_EQ(f.glyph('I')->left, 100);
    EXPECT_EQ(f.glyph('O')->right, 200);
    EXPECT_EQ(f.mean_width, (50 + 150) / 2);
    Font bad;
    std::string error;
    EXPECT_FALSE(parse_font("73 2 10 10 300 10\n", bad, error));
    EXPECT_NE(error.find("line 1"), std::string::npos) << error;
    EXPECT_FALSE(parse_font("73 0\n73 0\n", bad, error));
    EXPECT_NE(error.find("defined twice"), std::string::npos) << error;
}

TEST(TextPattern, FixedCellsPutEachLetterIn255Units) {
    // Without a spacing argument each character is one cell: font x = 255 * fraction.
    const TextLayout t(font(), {"IO", "O"}, {0, 0, 0}, {1, 0, 0}, {0, -1, 0}, false, 0);
    ASSERT_TRUE(t.valid());
    EXPECT_TRUE(at(t, 0.5, 0.5));     // I's bar: x 127.5, y 127.5
    EXPECT_FALSE(at(t, 0.2, 0.5));    // left of it
    EXPECT_FALSE(at(t, 0.5, 0.95));   // below the baseline (y 12.75)
    EXPECT_TRUE(at(t, 1.3, 0.5));     // O's ring (x 76.5)
    EXPECT_FALSE(at(t, 1.5, 0.5));    // O's hole (x 127.5, y 127.5)
    EXPECT_TRUE(at(t, 0.3, 1.5));     // the second line's O
    EXPECT_FALSE(at(t, 1.3, 1.5));    // past the second line's end
    EXPECT_FALSE(at(t, 0.5, 2.5));    // no third line
    EXPECT_FALSE(at(t, -0.5, 0.5));
}

TEST(TextPattern, NegativeSpacingSqueezesLettersToAGap) {
    // Spacing -.2: a gap of 51 units between letters' extents (25 at each end), cells of
    // mean width + 51 = 151 units. Offsets: I starts at 25 + 25 - 100 = -50, O at -50 + (150 +
    // 25) + (25 - 50) = 100; so I's bar (100..150) lies at line units 50..100 and O (50..200,
    // hole 100..150) at 150..300, its hole 200..250.
    const TextLayout t(font(), {"IO"}, {0, 0, 0}, {1, 0, 0}, {0, -1, 0}, true, -0.2);
    auto units = [&](double u) { return at(t, u / 151, 0.5); };
    EXPECT_FALSE(units(45));
    EXPECT_TRUE(units(55));
    EXPECT_TRUE(units(95));
    EXPECT_FALSE(units(130));
    EXPECT_TRUE(units(160));
    EXPECT_FALSE(units(210));
    EXPECT_TRUE(units(280));
    EXPECT_FALSE(units(320));
}

TEST(TextPattern, ParallelVectorsAreRefused) {
    EXPECT_FALSE(TextLayout(font(), {"I"}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, false, 0).valid());
    EXPECT_FALSE(TextLayout(font(), {"I"}, {0, 0, 0}, {0, 0, 0}, {0, 1, 0}, false, 0).valid());
}

}  // namespace
}  // namespace crex
