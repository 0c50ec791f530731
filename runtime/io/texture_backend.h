/// \file texture_backend.h
/// Filtered texture lookups through OpenImageIO's TextureSystem (MIP-mapped, anisotropic,
/// tile-cached within a memory limit), behind an interface so that the rest of crex does not
/// link OpenImageIO: the image plugin (libcrex_oiio.so) makes the backend, and only a scene
/// with textures loads it. One backend per render; their images share one texture cache for the
/// process (texture_backend_oiio.cpp says why), whose limit is the largest any render asked for.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace crex {

/// What a texture image is, as the backend found it.
struct TextureImageInfo {
    int width = 0, height = 0, channels = 0;
    int alpha_channel = -1;  ///< which channel is alpha (-1: none)
    int bytes_per_channel = 0;
    bool eight_bit = false;   ///< 8-bit integer texels
    /// Colours held sRGB-encoded: the file says so (PNG and JPEG at any depth, a gamma of about
    /// 2.2), or says nothing and holds 8-bit texels.
    bool srgb = false;
    bool tiled = false;       ///< tiled in the file (maketx's .tx), so read tile by tile
    int mip_levels = 0;       ///< those of the file, or made in memory for a file without them
    uint64_t file_bytes = 0;  ///< on disk (or embedded), 0 when unknown
    std::string format;       ///< "png", "openexr", ...
};

/// Where a lookup reads and how far its filter reaches: (s, t) and the texture-space
/// derivatives of the pixel footprint (zero: the sharpest, bilinear on the finest level;
/// OpenImageIO's default there, bicubic, cost a cut-out's every test about 700 ns).
struct TextureLookup {
    float s = 0, t = 0;
    float dsdx = 0, dtdx = 0, dsdy = 0, dtdy = 0;
    /// For a hit no eye sees (a diffuse or glossy bounce, the cache's hemisphere rays, a
    /// photon): an isotropic trilinear lookup over a round footprint of the same area. What
    /// such a hit gives is averaged over a hemisphere of rays; the anisotropic filter a seen
    /// hit gets was over half of a textured room's lookup time (docs/textures.md).
    bool indirect = false;
    /// The nearest texel's value, not an interpolation (TextureFilter::kNearest).
    bool nearest = false;
};

enum class BackendWrap { kBlack, kClamp, kPeriodic, kMirror };

/// The texture cache's own counters (OpenImageIO's statistics).
struct TextureCacheStats {
    uint64_t queries = 0;          ///< filtered lookups answered
    uint64_t memory_bytes = 0;     ///< tile memory held at the end
    uint64_t memory_limit = 0;     ///< what it was given
    uint64_t bytes_read = 0;       ///< from files (decoded texels)
    uint64_t tiles_peak = 0;
    uint64_t cache_misses = 0;     ///< tile look-ups that had to read
    uint64_t files = 0;            ///< distinct images opened
    double file_io_seconds = 0;    ///< reading and decoding
};

class TextureBackend {
public:
    virtual ~TextureBackend() = default;
    /// Opens an image: a file, or (with `bytes`) an encoded image held in memory under that
    /// name. Returns its id (>= 0) and fills `info`, or -1 with `error`.
    virtual int open(const std::string& name, const std::string* bytes, TextureImageInfo& info, std::string& error) = 0;
    /// A filtered lookup of `channels` channels from `first_channel` into `out`; false when
    /// the image cannot be read (out untouched). Thread-safe.
    virtual bool lookup(int id, const TextureLookup& at, BackendWrap wrap_s, BackendWrap wrap_t, int first_channel, int channels,
                        float* out, float* d_ds = nullptr, float* d_dt = nullptr) = 0;
    /// Every texel of the finest level: `channels` channels from `first_channel`, row by row
    /// from the top, into `out` (width x height x channels floats, 8-bit values as v / 255).
    /// False when the image cannot be read (out then undefined). Thread-safe.
    virtual bool texels(int id, int first_channel, int channels, float* out) = 0;
    virtual TextureCacheStats stats() const = 0;
    /// Writes a tiled, MIP-mapped copy (a TIFF, as maketx's .tx) of image file `source` at
    /// `target`, reading the source row by row in bounded memory (tiled_copy_oiio.h); false
    /// with `error`, and nothing at `target`, on failure. `progress`: the fraction written.
    virtual bool make_tiled_copy(const std::string& source, const std::string& target, std::string& error,
                                 const std::function<void(double)>& progress) = 0;
    /// Forgets what was read of file `name` (a damaged tiled copy about to be made again): the
    /// next open or lookup reads the file afresh.
    virtual void forget(const std::string& name) = 0;
};

/// A backend whose cache holds at most `cache_bytes` of texels (OpenImageIO may hold more
/// while it makes the MIP levels of an image that has none: twice that image). Loads the
/// image plugin; null with `error` when it cannot.
std::unique_ptr<TextureBackend> make_texture_backend(size_t cache_bytes, std::string& error);

}  // namespace crex
