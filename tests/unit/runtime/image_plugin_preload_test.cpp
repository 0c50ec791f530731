// The image plugin loaded on a thread of its own (preload_image_plugin): an image written or
// read while the load is under way waits for it and succeeds, and once the preload is done the
// plugin is there; the thread pool's workers are made before it starts. OpenEXR and PNG never
// load it, written or read. Each test runs in a process of its own (gtest_discover_tests), so
// the plugin is not loaded yet when each starts.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
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
    std::future<void> preload = preload_image_plugin({"a.exr", "b.hdr"});
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
    std::future<void> preload = preload_image_plugin({"a.exr", "b.hdr"});
    ASSERT_TRUE(preload.valid());
    // While the load is under way (it takes a third of a second; the libraries' own threads
    // start at its end): the main thread, a worker for every other slot of the arena, and the
    // loader's thread.
    EXPECT_GE(threads(), static_cast<size_t>(tbb::this_task_arena::max_concurrency()) + 1);
    preload.get();
}

TEST_F(ImagePluginPreload, WritesAndReadsDuringTheLoadWaitForIt) {
    const std::future<void> preload = preload_image_plugin({"a.exr", "b.hdr"});
    // Several threads meet the load under way; each must get a working plugin.
    std::vector<std::future<std::string>> writes;
    for (int t = 0; t < 4; ++t)
        writes.push_back(std::async(std::launch::async, [this, t] {
            const std::string file = path("frame" + std::to_string(t) + ".hdr");  // RGBE holds these values exactly
            if (std::string error = write_image(file, 2, 1, {{"", {1, 2, 3, 4, 5, float(t)}}}); !error.empty()) return error;
            int w = 0, h = 0;
            std::vector<float> rgb;
            if (std::string error = read_image(file, w, h, rgb); !error.empty()) return error;
            return w == 2 && h == 1 && rgb.size() == 6 && rgb[5] == float(t) ? std::string() : std::string("read back other pixels");
        }));
    for (auto& w : writes) EXPECT_EQ(w.get(), "");
}

// Whether this process has mapped the plugin.
bool plugin_loaded() {
    std::ifstream maps("/proc/self/maps");
    std::string line;
    while (std::getline(maps, line))
        if (line.find("libcrex_oiio.so") != std::string::npos) return true;
    return false;
}

TEST_F(ImagePluginPreload, ExrAndPngNeverLoadIt) {
    if (plugin_loaded()) GTEST_SKIP() << "needs a process of its own, as ctest gives each test";
    EXPECT_FALSE(preload_image_plugin({path("a.exr"), path("b.PNG")}).valid());
    ImageMetadata header = {{"crex:seed", 7}};
    ASSERT_EQ(write_image(path("a.exr"), 2, 1, {{"", {1, 2, 3, 4, 5, 6}}, {"D", {0.5f, 0, 0, 0, 0, 0.25f}}}, header), "");
    ASSERT_EQ(write_image(path("b.PNG"), 2, 1, {{"", {1, 2, 3, 4, 5, 6}}}, {{"Software", std::string("crex")}}), "");
    int w = 0, h = 0;
    std::vector<float> rgb;
    bool display = true;
    ASSERT_EQ(read_image(path("a.exr"), w, h, rgb, &display), "");
    EXPECT_EQ(rgb, (std::vector<float>{1, 2, 3, 4, 5, 6}));
    EXPECT_FALSE(display);
    ASSERT_EQ(read_image_layer(path("a.exr"), "D", w, h, rgb), "");
    EXPECT_EQ(rgb, (std::vector<float>{0.5f, 0, 0, 0, 0, 0.25f}));
    ImageMetadata read;
    ASSERT_EQ(read_image_metadata(path("a.exr"), w, h, read), "");
    EXPECT_EQ(attribute_text(read, "crex:seed"), "7");
    EXPECT_FALSE(plugin_loaded());
    // The PNG is a PNG (its signature), and other readers see what the plugin reads.
    std::ifstream png(path("b.PNG"), std::ios::binary);
    char signature[8] = {};
    png.read(signature, 8);
    EXPECT_EQ(std::string(signature + 1, 3), "PNG");
    ASSERT_EQ(read_image(path("b.PNG"), w, h, rgb, &display), "");
    EXPECT_TRUE(display);
    ASSERT_EQ(read_image_metadata(path("b.PNG"), w, h, read), "");
    EXPECT_EQ(attribute_text(read, "Software"), "crex");
    EXPECT_FALSE(plugin_loaded());
    // A file named .png that is not one goes to the plugin, which reads it by its content.
    ASSERT_EQ(write_image(path("c.hdr"), 2, 1, {{"", {1, 2, 3, 4, 5, 6}}}), "");
    std::filesystem::copy_file(path("c.hdr"), path("c.png"));
    ASSERT_EQ(read_image(path("c.png"), w, h, rgb, &display), "");
    EXPECT_EQ(rgb, (std::vector<float>{1, 2, 3, 4, 5, 6}));
    EXPECT_TRUE(plugin_loaded());
}

}  // namespace
}  // namespace crex
