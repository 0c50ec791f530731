#include "runtime/io/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

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

double srgb_encode(double x) {
    x = std::fmin(std::fmax(x, 0.0), 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
}

}  // namespace

std::vector<unsigned char> tone_map_srgb8(const std::vector<float>& rgb) {
    size_t n = rgb.size() / 3;
    double log_sum = 0;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        double y = 0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2];
        if (std::isfinite(y) && y > 0) {
            log_sum += std::log(1e-6 + y);
            ++count;
        }
    }
    double log_avg = count ? std::exp(log_sum / static_cast<double>(count)) : 1.0;
    double scale = 0.18 / std::fmax(log_avg, 1e-12);
    std::vector<unsigned char> out(rgb.size());
    for (size_t i = 0; i < rgb.size(); ++i) {
        double v = std::isfinite(rgb[i]) ? rgb[i] * scale : 0.0;
        v = v / (1 + v);  // Reinhard: keeps highlights from clipping hard
        out[i] = static_cast<unsigned char>(std::lround(255 * srgb_encode(v)));
    }
    return out;
}

std::string write_image(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers) {
    std::string ext = lower_ext(path);
    bool exr = ext == ".exr", hdr = ext == ".hdr";
    auto writer = [&](const std::string& tmp) -> std::string {
        auto out = OIIO::ImageOutput::create(path);  // format from the real name, not the temp
        if (!out) return "no image writer for '" + path + "': " + OIIO::geterror();
        std::vector<std::string> names;
        std::vector<float> pixels;
        size_t np = static_cast<size_t>(width) * static_cast<size_t>(height);
        size_t nlayers = exr ? layers.size() : 1;
        for (size_t l = 0; l < nlayers; ++l)
            for (const char* c : {"R", "G", "B"}) names.push_back(layers[l].name.empty() ? c : layers[l].name + "." + c);
        size_t nc = names.size();
        OIIO::ImageSpec spec(width, height, static_cast<int>(nc), exr || hdr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        spec.channelnames = names;
        if (exr) spec.attribute("compression", "zip");
        if (!out->open(tmp, spec)) return "cannot open '" + tmp + "': " + out->geterror();
        bool ok;
        if (exr || hdr) {
            pixels.resize(np * nc);
            for (size_t l = 0; l < nlayers; ++l)
                for (size_t p = 0; p < np; ++p)
                    for (size_t c = 0; c < 3; ++c) {
                        float v = layers[l].rgb[3 * p + c];
                        pixels[p * nc + 3 * l + c] = std::isfinite(v) ? v : 0.0f;
                    }
            ok = out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
        } else {
            std::vector<unsigned char> bytes = tone_map_srgb8(layers.front().rgb);
            ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        }
        if (!ok) return "cannot write '" + path + "': " + out->geterror();
        if (!out->close()) return "cannot close '" + path + "': " + out->geterror();
        return "";
    };
    if (layers.empty()) return "nothing to write";
    return write_atomically_via(path, writer);
}

std::string read_image(const std::string& path, int& width, int& height, std::vector<float>& rgb) {
    OIIO::ImageBuf buf(path);
    if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return "cannot read '" + path + "': " + buf.geterror();
    const OIIO::ImageSpec& spec = buf.spec();
    width = spec.width;
    height = spec.height;
    int nc = spec.nchannels;
    std::vector<float> all(static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(nc));
    buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, all.data());
    bool linearise = spec.format == OIIO::TypeDesc::UINT8 || spec.format == OIIO::TypeDesc::UINT16;
    rgb.assign(static_cast<size_t>(width) * static_cast<size_t>(height) * 3, 0.0f);
    for (size_t p = 0; p < static_cast<size_t>(width) * static_cast<size_t>(height); ++p)
        for (int c = 0; c < 3; ++c) {
            float v = all[p * static_cast<size_t>(nc) + static_cast<size_t>(std::min(c, nc - 1))];
            if (linearise) v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
            rgb[3 * p + static_cast<size_t>(c)] = v;
        }
    return "";
}

}  // namespace crex
