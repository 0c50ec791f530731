/// \file text_pattern.h
/// RADIANCE's text patterns (brighttext, colortext, mixtext): lines of text in a vector font,
/// laid on a surface by an origin and the vectors of one character's width (right) and one
/// line's height (down), and whether a point lies inside a letter. The font is RADIANCE's
/// format (helvet.fnt): per character its code, vertex count and one closed polygon of
/// integer vertices in a 256-unit cell (y up), separate strokes and holes joined by doubled
/// edges, '#' comments. Spacing follows RADIANCE: fixed 255-unit cells, letters squeezed to a
/// gap (negative spacing), or spread evenly within each word (positive).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "runtime/base/vec3.h"

namespace crex {

struct Font {
    struct Glyph {
        bool present = false;
        std::vector<std::array<int, 2>> vertices;
        int left = 128, right = 128, bottom = 128, top = 128;  ///< extent, always spanning 128 (RADIANCE's)
    };
    std::array<Glyph, 256> glyphs;
    int mean_width = 0;  ///< over glyphs of non-zero extent
    const Glyph* glyph(char c) const {
        const Glyph& g = glyphs[static_cast<unsigned char>(c)];
        return g.present ? &g : nullptr;
    }
};

/// Parses a font file's text; false with `error` ("line L: what") when malformed.
bool parse_font(const std::string& text, Font& out, std::string& error);

/// Text laid out for lookups.
class TextLayout {
public:
    /// `spacing`: RADIANCE's optional last real argument (`has_spacing` false without one).
    TextLayout(Font font, std::vector<std::string> lines, Vec3 origin, Vec3 right, Vec3 down, bool has_spacing, double spacing);
    /// False when the right and down vectors are (nearly) parallel or zero.
    bool valid() const { return valid_; }
    /// Whether `point` (in the pattern's coordinates) lies inside a letter.
    bool inside(const Vec3& point) const;

private:
    struct Line {
        std::string text;
        std::vector<int> offsets;  ///< per character, from the previous one's start (the first: from the line's start); then the tail
        int width = 0;
    };
    bool in_glyph(double x, double y, const Font::Glyph* g) const;
    Font font_;
    std::vector<Line> lines_;
    Vec3 origin_, right_, down_;  ///< right_, down_: the dual basis of the right and down vectors
    double scale_ = 255;          ///< font units per character width
    bool valid_ = false;
};

}  // namespace crex
