#include "base/image_formats.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>

namespace crex {
namespace {
constexpr std::array<std::string_view, 11> kExtensions = {".exr", ".hdr", ".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".tga", ".ppm", ".pfm"};
}  // namespace

std::string image_extension(std::string_view path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

bool is_image_file_name(std::string_view path) {
    const std::string ext = image_extension(path);
    return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

std::string_view image_formats_text() { return ".exr (float), .hdr, .png, .jpg, .tif, .bmp, .tga, .ppm or .pfm"; }

}  // namespace crex
