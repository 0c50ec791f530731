// The OpenImageIO side of texture_backend.h, in the image plugin (libcrex_oiio.so): one
// ImageCache and TextureSystem for the process, in which each render opens its images.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/strutil.h>
#include <OpenImageIO/texture.h>

#include <cmath>
#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <vector>

#include "runtime/base/image_signature.h"
#include "runtime/io/image_formats.h"
#include "runtime/io/texture_backend.h"
#include "runtime/io/tiled_copy_oiio.h"

namespace crex::oiio {
namespace {

OIIO::TextureOpt::Wrap wrap_of(BackendWrap w) {
    switch (w) {
    case BackendWrap::kBlack: return OIIO::TextureOpt::WrapBlack;
    case BackendWrap::kClamp: return OIIO::TextureOpt::WrapClamp;
    case BackendWrap::kPeriodic: return OIIO::TextureOpt::WrapPeriodic;
    case BackendWrap::kMirror: return OIIO::TextureOpt::WrapMirror;
    }
    return OIIO::TextureOpt::WrapPeriodic;
}

// One OpenImageIO cache and texture system for the whole process, never destroyed; each
// render's backend (below) opens its images in it. A private cache per render, destroyed with
// the render, crashed walks over a textured scene every few frames (each frame is a render):
// OpenImageIO aborted in the destructor of a tile of the old cache ("decr_tiles: m_mem_used >=
// 0") or a later lookup read freed memory. The threads that render keep per-thread state of the
// cache they used (a small cache of tiles) from one render to the next, and a cache that does
// not outlive them leaves it pointing at what the cache freed. One cache also keeps a walk's
// tiles from frame to frame, so each texture is read and MIP-mapped once per process.
class ProcessTextures {
public:
    struct Image {
        OIIO::ustring name;
        OIIO::TextureSystem::TextureHandle* handle = nullptr;
        std::string bytes;  // an embedded image, read through `proxy`, which must outlive the cache's use of it
        std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
    };

    static ProcessTextures& get() {
        static ProcessTextures* const textures = new ProcessTextures;  // never destroyed: threads may outlive exit's destructors
        return *textures;
    }

    /// The image under `name` (embedded `bytes`, else the file), opened once per process: the
    /// same name with other bytes is another image.
    const Image* open(const std::string& name, const std::string* bytes, std::string& error) {
        std::lock_guard<std::mutex> lock(mutex_);
        std::string key = name;
        for (int version = 2; images_.count(key) && bytes && images_.at(key)->bytes != *bytes; ++version) key = name + "#" + std::to_string(version);
        if (auto it = images_.find(key); it != images_.end()) return it->second.get();
        auto image = std::make_unique<Image>();
        // An embedded image's name in the cache ends in its format's extension: OpenImageIO
        // picks the reader by it ("scene.glb#image0" found none, and every embedded image of a
        // .glb rendered magenta).
        image->name = OIIO::ustring(bytes ? key + image_extension_of(*bytes) : key);
        if (bytes) {
            image->bytes = *bytes;
            image->proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(image->bytes.data(), image->bytes.size());
            OIIO::ImageSpec config;
            void* proxy = image->proxy.get();
            config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
            cache_->add_file(image->name, nullptr, &config);
        }
        image->handle = system_->get_texture_handle(image->name);
        if (!image->handle) {
            error = system_->geterror();
            return nullptr;  // not kept: a file that appears later is opened then
        }
        return (images_[key] = std::move(image)).get();
    }

    /// Raises the cache's limit to at least `bytes` (it never falls: a render in flight keeps its share).
    void reserve(size_t bytes) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (bytes <= limit_) return;
        limit_ = bytes;
        cache_->attribute("max_memory_MB", static_cast<float>(static_cast<double>(bytes) / (1 << 20)));
    }

    /// Drops the cache's tiles and open handle of file `name`, and that it found it broken.
    void forget(const std::string& name) {
        std::lock_guard<std::mutex> lock(mutex_);
        cache_->invalidate(OIIO::ustring(name), true);
    }

    OIIO::ImageCache& cache() const { return *cache_; }
    OIIO::TextureSystem& system() const { return *system_; }

private:
    ProcessTextures() {
        cache_ = OIIO::ImageCache::create(false);
        // Files without MIP levels (PNG, JPEG) get them made in memory; without tiles, an image
        // is one tile (autotile would re-decode a PNG from its top for every band of rows).
        cache_->attribute("automip", 1);
        cache_->attribute("accept_untiled", 1);
        cache_->attribute("accept_unmipped", 1);
        // Texels as the file holds them: PNG and TGA store colour apart from alpha (glTF's base
        // colour too), and an RGBA colour map multiplied by its alpha came out dark (a half-
        // transparent texel at half its colour) or black where the alpha was 0.
        cache_->attribute("unassociatedalpha", 1);
        // A bad texel file must not stop a render: its lookups fail and the caller shows it.
        cache_->attribute("failure_retries", 0);
        system_ = OIIO::TextureSystem::create(false, cache_);
    }

