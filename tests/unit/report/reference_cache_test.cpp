// The reference cache (runtime/report/reference_cache.h): which file `--reference auto` takes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "runtime/report/reference_cache.h"
#include "runtime/scene/load_scene.h"

namespace crex {
namespace {

// The cache finds KEY_sppN.exr with the most samples, and never the KEY_sppN.partial.exr an
// interrupted `crex reference` leaves beside it (it holds fewer than N samples).
TEST(ReferenceCache, AnInterruptedReferenceIsNotTakenForACachedOne) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("crex_reference_cache_" + std::to_string(::getpid()));
    ::setenv("CREX_CACHE", dir.c_str(), 1);
    ReferenceSettings s;
    s.width = s.height = 4;
    const std::optional<Scene> scene = builtin_scene("cornell");
    ASSERT_TRUE(scene.has_value());
    s.spp = 64;
    const std::string whole = reference_path(*scene, s);
    s.spp = 4096;
    const std::string partial = reference_path(*scene, s);
    fs::create_directories(fs::path(whole).parent_path());
    std::ofstream(whole) << "x";
    std::ofstream(fs::path(partial).replace_extension(".partial.exr")) << "x";
    EXPECT_EQ(find_cached_reference(*scene, s), whole);
    ::unsetenv("CREX_CACHE");
    fs::remove_all(dir);
}

}  // namespace
}  // namespace crex
