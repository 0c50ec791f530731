// The OpenImageIO side of image_io.h (formats other than OpenEXR and PNG, and textures), built
// as a plugin module (libcrex_oiio.so) that image_io.cpp loads on first use: linking OIIO into
// the tool made every `crex` start take 0.4 s relocating 265 shared libraries, most of them
// codecs an image write never touches.
#include "runtime/io/image_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>

#include "runtime/base/atomic_file.h"
#include "runtime/base/file_extension.h"
#include "runtime/io/image_formats.h"

namespace crex {
namespace {

// An attribute with the type OpenEXR gives it (OIIO maps int, float, matrix44 and float[8]
// "chromaticities" to EXR's int, float, M44f and chromaticities).
void set_attribute(OIIO::ImageSpec& spec, const std::string& name, const AttributeValue& value) {
    if (const auto* s = std::get_if<std::string>(&value)) spec.attribute(name, *s);
    else if (const auto* i = std::get_if<int>(&value)) spec.attribute(name, *i);
    else if (const auto* f = std::get_if<float>(&value)) spec.attribute(name, *f);
    else if (const auto* m = std::get_if<Matrix44>(&value)) spec.attribute(name, OIIO::TypeMatrix44, m->m.data());
    else if (const auto* c = std::get_if<Chromaticities>(&value)) spec.attribute(name, OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), c->xy.data());
}

// The typed value of a header attribute; other types as their text.
AttributeValue attribute_value(const OIIO::ParamValue& p) {
    const OIIO::TypeDesc t = p.type();
    if (t == OIIO::TypeDesc::STRING) return p.get_string();
    if (t == OIIO::TypeInt) return p.get_int();
    if (t == OIIO::TypeFloat) return p.get_float();
    if (t == OIIO::TypeMatrix44) {
        Matrix44 m;
        std::copy_n(static_cast<const float*>(p.data()), 16, m.m.begin());
        return m;
    }
    if (t == OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8)) {
        Chromaticities c;
        std::copy_n(static_cast<const float*>(p.data()), 8, c.xy.begin());
        return c;
    }
    return p.get_string();
}

}  // namespace

}  // namespace crex

