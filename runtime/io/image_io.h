/// \file image_io.h
/// Writing images through OpenImageIO, atomically (temporary file + rename):
///  - .exr: 32-bit float (half floats overflow at 65504), optionally with one layer per AOV
///    ("D.R", "D.G", "D.B", ...) besides the composite's R, G, B;
///  - .hdr: Radiance RGBE;
///  - .png (and other 8-bit formats): tone-mapped for eyes (spec/pipeline.md §7: exposure key
///    0.18 over the log-average luminance, then the sRGB curve).
#pragma once

#include <array>
#include <future>
#include <string>
#include <variant>
#include <vector>

namespace crex {

struct ImageLayer {
    std::string name;          ///< "" for the composite (channels R, G, B)
    std::vector<float> rgb;    ///< linear RGB, row-major, top row first (one value a pixel when `channels` is 1)
    /// rgb already holds display values in [0, 1] (maps, heat pictures): 8-bit formats store
    /// them as they are, without the tone map.
    bool display_referred = false;
    /// 3: R, G, B a pixel. 1: one value a pixel (a map, a count), stored as one channel: in an
    /// EXR named after the layer ("Y" for the unnamed one), in a PNG as grey.
    int channels = 3;
};

/// The interface version of the image plugin (libcrex_oiio.so): raised whenever the entry
/// points change, so a plugin from another build is refused instead of called wrongly (an
/// old binary that loaded a newer plugin crashed at the end of a 40-minute render).
inline constexpr int kImagePluginAbi = 9;

/// A 4x4 matrix as OpenEXR's M44f holds it (worldToCamera, worldToNDC): row-major, points as
/// row vectors (p' = p M), so the translation is the last row.
struct Matrix44 {
    std::array<float, 16> m{};
};
/// CIE 1931 xy of the red, green and blue primaries and of the white point, in that order
/// (OpenEXR's "chromaticities").
struct Chromaticities {
    std::array<float, 8> xy{};
};
/// The colour space of every image crex writes: linear Rec. 709 / sRGB primaries, white D65.
inline constexpr Chromaticities kRec709Chromaticities{{0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f}};

/// One attribute of an image's header, typed as OpenEXR stores it: a number is an int or a
/// float that a reader gets as a number, not as text to parse.
using AttributeValue = std::variant<std::string, int, float, Matrix44, Chromaticities>;
struct ImageAttribute {
    std::string name;
    AttributeValue value;
    /// The value as text: a string as it is, numbers as they print ("%.9g"), a matrix's or
    /// the chromaticities' numbers separated by spaces.
    std::string text() const;
};
/// Attributes stored in the file's header where the format keeps them (EXR: every one, typed;
/// "Software" goes where readers look for it): what made the image.
using ImageMetadata = std::vector<ImageAttribute>;
/// The text of the attribute `name` (ImageAttribute::text), or "" when the header has none.
std::string attribute_text(const ImageMetadata& metadata, const std::string& name);

/// Returns "" on success, else why it failed (nothing is left behind on failure).
std::string write_image(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers,
                        const ImageMetadata& metadata = {});

/// Whether writing `path` takes the OpenImageIO plugin: every format but OpenEXR and PNG,
/// which crex writes through their own libraries (image_formats.h). Reading takes it for every
/// format but OpenEXR and PNG (and for layouts of those their readers leave to it), and
/// textures take it.
bool needs_image_plugin(const std::string& path);
/// Loads the image plugin now rather than at its first use (0.3 s or more: it relocates
/// OpenImageIO's libraries), for a write that must be quick when it comes: rank 0's finished
/// rows, in the second mpirun gives it between SIGTERM and SIGKILL. "" when loaded.
std::string load_image_plugin();
/// Where any of `paths` is written through the plugin (needs_image_plugin), starts
/// load_image_plugin() on a thread of its own and returns at once, so that a command which
/// will write them renders while OpenImageIO's libraries are relocated (0.3 s here) instead of
/// after; else does nothing (an invalid future). Whoever reads or writes through the plugin
/// first waits for the load; the returned future's destructor waits too, so no load outlives
/// the command. A failure to load is not the preload's to say: the first use meets it.
std::future<void> preload_image_plugin(const std::vector<std::string>& paths);

/// The sRGB curve undone: an sRGB-encoded value in [0, 1] (what an 8- or 16-bit file stores) as
/// linear light.
double srgb_decode(double v);
/// Tone map of spec/pipeline.md §7 to 8-bit sRGB (exposed for tests and reports).
std::vector<unsigned char> tone_map_srgb8(const std::vector<float>& rgb);
/// What an 8-bit file stores for `layer` of `pixels` pixels: its values as they are where
/// they are display-referred, else through tone_map_srgb8 (a one-channel layer as grey through
/// the same tone map as colour); one byte a pixel for one channel, else three.
std::vector<unsigned char> eight_bit_pixels(const ImageLayer& layer, size_t pixels);
/// The same tone map in two halves, so guidance operators and metrics can see several
/// images through one exposure: the exposure (0.18 over the log-average luminance) of an
/// image, and linear RGB to display values in [0, 1] (Reinhard, then the sRGB curve).
double display_exposure(const std::vector<float>& rgb);
std::vector<float> to_display(const std::vector<float>& rgb, double exposure);
/// The same on `count` values, for callers that split an image between threads.
void to_display(const float* rgb, float* out, size_t count, double exposure);
/// An image as read_image() gave it, as a viewer sees it (display values in [0, 1]): an 8-bit
/// file (`ldr`: read_image linearised it) as stored, linear radiance through to_display() with
/// `exposure`, which is set from this image when not above 0, so that the frames of a sequence
/// can all be seen through the first one's (an exposure that changed would flicker).
std::vector<float> as_displayed(const std::vector<float>& rgb, bool ldr, double& exposure);

/// Reads an image's size and the attributes of its header (EXR: every one written by
/// write_image's `metadata`, with its type; attributes of other types come as their text),
/// without its pixels. Returns "" on success.
std::string read_image_metadata(const std::string& path, int& width, int& height, ImageMetadata& metadata);

/// Reads the layer `layer` of a multi-layer EXR (channels LAYER.R, LAYER.G, LAYER.B, as
/// write_image names them) as float RGB. Returns "" on success, else why (no such layer).
std::string read_image_layer(const std::string& path, const std::string& layer, int& width, int& height, std::vector<float>& rgb);

/// Reads an image's first three channels as linear float RGB (8- and 16-bit sRGB inputs are
/// linearised; `display_referred` says whether they were). Returns "" on success.
std::string read_image(const std::string& path, int& width, int& height, std::vector<float>& rgb,
                       bool* display_referred = nullptr);

}  // namespace crex
