#include "runtime/reference/windowed_image.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

namespace crex {

std::optional<PixelWindow> parse_window(const std::string& text) {
    int v[4];
    const char* p = text.data();
    const char* end = text.data() + text.size();
    for (int i = 0; i < 4; ++i) {
        auto [next, ec] = std::from_chars(p, end, v[i]);
        if (ec != std::errc() || next == p) return std::nullopt;
        p = next;
        if (i < 3) {
            if (p == end || *p != ',') return std::nullopt;
            ++p;
        }
    }
    if (p != end || v[0] < 0 || v[1] < 0 || v[2] < 1 || v[3] < 1) return std::nullopt;
    return PixelWindow{v[0], v[1], v[2], v[3]};
}

std::string format_windows(const std::vector<PixelWindow>& windows) {
    std::string out;
    for (const PixelWindow& w : windows) out += fmt::format("{}{},{},{},{}", out.empty() ? "" : ";", w.x, w.y, w.width, w.height);
    return out;
}

std::optional<std::vector<PixelWindow>> parse_windows(const std::string& text) {
    std::vector<PixelWindow> out;
    std::stringstream list(text);
    for (std::string item; std::getline(list, item, ';');) {
        auto w = parse_window(item);
        if (!w) return std::nullopt;
        out.push_back(*w);
    }
    if (out.empty()) return std::nullopt;
    return out;
}

std::string check_windows(const std::vector<PixelWindow>& windows, int width, int height) {
    if (windows.empty()) return "no window";
    auto name = [](const PixelWindow& w) { return fmt::format("{},{},{},{}", w.x, w.y, w.width, w.height); };
    for (size_t i = 0; i < windows.size(); ++i) {
        const PixelWindow& w = windows[i];
        if (w.x < 0 || w.y < 0 || w.width < 1 || w.height < 1 || w.x + w.width > width || w.y + w.height > height)
            return fmt::format("window {} ({}) does not lie inside the {}x{} frame", i + 1, name(w), width, height);
        for (size_t j = 0; j < i; ++j) {
            const PixelWindow& o = windows[j];
            if (w.x < o.x + o.width && o.x < w.x + w.width && w.y < o.y + o.height && o.y < w.y + w.height)
                return fmt::format("window {} ({}) overlaps window {} ({}): a pixel would count twice", i + 1, name(w), j + 1, name(o));
        }
    }
    return "";
}

WindowAtlas::WindowAtlas(std::vector<PixelWindow> ws) : windows(std::move(ws)) {
    for (const PixelWindow& w : windows) {
        column.push_back(width);
        width += w.width;
        height = std::max(height, w.height);
    }
}

std::vector<float> WindowAtlas::pack(const std::vector<float>& frame, int frame_width, int channels) const {
    const size_t nc = static_cast<size_t>(channels);
    std::vector<float> atlas(static_cast<size_t>(width) * static_cast<size_t>(height) * nc, 0.0f);
    for (size_t i = 0; i < windows.size(); ++i) {
        const PixelWindow& w = windows[i];
        for (int y = 0; y < w.height; ++y) {
            const size_t from = (static_cast<size_t>(w.y + y) * static_cast<size_t>(frame_width) + static_cast<size_t>(w.x)) * nc;
            const size_t to = (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(column[i])) * nc;
            std::copy_n(frame.begin() + static_cast<std::ptrdiff_t>(from), static_cast<size_t>(w.width) * nc,
                        atlas.begin() + static_cast<std::ptrdiff_t>(to));
        }
    }
    return atlas;
}

std::vector<float> WindowAtlas::window(const std::vector<float>& atlas, size_t i, int channels) const {
    const PixelWindow& w = windows[i];
    return crop(atlas, width, {column[i], 0, w.width, w.height}, channels);
}

std::vector<float> crop(const std::vector<float>& image, int width, const PixelWindow& w, int channels) {
    const size_t nc = static_cast<size_t>(channels), row = static_cast<size_t>(w.width) * nc;
    std::vector<float> out(row * static_cast<size_t>(w.height));
    for (int y = 0; y < w.height; ++y) {
        const size_t from = (static_cast<size_t>(w.y + y) * static_cast<size_t>(width) + static_cast<size_t>(w.x)) * nc;
        std::copy_n(image.begin() + static_cast<std::ptrdiff_t>(from), row, out.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(y)));
    }
    return out;
}

bool ReferenceHeader::whole_frame() const {
    return windows.size() == 1 && windows[0] == PixelWindow{0, 0, frame_width, frame_height};
}

ImageMetadata reference_metadata(const ReferenceHeader& h) {
    ImageMetadata m = {{"crex:reference", "true"},
                       {"crex:frame", fmt::format("{}x{}", h.frame_width, h.frame_height)},
                       {"crex:windows", format_windows(h.windows)},
                       {"crex:spp", std::to_string(h.spp)},
                       {"crex:seed", std::to_string(h.seed)},
                       {"crex:scene", h.scene},
                       {"crex:scene_hash", h.scene_hash},
                       {"crex:crex", h.crex},
                       {"crex:commands", h.commands},
                       {"crex:runs", h.runs},
                       {"crex:render_seconds", fmt::format("{:.6g}", h.render_seconds)}};
    if (h.exposure > 0) m.push_back({"crex:exposure", fmt::format("{:.9g}", h.exposure)});
    if (!h.context.empty()) m.push_back({"crex:context", h.context});
    if (h.own_rmse > 0) m.push_back({"crex:own_rmse", fmt::format("{:.6g}", h.own_rmse)});
    return m;
}

