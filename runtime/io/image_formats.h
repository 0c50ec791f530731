/// \file image_formats.h
/// The image formats crex writes and reads most, without OpenImageIO: OpenEXR through its own
/// library (image_io_exr.cpp) and PNG through libpng (image_io_png.cpp). Loading the OpenImageIO plugin
/// relocates about 260 shared libraries (0.35-0.47 s of CPU in every process that touched an
/// image, a fifth of the test suite's time); OpenEXR and libpng load in 5 ms. image_io.cpp sends
/// these formats here and everything else (other formats, textures) to the plugin.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runtime/io/image_io.h"

namespace crex::image_formats {

/// The bytes of an OpenEXR file: 32-bit float, ZIP compression, channels as write_image()
/// names them, every attribute typed. "" in `error` on success.
std::string encode_exr(int width, int height, const std::vector<ImageLayer>& layers, const ImageMetadata& metadata,
                       std::string& error);

/// The bytes of an 8-bit PNG of the first layer (tone-mapped unless display-referred; one
/// channel as grey), string attributes as tEXt chunks. "" in `error` on success.
std::string encode_png(int width, int height, const std::vector<ImageLayer>& layers, const ImageMetadata& metadata,
                       std::string& error);

/// The most pixels a reader here takes (8K UHD fits); a larger header is an error before
/// anything is allocated.
constexpr int64_t kMaxReadPixels = int64_t{1} << 25;

/// How many bytes of pixels one byte of a file may decode to at most: zlib's deflate (EXR's
/// and PNG's codecs but DWA) packs about 1032; no codec OpenImageIO reads packs more than a few
/// thousand (LZW under 1400, a flat JPEG block about 400).
constexpr double kDeflatePacking = 1100, kAnyCodecPacking = 4096;

/// Why a header claiming `width` x `height` pixels, `pixel_bytes` decoded, cannot be in a file
/// of `file_bytes` that packs at most `packing` bytes into one; "" where it could. Such a header
/// is refused before its pixels are allocated: OpenImageIO, OpenEXR and libpng allocate what a
/// header claims (a 486-byte TIFF claiming 40000 x 40000 took 23.7 GB before it was killed).
inline std::string claim_beyond_file(double pixel_bytes, uint64_t file_bytes, int64_t width, int64_t height, double packing) {
    if (pixel_bytes <= packing * static_cast<double>(file_bytes)) return "";
    return "the file (" + std::to_string(file_bytes) + " bytes) is too small for the " + std::to_string(width) + " x " +
           std::to_string(height) + " pixels its header claims (truncated?)";
}

/// What a header claiming more than kMaxReadPixels is told.
inline std::string beyond_read_limit(int64_t width, int64_t height) {
    return "an image of " + std::to_string(width) + " x " + std::to_string(height) + " pixels is beyond what crex reads (" +
           std::to_string(kMaxReadPixels) + " pixels)";
}

/// Readers of PNG files: nullopt where the file is not one (its signature), else "" or why it
/// could not be read. Every colour type and depth: values to linear by the sRGB curve (or by a
/// lone gAMA chunk's power), grey to all three channels, alpha composited over black; the
/// metadata is the text chunks before the pixels, as strings.
std::optional<std::string> read_png(const std::string& path, int& width, int& height, std::vector<float>& rgb);
std::optional<std::string> read_png_metadata(const std::string& path, int& width, int& height, ImageMetadata& metadata);

/// Readers of OpenEXR files. Each returns std::nullopt where the file is one it leaves to
/// OpenImageIO (an OpenEXR file laid out otherwise than crex and most renderers write: no
/// R, G, B and not one channel; channels not float or half; a data window other than the
/// display window), else "" or why it could not read the file.
std::optional<std::string> read_exr(const std::string& path, int& width, int& height, std::vector<float>& rgb);
std::optional<std::string> read_exr_layer(const std::string& path, const std::string& layer, int& width, int& height,
                                          std::vector<float>& rgb);
std::optional<std::string> read_exr_metadata(const std::string& path, int& width, int& height, ImageMetadata& metadata);

}  // namespace crex::image_formats
