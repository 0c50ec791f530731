// The OpenImageIO side of image_io.h, built as a plugin module (libcrex_oiio.so) that
// image_io.cpp loads on first use: linking OIIO into the tool made every `crex` start take
// 0.4 s relocating 265 shared libraries, most of them codecs an image write never touches.
#include "runtime/io/image_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "runtime/base/atomic_file.h"

namespace crex {
namespace {

std::string lower_ext(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

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
    std::string ext = lower_ext(path);
    bool exr = ext == ".exr", hdr = ext == ".hdr";
    auto writer = [&](const std::string& tmp) -> std::string {
        auto out = OIIO::ImageOutput::create(path);  // format from the real name, not the temp
        if (!out) return "no image writer for '" + path + "': " + OIIO::geterror();
        const size_t np = static_cast<size_t>(width) * static_cast<size_t>(height);
        // HDR holds RGB only: a one-channel layer goes there as grey.
        const size_t nlayers = exr ? layers.size() : 1;
        std::vector<std::string> names;
        std::vector<size_t> first;  // each layer's first channel in a pixel
        for (size_t l = 0; l < nlayers; ++l) {
            first.push_back(names.size());
            if (layers[l].channels == 1 && !hdr) names.push_back(layers[l].name.empty() ? "Y" : layers[l].name);
            else
                for (const char* c : {"R", "G", "B"}) names.push_back(layers[l].name.empty() ? c : layers[l].name + "." + c);
        }
        const size_t nc = names.size();
        OIIO::ImageSpec spec(width, height, static_cast<int>(nc), exr || hdr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        spec.channelnames = names;
        if (exr) spec.attribute("compression", "zip");
        // zlib level 3, not libpng's 6: a noisy 320x240 frame takes 7.6 ms instead of 22 and
        // is 7 % larger (75.6 KB against 70.4), which matters for a sequence's PNG every frame
        // (Blender's default PNG compression is as light, 15 %).
        if (ext == ".png") spec.attribute("png:compressionLevel", 3);
        for (const auto& [key, value] : metadata) set_attribute(spec, key, value);
        if (!out->open(tmp, spec)) return "cannot write '" + path + "': " + out->geterror();
        auto value = [&](size_t l, size_t p, size_t c) {  // channel c of pixel p of layer l, finite
            const ImageLayer& layer = layers[l];
            const float v = layer.channels == 1 ? layer.rgb[p] : layer.rgb[3 * p + c];
            return std::isfinite(v) ? v : 0.0f;
        };
        bool ok;
        if (exr || hdr) {
            std::vector<float> pixels(np * nc);
            for (size_t l = 0; l < nlayers; ++l) {
                const size_t width_of = l + 1 < nlayers ? first[l + 1] - first[l] : nc - first[l];
                for (size_t p = 0; p < np; ++p)
                    for (size_t c = 0; c < width_of; ++c) pixels[p * nc + first[l] + c] = value(l, p, c);
            }
            ok = out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
        } else {
            const ImageLayer& layer = layers.front();
            std::vector<unsigned char> bytes;
            if (layer.display_referred) {
                bytes.resize(np * nc);
                for (size_t p = 0; p < np; ++p)
                    for (size_t c = 0; c < nc; ++c)
                        bytes[p * nc + c] = static_cast<unsigned char>(std::lround(255 * std::clamp(value(0, p, c), 0.0f, 1.0f)));
            } else if (layer.channels == 1) {  // grey through the same tone map as colour
                std::vector<float> rgb(3 * np);
                for (size_t p = 0; p < np; ++p) rgb[3 * p] = rgb[3 * p + 1] = rgb[3 * p + 2] = value(0, p, 0);
                const std::vector<unsigned char> srgb = crex::tone_map_srgb8(rgb);
                bytes.resize(np);
                for (size_t p = 0; p < np; ++p) bytes[p] = srgb[3 * p];
            } else {
                bytes = crex::tone_map_srgb8(layer.rgb);
            }
            ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        }
        if (!ok) return "cannot write '" + path + "': " + out->geterror();
        if (!out->close()) return "cannot close '" + path + "': " + out->geterror();
        // Some writers (PNG's) do not report a short write: a full disk replaced a good old
        // file with a truncated one and said "wrote". Flushed, then read back whole, before
        // the rename puts it in place.
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

std::string read_image(const std::string& path, int& width, int& height, std::vector<float>& rgb, bool& display_referred) {
    OIIO::ImageBuf buf(path);
    if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return "cannot read '" + path + "': " + buf.geterror();
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
            if (linearise) v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
            rgb[3 * p + static_cast<size_t>(c)] = v;
        }
    return "";
}

std::string read_image_layer(const std::string& path, const std::string& layer, int& width, int& height, std::vector<float>& rgb) {
    OIIO::ImageBuf buf(path);
    if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return "cannot read '" + path + "': " + buf.geterror();
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
    if (!in) return "cannot read '" + path + "': " + OIIO::geterror();
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
