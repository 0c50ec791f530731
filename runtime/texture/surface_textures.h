/// \file surface_textures.h
/// A scene's textures at render time: every texture reference of its materials, opened once
/// through one texture backend (OpenImageIO's TextureSystem: one cache per render, within its
/// share of --max-memory), and what shading asks of them:
///  - a material's parameter values at a point, filtered over the pixel's footprint there;
///  - the shading normal a normal or bump map gives;
///  - the opacity at a point, sharp (cut-outs are decided per ray, not filtered).
/// A texture that cannot be read shows magenta where it gives a colour and leaves the
/// material's constant elsewhere; either way it is one warning, never a failed render.
#pragma once

#include <nlohmann/json.hpp>
#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/io/texture_backend.h"
#include "runtime/scene/material.h"
#include "runtime/scene/scene.h"

namespace crex {

inline constexpr size_t kDefaultTextureCacheBytes = size_t{64} << 20;

/// The texture cache's share of a render's --max-memory: an eighth, between 16 MiB and 1 GiB.
size_t texture_cache_bytes(size_t max_memory);

/// Where a texture is read: the point (scene coordinates, for planar mappings), its mesh
/// (u, v) and how both change across the pixel's footprint (zero: the sharpest lookup).
struct SurfacePoint {
    Vec3 position;         ///< scene (world) coordinates
    Vec3 dpdx, dpdy;       ///< footprint of the pixel on the surface
    double u = 0, v = 0;   ///< the mesh's texture coordinates (0 without them)
    double dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;
    bool indirect = false;  ///< no eye sees it: the cheaper filter (TextureLookup::indirect)
    /// Its light is averaged with hundreds of others' (an irradiance record's hemisphere ray,
    /// a photon): read bilinearly from the image's coarse copy, at most kCoarseSize texels a
    /// side, made once by the backend's own filter. A lookup through the TextureSystem cost
    /// ~450 ns, and such hits made most of a textured room's lookups.
    bool coarse = false;
};

/// One image the scene uses, as `crex scene-info` and `--format json` list it.
struct TextureImage {
    std::string name;   ///< the file, or the embedded image's name
    TextureImageInfo info;
    std::string error;  ///< why it cannot be read ("" when it can)
    uint64_t failed_lookups = 0;  ///< lookups the backend could not answer (a damaged or truncated file): magenta
    /// Lookups whose filtered texels were not finite (NaN or infinite texels in the file, which
    /// filtering and MIP levels spread to their neighbours): they read the nearest texel instead.
    uint64_t non_finite_lookups = 0;
    /// The tiled copy it is read through (tiled_copies.h), "" when it is read itself. With
    /// TiledCopies::kFindOnly, where the copy a render would make goes (tiled_copy_made false).
    std::string tiled_copy;
    bool tiled_copy_made = false;
    /// Texels held when all of it is in memory, MIP levels included (4/3 of the top level).
    uint64_t memory_bytes() const;
};

/// One readable image as `crex scene-info` lists it: name, size, channels, format, bytes on disk
/// and in memory, and the tiled copy it is read through; a line each, each ending in a newline.
std::string image_text(const TextureImage& image);

/// What the textures cost a render.
struct TextureStats {
    std::vector<TextureImage> images;
    TextureCacheStats cache;
    uint64_t lookups = 0;          ///< crex's requests (a colour is one, a bump map's height one)
    double lookup_seconds = 0;     ///< in the TextureSystem's lookups, summed over threads
    uint64_t coarse_lookups = 0;   ///< answered from the images' coarse copies (not timed, not in `lookups`)
    uint64_t mask_lookups = 0;     ///< cut-out tests answered from opacity masks (not timed, not in `lookups`)
    uint64_t mask_bytes = 0;       ///< the opacity masks' texels
    /// What was counted after `earlier` (the same textures' stats, taken before): a render of a
    /// scene that an earlier one built. Sizes (memory, peaks, files) stay as they are now.
    TextureStats since(const TextureStats& earlier) const;
};

/// The images as `crex scene-info --format json` lists them, and the cache and lookups as
/// `crex run --format json` reports them: `render_thread_seconds` is the render's time times
/// its worker threads (what the lookups' share is of), `render_cpu_seconds` the CPU it used.
nlohmann::json images_json(const std::vector<TextureImage>& images);
nlohmann::json to_json(const TextureStats& s, double render_thread_seconds, double render_cpu_seconds);

/// What SurfaceTextures does with a file without tiles larger than its cache: makes its tiled
/// copy where there is none yet (a render), or only uses one that is there (`crex scene-info`,
/// which reads headers only).
enum class TiledCopies { kMake, kFindOnly };

/// Progress of long work while textures are opened (a tiled copy being made): what, and the
/// fraction done.
using TextureProgress = std::function<void(const std::string& step, double fraction)>;

class SurfaceTextures {
public:
    /// Opens every image the materials reference. `warnings`: one line per image that cannot
    /// be read, or read through a tiled copy just made. Throws std::runtime_error when the
    /// image plugin cannot be loaded at all.
    SurfaceTextures(const Scene& scene, size_t cache_bytes, std::vector<Diagnostic>& warnings, TiledCopies copies = TiledCopies::kMake,
                    TextureProgress progress = {});
    ~SurfaceTextures();

    /// Has material `m` any texture (else its constants are all there is)?
    bool textured(uint32_t m) const { return slots_[m].any; }
    /// Does material `m` cut holes (an opacity texture, or a constant opacity below 1)?
    bool cuts_out(uint32_t m) const { return slots_[m].cuts_out; }
    /// Has material `m` a normal or bump map?
    bool perturbs_normal(uint32_t m) const { return slots_[m].normal.image != kNone || slots_[m].bump.image != kNone; }

