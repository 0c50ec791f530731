#include "runtime/io/tiled_copy_oiio.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

namespace crex::oiio {
namespace {

constexpr int kTile = 64;  // maketx's tile size, and the rows of a band

struct FileCloser {
    void operator()(std::FILE* f) const {
        if (f) std::fclose(f);
    }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// One MIP level being made: its size, and where its rows come from (the source for level 0, the
// temporary file the level above wrote for the rest).
struct Level {
    int width = 0, height = 0;
    std::string rows_file;  // "" for level 0
};

// Writes the rows of the level below that rows [y0, y1) of a level (width w, height h) make:
// each the 2x2 box average of rows 2y and 2y + 1 (the last row itself where h is 1).
bool write_half_rows(const std::vector<float>& band, int y0, int y1, int w, int h, int channels, std::FILE* out) {
    const int w2 = std::max(1, w / 2), h2 = std::max(1, h / 2);
    std::vector<float> row(static_cast<size_t>(w2) * static_cast<size_t>(channels));
    auto at = [&](int x, int y, int c) { return band[(static_cast<size_t>(y - y0) * static_cast<size_t>(w) + static_cast<size_t>(x)) * static_cast<size_t>(channels) + static_cast<size_t>(c)]; };
    for (int y2 = (y0 + 1) / 2; y2 < h2 && 2 * y2 < y1; ++y2) {
        const int ya = 2 * y2, yb = std::min(2 * y2 + 1, h - 1);
        for (int x2 = 0; x2 < w2; ++x2) {
            const int xa = 2 * x2, xb = std::min(2 * x2 + 1, w - 1);
            for (int c = 0; c < channels; ++c)
                row[static_cast<size_t>(x2) * static_cast<size_t>(channels) + static_cast<size_t>(c)] =
                    0.25f * ((at(xa, ya, c) + at(xb, ya, c)) + (at(xa, yb, c) + at(xb, yb, c)));
        }
        if (std::fwrite(row.data(), sizeof(float), row.size(), out) != row.size()) return false;
    }
    return true;
}

}  // namespace

bool write_tiled_copy(const std::string& source, const std::string& target, std::string& error,
                      const std::function<void(double)>& progress) {
    namespace fs = std::filesystem;
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // texels as stored, as the texture cache reads them
    auto in = OIIO::ImageInput::open(source, &config);
    if (!in) {
        error = OIIO::geterror();
        return false;
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.deep || spec.nchannels <= 0) {
        error = "not a flat 2-D image";
        return false;
    }
    // A texture lookup spans the display window; a copy of the data window alone would not.
    if (spec.x != 0 || spec.y != 0 || spec.full_x != 0 || spec.full_y != 0 || spec.full_width != spec.width || spec.full_height != spec.height) {
        error = "its pixels do not fill its display window";
        return false;
    }
    const int channels = spec.nchannels;
    // Temporary names of this process's own: two processes (MPI ranks) may make the same copy
    // at once, and the last rename leaves one whole copy.
    const std::string temporary = target + "." + std::to_string(::getpid());
    std::vector<Level> levels{{spec.width, spec.height, ""}};
    while (levels.back().width > 1 || levels.back().height > 1)
        levels.push_back({std::max(1, levels.back().width / 2), std::max(1, levels.back().height / 2),
                          temporary + ".level" + std::to_string(levels.size())});
    const std::string part = temporary + ".part";
    double rows_total = 0, rows_done = 0;
    for (const Level& l : levels) rows_total += l.height;
    std::error_code ec;
    auto remove_temporaries = [&] {
        for (const Level& l : levels)
            if (!l.rows_file.empty()) fs::remove(l.rows_file, ec);
        fs::remove(part, ec);
    };
    auto fail = [&](const std::string& why) {
        error = why;
        remove_temporaries();
        return false;
    };

    auto out = OIIO::ImageOutput::create("tiff");
    if (!out) return fail(OIIO::geterror());
    std::vector<float> band;
    for (size_t k = 0; k < levels.size(); ++k) {
        const Level& level = levels[k];
        OIIO::ImageSpec out_spec(level.width, level.height, channels, spec.format);
        out_spec.channelnames = spec.channelnames;
        out_spec.alpha_channel = spec.alpha_channel;
        out_spec.tile_width = out_spec.tile_height = kTile;
        out_spec.attribute("compression", "zip");
        out_spec.attribute("oiio:UnassociatedAlpha", 1);
        // TIFF has no MIP levels of its own: as maketx's, they are subimages halving in size,
        // which a file marked as a texture is read as (OpenImageIO's TIFF reader).
        out_spec.attribute("textureformat", "Plain Texture");
        if (const std::string space = spec.get_string_attribute("oiio:ColorSpace"); !space.empty()) out_spec.attribute("oiio:ColorSpace", space);
        if (!out->open(part, out_spec, k == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendSubimage))
            return fail(out->geterror());
        File rows_in, rows_out;
        if (k > 0) {
            rows_in.reset(std::fopen(level.rows_file.c_str(), "rb"));
            if (!rows_in) return fail("cannot read back " + level.rows_file);
        }
        if (k + 1 < levels.size()) {
            rows_out.reset(std::fopen(levels[k + 1].rows_file.c_str(), "wb"));
            if (!rows_out) return fail("cannot write " + levels[k + 1].rows_file);
        }
        const size_t row_floats = static_cast<size_t>(level.width) * static_cast<size_t>(channels);
        for (int y0 = 0; y0 < level.height; y0 += kTile) {
            const int y1 = std::min(level.height, y0 + kTile);
            band.resize(row_floats * static_cast<size_t>(y1 - y0));
            if (k == 0) {
                if (!in->read_scanlines(0, 0, y0, y1, 0, 0, channels, OIIO::TypeFloat, band.data())) return fail(in->geterror());
            } else if (std::fread(band.data(), sizeof(float), band.size(), rows_in.get()) != band.size()) {
                return fail("cannot read back " + level.rows_file);
            }
            if (!out->write_tiles(0, level.width, y0, y1, 0, 1, OIIO::TypeFloat, band.data())) return fail(out->geterror());
            if (rows_out && !write_half_rows(band, y0, y1, level.width, level.height, channels, rows_out.get()))
                return fail("cannot write " + levels[k + 1].rows_file + " (is the disk full?)");
            rows_done += y1 - y0;
            if (progress) progress(rows_done / rows_total);
        }
        rows_in.reset();
        if (k > 0) fs::remove(level.rows_file, ec);
        if (rows_out && std::fflush(rows_out.get()) != 0) return fail("cannot write " + levels[k + 1].rows_file + " (is the disk full?)");
    }
    if (!out->close()) return fail(out->geterror());
    fs::rename(part, target, ec);
    if (ec) return fail("cannot rename " + part + ": " + ec.message());
    return true;
}

}  // namespace crex::oiio
