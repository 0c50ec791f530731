/// \file reference_cache.h
/// Converged references, cached by what determines them: the scene (its full JSON form, not
/// its path), image size, samples, seed, crex and limits. `crex reference` fills the cache;
/// `crex run --reference auto` looks there.
#pragma once

#include <cstdint>
#include <string>

#include "runtime/scene/scene.h"

namespace crex {

struct ReferenceSettings {
    int width = 128, height = 128;
    uint32_t spp = 1024;
    uint64_t seed = 0;
    std::string crex = "(TTMRSGD)*";
    double lw = 1e-3;
    uint32_t max_depth = 256;
};

/// 16 hex digits: FNV-1a 64 of the scene's full JSON form with its texture files named by their
/// content (scene_identity_text: what it holds, not where it came from, so a clone elsewhere
/// gives the same). A reference records it, so that one made of a scene that has changed since
/// is found.
std::string scene_content_hash(const Scene& scene);

/// 16 hex digits (FNV-1a 64 of the scene's identity text and the settings but spp, which is in the
/// file name: KEY_sppN.exr).
std::string reference_key(const Scene& scene, const ReferenceSettings& s);
/// references/ in crex_cache_folder() (runtime/base/cache_folder.h).
std::string reference_cache_dir();
std::string reference_path(const Scene& scene, const ReferenceSettings& s);
/// Whether `path` already holds the reference of `scene` with settings `s`, so that it need not
/// be rendered again: an image of s's size, and, where `keyed` (a path the user named, which
/// might hold anything: -o /etc/hostname was taken once), the key file beside it
/// (PATH.key) naming the same scene content and settings. The cache's own names are keys.
bool holds_reference(const std::string& path, const Scene& scene, const ReferenceSettings& s, bool keyed);
/// The cached reference with these settings and the most samples (s.spp ignored); "" if none.
std::string find_cached_reference(const Scene& scene, const ReferenceSettings& s);

}  // namespace crex
