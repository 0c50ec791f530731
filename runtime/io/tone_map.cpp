// The tone map for eyes (spec/pipeline.md §7), shared by the loader and the OIIO plugin.
#include <algorithm>
#include <cmath>

#include "runtime/io/image_io.h"

namespace crex {
namespace {

double srgb_encode(double x) {
    x = std::fmin(std::fmax(x, 0.0), 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
}

}  // namespace

double srgb_decode(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

double display_exposure(const std::vector<float>& rgb) {
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
    return 0.18 / std::fmax(log_avg, 1e-12);
}

void to_display(const float* rgb, float* out, size_t count, double exposure) {
    for (size_t i = 0; i < count; ++i) {
        double v = std::isfinite(rgb[i]) ? std::fmax(rgb[i] * exposure, 0.0) : 0.0;
        v = v / (1 + v);  // Reinhard: keeps highlights from clipping hard
        out[i] = static_cast<float>(srgb_encode(v));
    }
}

std::vector<float> to_display(const std::vector<float>& rgb, double exposure) {
    std::vector<float> out(rgb.size());
    to_display(rgb.data(), out.data(), rgb.size(), exposure);
    return out;
}

std::vector<float> as_displayed(const std::vector<float>& rgb, bool ldr, double& exposure) {
    if (!ldr) {
        if (!(exposure > 0)) exposure = display_exposure(rgb);
        return to_display(rgb, exposure);
    }
    std::vector<float> out(rgb.size());  // back through the sRGB curve read_image undid
    for (size_t i = 0; i < rgb.size(); ++i) out[i] = static_cast<float>(srgb_encode(rgb[i]));
    return out;
}

std::vector<unsigned char> tone_map_srgb8(const std::vector<float>& rgb) {
    std::vector<float> d = to_display(rgb, display_exposure(rgb));
    std::vector<unsigned char> out(d.size());
    for (size_t i = 0; i < d.size(); ++i) out[i] = static_cast<unsigned char>(std::lround(255 * d[i]));
    return out;
}

std::vector<unsigned char> eight_bit_pixels(const ImageLayer& layer, size_t pixels) {
    const size_t nc = layer.channels == 1 ? 1 : 3;
    auto value = [&](size_t p, size_t c) {  // finite
        const float v = layer.rgb[nc * p + c];
        return std::isfinite(v) ? v : 0.0f;
    };
    std::vector<unsigned char> bytes;
    if (layer.display_referred) {
        bytes.resize(pixels * nc);
        for (size_t p = 0; p < pixels; ++p)
            for (size_t c = 0; c < nc; ++c) bytes[p * nc + c] = static_cast<unsigned char>(std::lround(255 * std::clamp(value(p, c), 0.0f, 1.0f)));
    } else if (nc == 1) {
        std::vector<float> rgb(3 * pixels);
        for (size_t p = 0; p < pixels; ++p) rgb[3 * p] = rgb[3 * p + 1] = rgb[3 * p + 2] = value(p, 0);
        const std::vector<unsigned char> srgb = tone_map_srgb8(rgb);
        bytes.resize(pixels);
        for (size_t p = 0; p < pixels; ++p) bytes[p] = srgb[3 * p];
    } else {
        bytes = tone_map_srgb8(layer.rgb);
    }
    return bytes;
}

}  // namespace crex
