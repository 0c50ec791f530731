// image_io.h for the rest of crex: OpenEXR and PNG written and read by their own libraries
// (image_formats.h); every other format, and textures, through the OpenImageIO plugin
// (libcrex_oiio.so), loaded the first time one is needed, so that commands that never need it
// start fast.
#include "runtime/io/image_io.h"
#include "runtime/io/image_formats.h"
#include "runtime/io/texture_backend.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "base/input_file.h"
#include "base/install_paths.h"
#include "runtime/base/atomic_file.h"
#include "runtime/base/file_extension.h"

namespace crex {
namespace {

using WriteFn = std::string (*)(const std::string&, int, int, const std::vector<ImageLayer>&, const ImageMetadata&);
using ReadFn = std::string (*)(const std::string&, int&, int&, std::vector<float>&, bool&);
using ReadMetadataFn = std::string (*)(const std::string&, int&, int&, ImageMetadata&);
using ReadLayerFn = std::string (*)(const std::string&, const std::string&, int&, int&, std::vector<float>&);
using MakeTextureBackendFn = TextureBackend* (*)(size_t);

struct Plugin {
    WriteFn write = nullptr;
    ReadFn read = nullptr;
    ReadMetadataFn read_metadata = nullptr;
    ReadLayerFn read_layer = nullptr;
    MakeTextureBackendFn make_texture_backend = nullptr;
    std::string error;
};

// Where the plugin may be: $CREX_OIIO_MODULE, beside the running executable, in the install
// tree the code runs from (base/install_paths.h), then where the build put it.
std::vector<std::string> candidates() {
    std::vector<std::string> out;
    if (const char* env = std::getenv("CREX_OIIO_MODULE")) out.push_back(env);
    std::error_code ec;
    auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) out.push_back((exe.parent_path() / "libcrex_oiio.so").string());
    if (std::string installed = installed_path(CREX_OIIO_INSTALL_PATH); !installed.empty()) out.push_back(installed);
    out.push_back(CREX_OIIO_MODULE_PATH);
    return out;
}

const Plugin& plugin() {
    static Plugin p;
    static std::once_flag once;
    std::call_once(once, [] {
        std::string tried;
        for (const auto& path : candidates()) {
            void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
            if (!h) {
                tried += "\n  " + path + ": " + dlerror();
                continue;
            }
            using AbiFn = int (*)();
            auto abi = reinterpret_cast<AbiFn>(dlsym(h, "crex_oiio_abi_version"));
            if (!abi || abi() != kImagePluginAbi) {
                tried += "\n  " + path + ": an image plugin of another crex build (interface " + (abi ? std::to_string(abi()) : "1") +
                         ", this crex needs " + std::to_string(kImagePluginAbi) + ")";
                dlclose(h);
                continue;
            }
            p.write = reinterpret_cast<WriteFn>(dlsym(h, "crex_oiio_write_image"));
            p.read = reinterpret_cast<ReadFn>(dlsym(h, "crex_oiio_read_image"));
            p.read_metadata = reinterpret_cast<ReadMetadataFn>(dlsym(h, "crex_oiio_read_image_metadata"));
            p.read_layer = reinterpret_cast<ReadLayerFn>(dlsym(h, "crex_oiio_read_image_layer"));
            p.make_texture_backend = reinterpret_cast<MakeTextureBackendFn>(dlsym(h, "crex_oiio_make_texture_backend"));
            if (p.write && p.read && p.read_metadata && p.read_layer && p.make_texture_backend) return;
            tried += "\n  " + path + ": not a crex image plugin";
        }
        p.error = "cannot load the image plugin libcrex_oiio.so (OpenImageIO); tried:" + tried;
    });
    return p;
}

}  // namespace

std::string load_image_plugin() { return plugin().error; }

bool needs_image_plugin(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext != ".exr" && ext != ".png";
}

