/// \file image_signature.h
/// The file extension of the image format some bytes begin with, for an image that has no
/// file name of its own (one carried in a .glb): OpenImageIO picks its reader by extension.
#pragma once

#include <string>
#include <string_view>
#include <utility>

namespace crex {

/// ".png", ".jpg", ... for the signature `bytes` begin with; "" when none is known.
inline std::string image_extension_of(std::string_view bytes) {
    using namespace std::string_view_literals;
    static constexpr std::pair<std::string_view, const char*> kSignatures[] = {
        {"\x89PNG"sv, ".png"}, {"\xff\xd8\xff"sv, ".jpg"}, {"RIFF"sv, ".webp"}, {"DDS "sv, ".dds"}, {"\x76\x2f\x31\x01"sv, ".exr"},
        {"#?RADIANCE"sv, ".hdr"}, {"#?RGBE"sv, ".hdr"}, {"II*\0"sv, ".tif"}, {"MM\0*"sv, ".tif"}, {"BM"sv, ".bmp"}, {"GIF8"sv, ".gif"}};
    for (const auto& [signature, extension] : kSignatures)
        if (bytes.substr(0, signature.size()) == signature) return extension;
    return "";
}

}  // namespace crex
