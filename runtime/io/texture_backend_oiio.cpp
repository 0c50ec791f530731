// The OpenImageIO side of texture_backend.h, in the image plugin (libcrex_oiio.so): a private
// ImageCache and TextureSystem per backend, so each render has one cache of its own size.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/texture.h>

#include <cmath>
#include <filesystem>
#include <mutex>
#include <vector>

#include "runtime/io/texture_backend.h"

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

class OiioTextureBackend final : public TextureBackend {
public:
    explicit OiioTextureBackend(size_t cache_bytes) : limit_(cache_bytes) {
        cache_ = OIIO::ImageCache::create(false);
        // Files without MIP levels (PNG, JPEG) get them made in memory; without tiles, an image
        // is one tile (autotile would re-decode a PNG from its top for every band of rows).
        cache_->attribute("max_memory_MB", static_cast<float>(static_cast<double>(cache_bytes) / (1 << 20)));
        cache_->attribute("automip", 1);
        cache_->attribute("accept_untiled", 1);
        cache_->attribute("accept_unmipped", 1);
        // A bad texel file must not stop a render: its lookups fail and the caller shows it.
        cache_->attribute("failure_retries", 0);
        system_ = OIIO::TextureSystem::create(false, cache_);
    }
    ~OiioTextureBackend() override {
        OIIO::TextureSystem::destroy(system_);
        OIIO::ImageCache::destroy(cache_, true);
    }

    int open(const std::string& name, const std::string* bytes, TextureImageInfo& info, std::string& error) override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto image = std::make_unique<Image>();
        image->name = OIIO::ustring(name);
        if (bytes) {
            // An encoded image in memory: the cache reads it through an IOProxy, which must
            // outlive the cache's use of it (so it lives as long as this backend).
            image->bytes = *bytes;
            image->proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(image->bytes.data(), image->bytes.size());
            OIIO::ImageSpec config;
            void* proxy = image->proxy.get();
            config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
            cache_->add_file(image->name, nullptr, &config);
        }
        image->handle = system_->get_texture_handle(image->name);
        OIIO::ImageSpec spec;
        int resolution[2] = {0, 0};
        if (!image->handle || !system_->get_texture_info(image->handle, nullptr, 0, OIIO::ustring("resolution"), OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), resolution) ||
            !system_->get_imagespec(image->handle, nullptr, 0, spec)) {
            error = system_->geterror();
            if (error.empty()) error = "cannot read the image";
            return -1;
        }
        info.width = resolution[0], info.height = resolution[1];
        info.channels = spec.nchannels;
        info.eight_bit = spec.format == OIIO::TypeDesc::UINT8;
        info.bytes_per_channel = static_cast<int>(spec.format.size());
        info.tiled = spec.tile_width > 0 && spec.tile_width < spec.width;
        int levels = 0;
        if (system_->get_texture_info(image->handle, nullptr, 0, OIIO::ustring("miplevels"), OIIO::TypeInt, &levels)) info.mip_levels = levels;
        const char* format = nullptr;
        if (system_->get_texture_info(image->handle, nullptr, 0, OIIO::ustring("fileformat"), OIIO::TypeString, &format) && format)
            info.format = format;
        std::error_code ec;
        info.file_bytes = bytes ? bytes->size() : static_cast<uint64_t>(std::filesystem::file_size(name, ec));
        if (ec) info.file_bytes = 0;
        images_.push_back(std::move(image));
        return static_cast<int>(images_.size() - 1);
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
        }
        // images_ only grows under the mutex before rendering starts: reading it here is safe.
        return system_->texture(images_[static_cast<size_t>(id)]->handle, system_->get_perthread_info(), opt, at.s, at.t, dsdx, dtdx, dsdy,
                                dtdy, channels, out, d_ds, d_dt);
    }

    TextureCacheStats stats() const override {
        TextureCacheStats s;
        long long v64 = 0;
        int v = 0;
        float f = 0;
        if (cache_->getattribute("stat:texture_queries", OIIO::TypeDesc::INT64, &v64)) s.queries = static_cast<uint64_t>(v64);
        if (cache_->getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &v64)) s.memory_bytes = static_cast<uint64_t>(v64);
        if (cache_->getattribute("stat:bytes_read", OIIO::TypeDesc::INT64, &v64)) s.bytes_read = static_cast<uint64_t>(v64);
        if (cache_->getattribute("stat:tiles_peak", OIIO::TypeInt, &v)) s.tiles_peak = static_cast<uint64_t>(v);
        if (cache_->getattribute("stat:find_tile_cache_misses", OIIO::TypeInt, &v)) s.cache_misses = static_cast<uint64_t>(v);
        if (cache_->getattribute("stat:unique_files", OIIO::TypeInt, &v)) s.files = static_cast<uint64_t>(v);
        if (cache_->getattribute("stat:fileio_time", OIIO::TypeFloat, &f)) s.file_io_seconds = f;
        // The texture system counts its own queries (the cache's counter is its tiles').
        if (system_->getattribute("stat:texture_queries", OIIO::TypeDesc::INT64, &v64)) s.queries = static_cast<uint64_t>(v64);
        s.memory_limit = limit_;
        return s;
    }

private:
    struct Image {
        OIIO::ustring name;
        OIIO::TextureSystem::TextureHandle* handle = nullptr;
        std::string bytes;
        std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
    };
    size_t limit_;
    OIIO::ImageCache* cache_ = nullptr;
    OIIO::TextureSystem* system_ = nullptr;
    std::vector<std::unique_ptr<Image>> images_;
    std::mutex mutex_;
};

}  // namespace
}  // namespace crex::oiio

// The entry point image_io.cpp resolves with dlsym.
extern "C" crex::TextureBackend* crex_oiio_make_texture_backend(size_t cache_bytes) {
    return new crex::oiio::OiioTextureBackend(cache_bytes);
}
