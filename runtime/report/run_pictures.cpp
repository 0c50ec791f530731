#include "runtime/report/run_pictures.h"

#include <algorithm>
#include <bit>
#include <filesystem>

#include "runtime/io/heat_map.h"
#include "runtime/io/image_io.h"

namespace crex {

std::string write_run_pictures(const std::string& dir, const Film& film, const std::vector<float>* preview,
                               const std::vector<std::pair<std::string, guidance::Raster>>& maps, PictureSummary& summary) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return "cannot create '" + dir + "': " + ec.message();
    const int w = film.width(), h = film.height();
    const size_t n = film.pixel_count();
    auto put = [&](const std::string& name, ImageLayer layer, const ImageMetadata& metadata = {}) -> std::string {
        std::string path = (std::filesystem::path(dir) / name).string();
        std::string error = write_image(path, w, h, {std::move(layer)}, metadata);
        if (error.empty()) summary.written.push_back(path);
        return error;
    };
    if (preview)
        if (auto e = put("preview.png", {"", *preview}); !e.empty()) return e;
    // A map is one value a pixel: a grey picture that says which map it is.
    for (const auto& [name, map] : maps) {
        std::vector<float> values(n, 0.0f);
        std::copy_n(map.v.begin(), std::min(n, map.v.size()), values.begin());
        std::string safe = name;
        std::replace_if(safe.begin(), safe.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)) && c != '_'; }, '_');
        if (auto e = put("map_" + safe + ".png", {safe, std::move(values), true, 1}, {{"crex:map", name}}); !e.empty()) return e;
    }
    std::vector<double> samples(n), rays(n), components(n);
    double sum = 0;
    for (uint32_t p = 0; p < n; ++p) {
        samples[p] = film.samples(p);
        rays[p] = film.rays(p);
        components[p] = std::popcount(static_cast<unsigned>(film.components(p)));
        sum += rays[p];
        summary.max_rays_per_pixel = std::max(summary.max_rays_per_pixel, rays[p]);
    }
    summary.mean_rays_per_pixel = n ? sum / static_cast<double>(n) : 0;
    auto raw = [&](const std::vector<double>& v) {  // the counts themselves, one channel named for them
        return std::vector<float>(v.begin(), v.end());
    };
    auto max_of = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
    for (auto [name, values] : {std::pair{"samples_per_pixel", &samples}, std::pair{"rays_per_pixel", &rays},
                                std::pair{"components_per_pixel", &components}}) {
        double mx = std::string(name) == "components_per_pixel" ? double(kAovCount) : max_of(*values);
        if (auto e = put(std::string(name) + ".png", {"", heat_colours(*values, mx), true}); !e.empty()) return e;
        const char* unit = std::string(name) == "samples_per_pixel" ? "samples" : std::string(name) == "rays_per_pixel" ? "rays" : "components";
        summary.heat_scale[summary.written.back()] = {mx, unit};
        if (auto e = put(std::string(name) + ".exr", {unit, raw(*values), false, 1}, {{"crex:map", std::string(name)}}); !e.empty()) return e;
    }
    return "";
}

}  // namespace crex