namespace crex::oiio {

std::string write_image(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers,
                        const ImageMetadata& metadata) {
    using crex::write_atomically_via;
    // The formats image_io.cpp leaves to the plugin (not EXR, not PNG) hold one layer: HDR as
    // float RGB (a one-channel layer as grey), the others as 8-bit display values.
    const bool hdr = lower_extension(path) == ".hdr";
    auto writer = [&](const std::string& tmp) -> std::string {
        auto out = OIIO::ImageOutput::create(path);  // format from the real name, not the temp
        if (!out) return "no image writer for '" + path + "': " + OIIO::geterror();
        const ImageLayer& layer = layers.front();
        const size_t np = static_cast<size_t>(width) * static_cast<size_t>(height);
        const int nc = hdr || layer.channels != 1 ? 3 : 1;
        OIIO::ImageSpec spec(width, height, nc, hdr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        for (const auto& [key, value] : metadata) set_attribute(spec, key, value);
        if (!out->open(tmp, spec)) return "cannot write '" + path + "': " + out->geterror();
        bool ok;
        if (hdr) {
            std::vector<float> pixels(3 * np);
            for (size_t p = 0; p < np; ++p)
                for (size_t c = 0; c < 3; ++c) {
                    const float v = layer.channels == 1 ? layer.rgb[p] : layer.rgb[3 * p + c];
                    pixels[3 * p + c] = std::isfinite(v) ? v : 0.0f;
                }
            ok = out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
        } else {
            const std::vector<unsigned char> bytes = crex::eight_bit_pixels(layer, np);
            ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        }
        if (!ok) return "cannot write '" + path + "': " + out->geterror();
        if (!out->close()) return "cannot close '" + path + "': " + out->geterror();
        // Some writers do not report a short write: a full disk replaced a good old file with
        // a truncated one and said "wrote". Flushed, then read back whole, before the rename
        // puts it in place.
        int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
        bool synced = fd >= 0 && ::fsync(fd) == 0;
        if (fd >= 0) ::close(fd);
        if (!synced) return "cannot write '" + path + "': the data did not reach the disk";
        OIIO::ImageBuf check(tmp);
        if (!check.read(0, 0, true, OIIO::TypeDesc::FLOAT) || check.spec().width != width || check.spec().height != height)
            return "cannot write '" + path + "': what reached the disk does not read back (disk full?)";
        return "";
    };
    if (layers.empty()) return "nothing to write";
    return write_atomically_via(path, writer);
}

namespace {

// Why a file cannot be read, from OpenImageIO's error (which some readers leave empty).
std::string cannot_read(const std::string& path, const std::string& error) {
    return "cannot read '" + path + "': " + (error.empty() ? "OpenImageIO could not decode it (damaged or truncated?)" : error);
}

// Why `path`'s pixels must not be read, else "". OpenImageIO allocates what a header claims
// before it reads a pixel (`crex compare` of a 486-byte TIFF whose header claimed 40000 x 40000
// took 23.7 GB and was killed after 133 s), so a header is held first to the readers' limit
// (image_formats::kMaxReadPixels) and to what its file could hold (claim_beyond_file()).
std::string unreadable(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return cannot_read(path, OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    const int64_t pixels = static_cast<int64_t>(spec.width) * spec.height * std::max(spec.depth, 1);
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        return cannot_read(path, "its header claims an image of " + std::to_string(spec.width) + " x " + std::to_string(spec.height) + " pixels");
    if (pixels > image_formats::kMaxReadPixels) return cannot_read(path, image_formats::beyond_read_limit(spec.width, spec.height));
    std::error_code ec;
    const uintmax_t file_bytes = std::filesystem::file_size(path, ec);
    const std::string why = ec ? "" : image_formats::claim_beyond_file(static_cast<double>(spec.image_bytes()), file_bytes, spec.width,
                                                                        spec.height, image_formats::kAnyCodecPacking);
    return why.empty() ? "" : cannot_read(path, why);
}

}  // namespace

std::string read_image(const std::string& path, int& width, int& height, std::vector<float>& rgb, bool& display_referred) {
    if (std::string why = unreadable(path); !why.empty()) return why;
    OIIO::ImageBuf buf(path);
    if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return cannot_read(path, buf.geterror());
    const OIIO::ImageSpec& spec = buf.spec();
    width = spec.width;
    height = spec.height;
    int nc = spec.nchannels;
    std::vector<float> all(static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(nc));
    buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, all.data());
    // The file's own type: the buffer was read as float, so spec() says FLOAT for any file.
    const OIIO::TypeDesc stored = buf.nativespec().format;
    bool linearise = stored == OIIO::TypeDesc::UINT8 || stored == OIIO::TypeDesc::UINT16;
    display_referred = linearise;
    rgb.assign(static_cast<size_t>(width) * static_cast<size_t>(height) * 3, 0.0f);
    for (size_t p = 0; p < static_cast<size_t>(width) * static_cast<size_t>(height); ++p)
        for (int c = 0; c < 3; ++c) {
            float v = all[p * static_cast<size_t>(nc) + static_cast<size_t>(std::min(c, nc - 1))];
            if (linearise) v = static_cast<float>(srgb_decode(v));
            rgb[3 * p + static_cast<size_t>(c)] = v;
        }
    return "";
}

std::string read_image_layer(const std::string& path, const std::string& layer, int& width, int& height, std::vector<float>& rgb) {
    if (std::string why = unreadable(path); !why.empty()) return why;
    OIIO::ImageBuf buf(path);
    if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return cannot_read(path, buf.geterror());
    const OIIO::ImageSpec& spec = buf.spec();
    int at[3];
    for (int c = 0; c < 3; ++c) {
        at[c] = spec.channelindex(layer + "." + "RGB"[c]);
        if (at[c] < 0) return "'" + path + "' has no layer '" + layer + "' (channels " + layer + ".R, .G, .B)";
    }
    width = spec.width, height = spec.height;
    const size_t np = static_cast<size_t>(width) * static_cast<size_t>(height), nc = static_cast<size_t>(spec.nchannels);
    std::vector<float> all(np * nc);
    buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, all.data());
    rgb.assign(3 * np, 0.0f);
    for (size_t p = 0; p < np; ++p)
        for (size_t c = 0; c < 3; ++c) rgb[3 * p + c] = all[p * nc + static_cast<size_t>(at[c])];
    return "";
}

std::string read_image_metadata(const std::string& path, int& width, int& height, ImageMetadata& metadata) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return cannot_read(path, OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    width = spec.width, height = spec.height;
    metadata.clear();
    for (const OIIO::ParamValue& p : spec.extra_attribs) metadata.push_back({p.name().string(), attribute_value(p)});
    return "";
}

}  // namespace crex::oiio

// The entry points image_io.cpp resolves with dlsym.
extern "C" {
int crex_oiio_abi_version() { return crex::kImagePluginAbi; }
std::string crex_oiio_write_image(const std::string& path, int width, int height, const std::vector<crex::ImageLayer>& layers,
                                  const crex::ImageMetadata& metadata) {
    return crex::oiio::write_image(path, width, height, layers, metadata);
}
std::string crex_oiio_read_image(const std::string& path, int& width, int& height, std::vector<float>& rgb,
                                 bool& display_referred) {
    return crex::oiio::read_image(path, width, height, rgb, display_referred);
}
std::string crex_oiio_read_image_layer(const std::string& path, const std::string& layer, int& width, int& height,
                                       std::vector<float>& rgb) {
    return crex::oiio::read_image_layer(path, layer, width, height, rgb);
}
std::string crex_oiio_read_image_metadata(const std::string& path, int& width, int& height, crex::ImageMetadata& metadata) {
    return crex::oiio::read_image_metadata(path, width, height, metadata);
}
}
