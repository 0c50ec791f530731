/// \file tiled_copies.h
/// Where a texture file without tiles that is larger than the texture cache is read from: a
/// tiled, MIP-mapped copy the first render makes (TextureBackend::make_tiled_copy) in crex's
/// cache folder, so that it is read tile by tile within the cache's limit. OpenImageIO reads
/// an image without tiles whole whatever its cache's limit (6.9 GB for a 2.6 MB PNG of 30000 x
/// 30000 texels), and an 8K PNG is larger than the cache's share of the default --max-memory.
#pragma once

#include <cstdint>
#include <string>

#include "runtime/io/texture_backend.h"

namespace crex {

/// textures/NAME-KEY.tx in crex_cache_folder(): KEY hashes the file's absolute path, size and
/// modification time, so a file that is changed gets a copy of its own. "" when the file's
/// size or time cannot be read.
std::string tiled_copy_path(const std::string& file);

/// The same for an image embedded in a scene file (a .glb's), named `name`: KEY hashes its bytes.
std::string embedded_tiled_copy_path(const std::string& name, const std::string& bytes);

/// Removes what a process making `copy` left behind when it was killed (its temporary files,
/// named with its process id: the coarser levels of a large image are gigabytes), where no
/// process of that id runs any more.
void remove_stale_temporaries(const std::string& copy);

/// Writes an embedded image's `bytes` beside `copy` as a file of its own for the copy to be made
/// from (named with this process's id and their format's extension); its path, or ""
/// with `error`.
std::string write_embedded_source(const std::string& copy, const std::string& bytes, std::string& error);

/// What making the copy of an image holds in memory: a band of 64 rows as floats, and the
/// writer's band as stored (runtime/io/tiled_copy_oiio.cpp). A PNG may say it is a million
/// texels wide.
inline uint64_t tiled_copy_memory(const TextureImageInfo& info) {
    return 64 * uint64_t(info.width) * uint64_t(info.channels) * (4 + uint64_t(info.bytes_per_channel));
}

}  // namespace crex