    /// Material `m`'s parameters at `p` (constants where it has no texture).
    MaterialValues values(uint32_t m, const SurfacePoint& p) const;
    /// Its emission alone at `p` (0 without one): what direct lighting reads at a sample of a
    /// textured emission.
    Vec3 emission(uint32_t m, const SurfacePoint& p) const;

    /// The shading normal after material `m`'s normal or bump map at `p`, for the unit normal
    /// `n` (on the side the ray came from) and the surface's derivatives in mesh (u, v)
    /// (zero: no map applies). A flat normal map returns `n` itself, bit for bit.
    Vec3 perturbed_normal(uint32_t m, const SurfacePoint& p, const Vec3& n, const Vec3& dpdu, const Vec3& dpdv) const;

    /// Material `m`'s opacity at (u, v) and `position`, sharp.
    double opacity(uint32_t m, const SurfacePoint& p) const;

    TextureStats stats() const;

private:
    static constexpr int kNone = -2;     ///< no texture in this slot
    static constexpr int kMissing = -1;  ///< a texture that cannot be read
    struct Slot {
        int image = kNone;
        TextureRef ref;
        bool srgb = false;
        bool grey = false;  ///< a one-channel image read as a colour: its value thrice
        int mask = -1;      ///< an opacity slot's mask (masks_), -1: read through the backend
    };
    struct MaterialSlots {
        Slot color, specular_color, specularity, roughness, metallic, normal, bump, opacity, emission;
        bool any = false, cuts_out = false;
    };
    /// What a slot reads: a colour (1 channel replicated, or 3), a number, a normal (3) or an
    /// opacity (a missing alpha channel is opaque).
    enum class SlotKind { kColour, kScalar, kVector, kOpacity };
    Slot open_slot(const std::optional<TextureRef>& ref, SlotKind kind, const Scene& scene, std::vector<Diagnostic>& warnings);
    /// `image` (file `file`, or the embedded `bytes`; opened as `id`) has no tiles and is larger
    /// than the cache: its tiled copy's id, made if need be, or -1 with image.error (or,
    /// finding only, `id`).
    int open_tiled_copy(const std::string& file, const std::string* bytes, int id, TextureImage& image, std::vector<Diagnostic>& warnings);
    /// (s, t) and footprint of `slot` at `p`.
    TextureLookup coordinates(const Slot& slot, const SurfacePoint& p) const;
    /// A filtered lookup of `n` channels (1 or 3) at `p` (from the coarse copy where `p` asks and
    /// no derivatives are wanted); false when the slot's image cannot be read.
    bool read(const Slot& slot, const SurfacePoint& p, int n, float* out, float* d_ds = nullptr, float* d_dt = nullptr) const;
    Vec3 colour(const Slot& slot, const SurfacePoint& p, const Vec3& constant) const;
    double scalar(const Slot& slot, const SurfacePoint& p, double constant) const;

    /// An image's coarse copy (SurfacePoint::coarse): all its channels (at most 4), made on
    /// first use; `ok` false when the image cannot be read (lookups then go to the backend).
    struct CoarseImage {
        std::once_flag once;
        int width = 0, height = 0, channels = 0;
        std::vector<float> texels;
        bool ok = false;
    };
    const CoarseImage& coarse_image(size_t image) const;
    /// A bilinear lookup of `n` channels from `first_channel` of `slot`'s coarse copy; false
    /// when the copy cannot answer it.
    bool read_coarse(const Slot& slot, const TextureLookup& at, int first_channel, int n, float* out) const;

    /// A cut-out's opacity channel at full resolution, in memory: a cut-out is tested at every
    /// candidate hit Embree finds on it (shadow and cache rays through foliage too), and the
    /// backend's sharp lookup, ~700 ns, was a tenth of a textured room's render. Read
    /// bilinearly, as the backend reads a lookup without a footprint. Made on first use; `ok`
    /// false when the image cannot be read (tests then go to the backend).
    struct OpacityMask {
        std::once_flag once;
        int image = 0, channel = 0;
        int width = 0, height = 0;
        std::vector<uint8_t> bytes;  ///< 8-bit images: the texels as stored
        std::vector<float> floats;   ///< any other
        bool ok = false;
    };
    /// Masks take at most this share of the texture cache's bytes, given out in material order
    /// (a render's masks do not depend on which thread asks first); the rest read the backend.
    static constexpr size_t kMaskShare = 8;
    const OpacityMask& opacity_mask(int mask) const;
    /// The slot's mask for `slot`, planned within `budget` bytes (left unplanned beyond it).
    void plan_mask(Slot& slot, size_t& budget);

    const Scene& scene_;
    size_t cache_bytes_ = 0;  ///< the texture cache's share of --max-memory
    TiledCopies copies_ = TiledCopies::kMake;
    TextureProgress progress_;
    std::unique_ptr<TextureBackend> backend_;
    std::vector<TextureImage> images_;
    std::vector<int> ids_;  ///< per image: the backend's id, -1 when it cannot be read
    std::vector<MaterialSlots> slots_;  ///< per scene material
    mutable std::vector<std::unique_ptr<CoarseImage>> coarse_;  ///< per image
    mutable std::vector<std::unique_ptr<OpacityMask>> masks_;
    mutable std::unique_ptr<std::atomic<uint64_t>[]> failed_lookups_;  ///< per image
    mutable std::unique_ptr<std::atomic<uint64_t>[]> non_finite_lookups_;  ///< per image
    uint64_t mask_bytes_ = 0;
    struct Counters {
        uint64_t lookups = 0, coarse_lookups = 0, mask_lookups = 0;
        double seconds = 0;
    };
    mutable tbb::enumerable_thread_specific<Counters> counters_;
};

}  // namespace crex
