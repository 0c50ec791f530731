/// \file windowed_image.h
/// References that scale with the frame (issue 32): a converged reference of a few windows of
/// the full-resolution frame instead of all of it. A windowed image holds its windows side by
/// side (an atlas: window i from column `WindowAtlas::column[i]`, row 0, top-aligned; black
/// where a window is shorter than the tallest) and says in its header which pixels of which
/// frame they are. Beside the reference's own pixels it carries what the windows alone cannot
/// give: the exposure of the whole frame, so that the perceptual metrics see the windows as
/// they would be displayed in the frame, and (layer "attention") the saliency of the whole
/// frame at the windows' pixels, the weights of the attention-weighted FLIP.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runtime/driver/sample_passes.h"
#include "runtime/io/image_io.h"

namespace crex {

/// "X,Y,W,H" (whole numbers, X and Y from 0, W and H from 1); nullopt for anything else.
std::optional<PixelWindow> parse_window(const std::string& text);
/// "X,Y,W,H;X,Y,W,H..." (what a windowed image's header holds) and back.
std::string format_windows(const std::vector<PixelWindow>& windows);
std::optional<std::vector<PixelWindow>> parse_windows(const std::string& text);
/// "" when there is at least one window, every window lies inside a width x height frame and
/// none overlaps another; else what is wrong, naming the window.
std::string check_windows(const std::vector<PixelWindow>& windows, int width, int height);

/// Where each window lies in a windowed image.
struct WindowAtlas {
    explicit WindowAtlas(std::vector<PixelWindow> windows);
    std::vector<PixelWindow> windows;
    std::vector<int> column;  ///< of each window's first pixel
    int width = 0, height = 0;
    /// The windows' pixels of a full frame (`channels` floats a pixel, `frame_width` wide).
    std::vector<float> pack(const std::vector<float>& frame, int frame_width, int channels = 3) const;
    /// Window i's pixels of an atlas image.
    std::vector<float> window(const std::vector<float>& atlas, size_t i, int channels = 3) const;
};

/// A window's pixels of an image `width` pixels wide.
std::vector<float> crop(const std::vector<float>& image, int width, const PixelWindow& w, int channels = 3);

/// The header of a reference crex wrote, windowed or not (a whole frame is one window).
struct ReferenceHeader {
    int frame_width = 0, frame_height = 0;
    std::vector<PixelWindow> windows;
    uint32_t spp = 0;             ///< camera samples per pixel in total, over every run
    uint64_t seed = 0;
    std::string scene;            ///< as given on the command line
    std::string scene_hash;       ///< scene_content_hash() of the scene it was rendered from
    std::string crex;             ///< the crex it was rendered with
    std::string commands;         ///< the command of each run that made it, one per line
    std::string runs;             ///< samples of each run: "4096+4096"
    double render_seconds = 0;    ///< over every run
    double exposure = 0;          ///< of the whole frame's tone map (0: not recorded)
    std::string context;          ///< how the exposure and the attention layer were found
    /// Its own RMSE against the converged image, estimated when its last run was added to the
    /// runs before (own_rmse_estimate); 0: not known (one run).
    double own_rmse = 0;
    bool whole_frame() const;     ///< one window, the frame itself: an ordinary image
};

/// The header as image attributes ("crex:..."), and back: nullopt without "crex:windows"
/// (an image crex did not write as a reference, or an older one); `error` says what is
/// malformed in one that has it.
ImageMetadata reference_metadata(const ReferenceHeader& header);
std::optional<ReferenceHeader> reference_header(const ImageMetadata& metadata, std::string& error);

/// The layer of a windowed reference holding the whole frame's saliency at its pixels.
inline constexpr const char* kAttentionLayer = "attention";

struct ReferenceImage {
    ReferenceHeader header;
    int width = 0, height = 0;    ///< of the atlas (the frame's, for a whole frame)
    std::vector<float> rgb;       ///< linear RGB, the atlas
    std::vector<float> attention; ///< one weight a pixel of the atlas; empty if none was recorded
};

/// Written atomically (an EXR: float, with the attention layer when there is one); `software`:
/// attributes naming what wrote it, first in the header.
std::string write_reference_image(const std::string& path, const ReferenceImage& image, const ImageMetadata& software = {});
/// Reads a reference crex wrote; `image` is nullopt (and "" returned) for an image without a
/// reference header. Checks that the atlas matches its windows. Errors about the header say
/// "header" (the caller tells them from a file it cannot read).
std::string read_reference_image(const std::string& path, std::optional<ReferenceImage>& image);

/// The mean of two independent estimates of the same pixels, `a` of `a_samples` samples a pixel
/// and `b` of `b_samples`, as one of their sum: what accumulation makes.
std::vector<float> accumulate_samples(const std::vector<float>& a, uint32_t a_samples, const std::vector<float>& b, uint32_t b_samples);

/// The RMSE against the converged image of the mean of `a` (a mean of `a_samples`) and `b`
/// (`b_samples` more, independent): a - b has the per-sample variance times 1/na + 1/nb, and
/// their mean that variance over na + nb, so it is rmse(a, b) sqrt(na nb) / (na + nb).
double own_rmse_estimate(const std::vector<float>& a, uint32_t a_samples, const std::vector<float>& b, uint32_t b_samples);

}  // namespace crex