    OIIO::ImageCache* cache_ = nullptr;
    OIIO::TextureSystem* system_ = nullptr;
    std::map<std::string, std::unique_ptr<Image>> images_;
    size_t limit_ = 0;
    std::mutex mutex_;
};

// The process's cache counters that a render's statistics are the growth of.
struct CacheCounters {
    uint64_t queries = 0, bytes_read = 0, cache_misses = 0;
    double file_io_seconds = 0;
};

CacheCounters counters_now() {
    const ProcessTextures& t = ProcessTextures::get();
    CacheCounters c;
    long long v64 = 0;
    int v = 0;
    float f = 0;
    if (t.cache().getattribute("stat:bytes_read", OIIO::TypeDesc::INT64, &v64)) c.bytes_read = static_cast<uint64_t>(v64);
    if (t.cache().getattribute("stat:find_tile_cache_misses", OIIO::TypeInt, &v)) c.cache_misses = static_cast<uint64_t>(v);
    if (t.cache().getattribute("stat:fileio_time", OIIO::TypeFloat, &f)) c.file_io_seconds = f;
    // The texture system counts its own queries (the cache's counter is its tiles').
    if (t.system().getattribute("stat:texture_queries", OIIO::TypeDesc::INT64, &v64)) c.queries = static_cast<uint64_t>(v64);
    return c;
}

// A render's textures: the images it opened in the process's cache, and the limit it asked for.
class OiioTextureBackend final : public TextureBackend {
public:
    explicit OiioTextureBackend(size_t cache_bytes) : limit_(cache_bytes), textures_(ProcessTextures::get()) {
        textures_.reserve(cache_bytes);
        start_ = counters_now();
    }

    void forget(const std::string& name) override { textures_.forget(name); }

    int open(const std::string& name, const std::string* bytes, TextureImageInfo& info, std::string& error) override {
        std::lock_guard<std::mutex> lock(mutex_);
        const ProcessTextures::Image* image = textures_.open(name, bytes, error);
        OIIO::TextureSystem& system = textures_.system();
        OIIO::ImageSpec spec;
        int resolution[2] = {0, 0};
        if (!image || !system.get_texture_info(image->handle, nullptr, 0, OIIO::ustring("resolution"), OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), resolution) ||
            !system.get_imagespec(image->handle, nullptr, 0, spec)) {
            if (error.empty()) error = system.geterror();
            if (error.empty()) error = "cannot read the image";
            return -1;
        }
        info.width = resolution[0], info.height = resolution[1];
        info.channels = spec.nchannels;
        info.alpha_channel = spec.alpha_channel < spec.nchannels ? spec.alpha_channel : -1;
        info.eight_bit = spec.format == OIIO::TypeDesc::UINT8;
        // A 16-bit PNG is sRGB-encoded as an 8-bit one is (it was read as linear: a colour of 0.5
        // rendered as 0.5 where it means 0.214).
        const std::string space = spec.get_string_attribute("oiio:ColorSpace");
        info.srgb = OIIO::Strutil::iequals(space, "sRGB") || OIIO::Strutil::istarts_with(space, "GammaCorrected2.2") ||
                    (space.empty() && info.eight_bit);
        info.bytes_per_channel = static_cast<int>(spec.format.size());
        info.tiled = spec.tile_width > 0 && (spec.tile_width < spec.width || spec.tile_height < spec.height);
        int levels = 0;
        if (system.get_texture_info(image->handle, nullptr, 0, OIIO::ustring("miplevels"), OIIO::TypeInt, &levels)) info.mip_levels = levels;
        const char* format = nullptr;
        if (system.get_texture_info(image->handle, nullptr, 0, OIIO::ustring("fileformat"), OIIO::TypeString, &format) && format)
            info.format = format;
        std::error_code ec;
        info.file_bytes = bytes ? bytes->size() : static_cast<uint64_t>(std::filesystem::file_size(name, ec));
        if (ec) info.file_bytes = 0;
        // A header claiming more than its file could hold is refused before a texel is read:
        // the cache reads an untiled image whole (a 486-byte TIFF claiming 40000 x 40000 took
        // 12 GB and two minutes of a 32x32 render).
        if (info.file_bytes > 0) {
            error = image_formats::claim_beyond_file(static_cast<double>(spec.image_bytes()), info.file_bytes, spec.width, spec.height,
                                                     image_formats::kAnyCodecPacking);
            if (!error.empty()) {
                textures_.forget(image->name.string());
                return -1;
            }
        }
        handles_.push_back(image->handle);
        return static_cast<int>(handles_.size() - 1);
    }