std::optional<ReferenceHeader> reference_header(const ImageMetadata& metadata, std::string& error) {
    std::map<std::string, std::string> m;
    for (const ImageAttribute& a : metadata) m[a.name] = a.text();
    error.clear();
    if (!m.count("crex:windows")) return std::nullopt;
    ReferenceHeader h;
    auto bad = [&](const std::string& key) {
        error = fmt::format("its header's {} is malformed ('{}')", key, m[key]);
        return std::nullopt;
    };
    auto windows = parse_windows(m["crex:windows"]);
    if (!windows) return bad("crex:windows");
    h.windows = *windows;
    if (std::sscanf(m["crex:frame"].c_str(), "%dx%d", &h.frame_width, &h.frame_height) != 2 || h.frame_width < 1 || h.frame_height < 1)
        return bad("crex:frame");
    if (!check_windows(h.windows, h.frame_width, h.frame_height).empty()) return bad("crex:windows");
    auto whole = [](const std::string& text, auto& value) {
        auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        return ec == std::errc() && end == text.data() + text.size();
    };
    if (!whole(m["crex:spp"], h.spp) || h.spp == 0) return bad("crex:spp");
    if (!whole(m["crex:seed"], h.seed)) return bad("crex:seed");
    h.scene = m["crex:scene"], h.scene_hash = m["crex:scene_hash"], h.crex = m["crex:crex"];
    h.commands = m["crex:commands"], h.runs = m["crex:runs"], h.context = m["crex:context"];
    h.render_seconds = std::atof(m["crex:render_seconds"].c_str());
    if (m.count("crex:own_rmse")) {
        h.own_rmse = std::atof(m["crex:own_rmse"].c_str());
        if (!(h.own_rmse >= 0) || !std::isfinite(h.own_rmse)) return bad("crex:own_rmse");
    }
    if (m.count("crex:exposure")) {
        h.exposure = std::atof(m["crex:exposure"].c_str());
        if (!(h.exposure > 0) || !std::isfinite(h.exposure)) return bad("crex:exposure");
    }
    return h;
}

std::string write_reference_image(const std::string& path, const ReferenceImage& image, const ImageMetadata& software) {
    std::vector<ImageLayer> layers = {{"", image.rgb}};
    if (!image.attention.empty()) {
        std::vector<float> rgb(3 * image.attention.size());
        for (size_t i = 0; i < image.attention.size(); ++i) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = image.attention[i];
        layers.push_back({kAttentionLayer, rgb});
    }
    ImageMetadata m = software;
    for (auto& kv : reference_metadata(image.header)) m.push_back(kv);
    return write_image(path, image.width, image.height, layers, m);
}

std::string read_reference_image(const std::string& path, std::optional<ReferenceImage>& image) {
    image.reset();
    ImageMetadata metadata;
    int w = 0, h = 0;
    if (std::string e = read_image_metadata(path, w, h, metadata); !e.empty()) return e;
    std::string error;
    auto header = reference_header(metadata, error);
    if (!error.empty()) return fmt::format("{}: {}", path, error);
    if (!header) return "";
    ReferenceImage r;
    r.header = *header;
    if (std::string e = read_image(path, r.width, r.height, r.rgb); !e.empty()) return e;
    const WindowAtlas atlas(header->windows);
    if (r.width != atlas.width || r.height != atlas.height)
        return fmt::format("{} is {}x{}, but its header's windows ({}) make an image of {}x{}", path, r.width, r.height,
                           format_windows(header->windows), atlas.width, atlas.height);
    std::vector<float> attention;
    int aw = 0, ah = 0;
    if (read_image_layer(path, kAttentionLayer, aw, ah, attention).empty() && aw == r.width && ah == r.height) {
        r.attention.resize(attention.size() / 3);
        for (size_t i = 0; i < r.attention.size(); ++i) r.attention[i] = attention[3 * i];
    }
    image = std::move(r);
    return "";
}

std::vector<float> accumulate_samples(const std::vector<float>& a, uint32_t a_samples, const std::vector<float>& b, uint32_t b_samples) {
    std::vector<float> out(a.size());
    const double na = a_samples, nb = b_samples, n = na + nb;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
        const float v = static_cast<float>((na * a[i] + nb * b[i]) / n);
        out[i] = std::isfinite(v) ? v : 0.0f;
    }
    return out;
}

double own_rmse_estimate(const std::vector<float>& a, uint32_t a_samples, const std::vector<float>& b, uint32_t b_samples) {
    const size_t n = std::min(a.size(), b.size());
    if (n == 0 || a_samples == 0 || b_samples == 0) return 0;
    double sum = 0;
    for (size_t i = 0; i < n; ++i) {
        const double d = static_cast<double>(a[i]) - b[i];
        if (std::isfinite(d)) sum += d * d;
    }
    const double na = a_samples, nb = b_samples;
    return std::sqrt(sum / static_cast<double>(n)) * std::sqrt(na * nb) / (na + nb);
}

}  // namespace crex
