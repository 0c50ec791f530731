// The image plugin loaded on a thread of its own (preload_image_plugin): an image written or
// read while the load is under way waits for it and succeeds, and once the preload is done the
// plugin is there; the thread pool's workers are made before it starts. Each test runs in a
// process of its own (gtest_discover_tests), so the plugin is not loaded yet when each starts.
#include <gtest/gtest.h>

#include <filesystem>
#include <future>
#include <thread>
#include <vector>

#include <tbb/task_arena.h>

#include "runtime/io/image_io.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

class ImagePluginPreload : public testing::ScratchFolderTest {
protected:
    ImagePluginPreload() : ScratchFolderTest("crex_image_plugin_preload_") {}
};

TEST_F(ImagePluginPreload, LeavesThePluginLoaded) {
    std::future<void> preload = preload_image_plugin();
    ASSERT_TRUE(preload.valid());
    preload.get();
    EXPECT_EQ(load_image_plugin(), "");
}

// TBB's workers are made before the load starts: a thread made during it waits for the
// loader's lock until the load ends, and the render's setup (the first to fork) waited 0.39 s.
TEST_F(ImagePluginPreload, MakesTheThreadPoolsWorkersFirst) {
    auto threads = [] {
        size_t n = 0;
        for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) ++n;
        return n;
    };
    if (threads() != 1) GTEST_SKIP() << "needs a process of its own, as ctest gives each test";
    std::future<void> preload = preload_image_plugin();
    ASSERT_TRUE(preload.valid());
    // While the load is under way (it takes a third of a second; the libraries' own threads
    // start at its end): the main thread, a worker for every other slot of the arena, and the
    // loader's thread.
    EXPECT_GE(threads(), static_cast<size_t>(tbb::this_task_arena::max_concurrency()) + 1);
    preload.get();
}

TEST_F(ImagePluginPreload, WritesAndReadsDuringTheLoadWaitForIt) {
    const std::future<void> preload = preload_image_plugin();
    // Several threads meet the load under way; each must get a working plugin.
    std::vector<std::future<std::string>> writes;
    for (int t = 0; t < 4; ++t)
        writes.push_back(std::async(std::launch::async, [this, t] {
            const std::string file = path("frame" + std::to_string(t) + ".exr");
            if (std::string error = write_image(file, 2, 1, {{"", {1, 2, 3, 4, 5, float(t)}}}); !error.empty()) return error;
            int w = 0, h = 0;
            std::vector<float> rgb;
            if (std::string error = read_image(file, w, h, rgb); !error.empty()) return error;
            return w == 2 && h == 1 && rgb.size() == 6 && rgb[5] == float(t) ? std::string() : std::string("read back other pixels");
        }));
    for (auto& w : writes) EXPECT_EQ(w.get(), "");
}

}  // namespace
}  // namespace crex
