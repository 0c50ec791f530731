// The image plugin loaded on a thread of its own (preload_image_plugin): an image written or
// read while the load is under way waits for it and succeeds, and once the preload is done the
// plugin is there. Each test runs in a process of its own (gtest_discover_tests), so the
// plugin is not loaded yet when each starts.
#include <gtest/gtest.h>

#include <future>
#include <thread>
#include <vector>

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