    bool lookup(int id, const TextureLookup& at, BackendWrap wrap_s, BackendWrap wrap_t, int first_channel, int channels, float* out,
                float* d_ds, float* d_dt) override {
        OIIO::TextureOpt opt;
        opt.swrap = wrap_of(wrap_s);
        opt.twrap = wrap_of(wrap_t);
        opt.firstchannel = first_channel;
        float dsdx = at.dsdx, dtdx = at.dtdx, dsdy = at.dsdy, dtdy = at.dtdy;
        if (at.indirect) {
            opt.mipmode = OIIO::TextureOpt::MipModeTrilinear;
            // A round footprint of the same area: the trilinear filter sizes itself by the
            // longer axis, which blurred a grazing footprint far beyond what it covers.
            const float w = std::sqrt(std::fabs(dsdx * dtdy - dtdx * dsdy));
            dsdx = dtdy = w, dtdx = dsdy = 0;
        } else if (dsdx == 0 && dtdx == 0 && dsdy == 0 && dtdy == 0) {
            opt.interpmode = OIIO::TextureOpt::InterpBilinear;  // the default magnifies bicubically
        }
        if (at.nearest) opt.interpmode = OIIO::TextureOpt::InterpClosest;
        // handles_ only grows under the mutex before rendering starts: reading it here is safe.
        OIIO::TextureSystem& system = textures_.system();
        return system.texture(handles_[static_cast<size_t>(id)], system.get_perthread_info(), opt, at.s, at.t, dsdx, dtdx, dsdy, dtdy,
                              channels, out, d_ds, d_dt);
    }

    bool texels(int id, int first_channel, int channels, float* out) override {
        OIIO::TextureSystem& system = textures_.system();
        OIIO::TextureSystem::TextureHandle* handle = handles_[static_cast<size_t>(id)];
        int resolution[2] = {0, 0};
        if (!system.get_texture_info(handle, nullptr, 0, OIIO::ustring("resolution"), OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), resolution))
            return false;
        OIIO::TextureOpt opt;
        return system.get_texels(handle, system.get_perthread_info(), opt, 0, 0, resolution[0], 0, resolution[1], 0, 1, first_channel,
                                 first_channel + channels, OIIO::TypeFloat, out);
    }

    bool make_tiled_copy(const std::string& source, const std::string& target, std::string& error,
                         const std::function<void(double)>& progress) override {
        return write_tiled_copy(source, target, error, progress);
    }

    // The process's cache over this render: its counters' growth since the render opened it
    // (renders one after another, as a walk's frames, each count their own), its memory now.
    TextureCacheStats stats() const override {
        const CacheCounters now = counters_now();
        TextureCacheStats s;
        s.queries = now.queries - std::min(now.queries, start_.queries);
        s.bytes_read = now.bytes_read - std::min(now.bytes_read, start_.bytes_read);
        s.cache_misses = now.cache_misses - std::min(now.cache_misses, start_.cache_misses);
        s.file_io_seconds = std::max(0.0, now.file_io_seconds - start_.file_io_seconds);
        long long v64 = 0;
        int v = 0;
        if (textures_.cache().getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &v64)) s.memory_bytes = static_cast<uint64_t>(v64);
        if (textures_.cache().getattribute("stat:tiles_peak", OIIO::TypeInt, &v)) s.tiles_peak = static_cast<uint64_t>(v);
        s.files = std::set<OIIO::TextureSystem::TextureHandle*>(handles_.begin(), handles_.end()).size();
        s.memory_limit = limit_;
        return s;
    }

private:
    size_t limit_;
    ProcessTextures& textures_;
    CacheCounters start_;
    std::vector<OIIO::TextureSystem::TextureHandle*> handles_;
    std::mutex mutex_;
};

}  // namespace
}  // namespace crex::oiio

// The entry point image_io.cpp resolves with dlsym.
extern "C" crex::TextureBackend* crex_oiio_make_texture_backend(size_t cache_bytes) {
    return new crex::oiio::OiioTextureBackend(cache_bytes);
}
