/// \file image_io.h
/// Writing images through OpenImageIO, atomically (temporary file + rename):
///  - .exr: 32-bit float (half floats overflow at 65504), optionally with one layer per AOV
///    ("D.R", "D.G", "D.B", ...) besides the composite's R, G, B;
///  - .hdr: Radiance RGBE;
///  - .png (and other 8-bit formats): tone-mapped for eyes (spec/pipeline.md §7: exposure key
///    0.18 over the log-average luminance, then the sRGB curve).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace crex {

struct ImageLayer {
    std::string name;          ///< "" for the composite (channels R, G, B)
    std::vector<float> rgb;    ///< linear RGB, row-major, top row first
    /// rgb already holds display values in [0, 1] (maps, heat pictures): 8-bit formats store
    /// them as they are, without the tone map.
    bool display_referred = false;
};

/// The interface version of the image plugin (libcrex_oiio.so): raised whenever the entry
/// points change, so a plugin from another build is refused instead of called wrongly (an
/// old binary that loaded a newer plugin crashed at the end of a 40-minute render).
inline constexpr int kImagePluginAbi = 4;

/// Attributes stored in the file's header where the format keeps them (EXR: every one, as
/// strings; "Software" goes where readers look for it): what made the image.
using ImageMetadata = std::vector<std::pair<std::string, std::string>>;

/// Returns "" on success, else why it failed (nothing is left behind on failure).
std::string write_image(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers,
                        const ImageMetadata& metadata = {});

/// Loads the image plugin now rather than at the first read or write (0.3 s or more: it
/// relocates OpenImageIO's libraries), for a write that must be quick when it comes: rank 0's
/// finished rows, in the second mpirun gives it between SIGTERM and SIGKILL. "" when loaded.
std::string load_image_plugin();

/// Tone map of spec/pipeline.md §7 to 8-bit sRGB (exposed for tests and reports).
std::vector<unsigned char> tone_map_srgb8(const std::vector<float>& rgb);
/// The same tone map in two halves, so guidance operators and metrics can see several
/// images through one exposure: the exposure (0.18 over the log-average luminance) of an
/// image, and linear RGB to display values in [0, 1] (Reinhard, then the sRGB curve).
double display_exposure(const std::vector<float>& rgb);
std::vector<float> to_display(const std::vector<float>& rgb, double exposure);

/// Reads an image's size and the string attributes of its header (EXR: every one written by
/// write_image's `metadata`), without its pixels. Returns "" on success.
std::string read_image_metadata(const std::string& path, int& width, int& height, ImageMetadata& metadata);

/// Reads the layer `layer` of a multi-layer EXR (channels LAYER.R, LAYER.G, LAYER.B, as
/// write_image names them) as float RGB. Returns "" on success, else why (no such layer).
std::string read_image_layer(const std::string& path, const std::string& layer, int& width, int& height, std::vector<float>& rgb);

/// Reads an image's first three channels as linear float RGB (8- and 16-bit sRGB inputs are
/// linearised; `display_referred` says whether they were). Returns "" on success.
std::string read_image(const std::string& path, int& width, int& height, std::vector<float>& rgb,
                       bool* display_referred = nullptr);

}  // namespace crex