std::future<void> preload_image_plugin(const std::vector<std::string>& paths) {
    if (std::none_of(paths.begin(), paths.end(), needs_image_plugin)) return {};
    // TBB dlopens its allocator and its thread server at its first parallel loop, and makes its
    // worker threads when a loop first has work for them. Either, under way beside the plugin's
    // load, waits for the loader's lock until the load ends (a new thread's TLS is set up under
    // it): the Cornell box's BVH build, the first to fork, waited 0.39 s so. A loop with a task
    // for every worker first makes them all.
    const int workers = tbb::this_task_arena::max_concurrency();
    tbb::parallel_for(tbb::blocked_range<int>(0, 4 * workers, 1), [](const tbb::blocked_range<int>&) {});
    try {
        return std::async(std::launch::async, [] { (void)plugin(); });
    } catch (const std::system_error&) {  // no thread to be had: the first read or write loads it
        return {};
    }
}

std::string ImageAttribute::text() const {
    struct Text {
        std::string operator()(const std::string& s) const { return s; }
        std::string operator()(int i) const { return std::to_string(i); }
        std::string operator()(float f) const { return fmt::format("{:.9g}", f); }
        std::string operator()(const Matrix44& m) const { return fmt::format("{:.9g}", fmt::join(m.m, " ")); }
        std::string operator()(const Chromaticities& c) const { return fmt::format("{:.9g}", fmt::join(c.xy, " ")); }
    };
    return std::visit(Text{}, value);
}

std::string attribute_text(const ImageMetadata& metadata, const std::string& name) {
    for (const ImageAttribute& a : metadata)
        if (a.name == name) return a.text();
    return {};
}

std::string write_image(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers,
                        const ImageMetadata& metadata) {
    if (needs_image_plugin(path)) {
        const Plugin& p = plugin();
        return p.write ? p.write(path, width, height, layers, metadata) : p.error;
    }
    if (layers.empty()) return "nothing to write";
    if (width <= 0 || height <= 0) return "cannot write '" + path + "': an image of no pixels";
    std::string error;
    const std::string bytes = lower_extension(path) == ".exr" ? image_formats::encode_exr(width, height, layers, metadata, error)
                                                              : image_formats::encode_png(width, height, layers, metadata, error);
    if (!error.empty()) return "cannot write '" + path + "': " + error;
    if (std::string e = write_file_atomically(path, bytes); !e.empty()) return "cannot write '" + path + "': " + e;
    return "";
}

std::string read_image_metadata(const std::string& path, int& width, int& height, ImageMetadata& metadata) {
    // No reader opens what it is given blindly: /dev/zero or a FIFO must not reach one.
    if (std::string error = check_input_file(path, kMaxDataInputBytes); !error.empty()) return error;
    if (auto done = image_formats::read_exr_metadata(path, width, height, metadata)) return *done;
    if (auto done = image_formats::read_png_metadata(path, width, height, metadata)) return *done;
    const Plugin& p = plugin();
    return p.read_metadata ? p.read_metadata(path, width, height, metadata) : p.error;
}

std::string read_image_layer(const std::string& path, const std::string& layer, int& width, int& height, std::vector<float>& rgb) {
    if (std::string error = check_input_file(path, kMaxDataInputBytes); !error.empty()) return error;
    if (auto done = image_formats::read_exr_layer(path, layer, width, height, rgb)) return *done;
    const Plugin& p = plugin();
    return p.read_layer ? p.read_layer(path, layer, width, height, rgb) : p.error;
}

std::string read_image(const std::string& path, int& width, int& height, std::vector<float>& rgb, bool* display_referred) {
    if (std::string error = check_input_file(path, kMaxDataInputBytes); !error.empty()) return error;
    if (auto done = image_formats::read_exr(path, width, height, rgb)) {  // float or half: scene-referred
        if (display_referred) *display_referred = false;
        return *done;
    }
    if (auto done = image_formats::read_png(path, width, height, rgb)) {  // 8 or 16 bits, sRGB: display-referred
        if (display_referred) *display_referred = true;
        return *done;
    }
    const Plugin& p = plugin();
    bool ldr = false;
    std::string error = p.read ? p.read(path, width, height, rgb, ldr) : p.error;
    if (display_referred) *display_referred = ldr;
    return error;
}

std::unique_ptr<TextureBackend> make_texture_backend(size_t cache_bytes, std::string& error) {
    const Plugin& p = plugin();
    if (!p.make_texture_backend) {
        error = p.error;
        return nullptr;
    }
    return std::unique_ptr<TextureBackend>(p.make_texture_backend(cache_bytes));
}

}  // namespace crex
