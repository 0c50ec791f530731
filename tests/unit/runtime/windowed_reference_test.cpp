// Windowed references (issue 32): the window text, the atlas, the header, accumulation, the
// rule that chooses windows, and the committed references under bench/refs/ against their
// scenes.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "compiler/crex/compile.h"
#include "runtime/pipeline/pixel_probe.h"
#include "runtime/reference/reference_render.h"
#include "runtime/reference/reference_windows.h"
#include "runtime/reference/windowed_image.h"
#include "runtime/report/reference_cache.h"
#include "runtime/scene/load_scene.h"

namespace crex {
namespace {

TEST(WindowedImage, WindowsAreReadStrictly) {
    EXPECT_EQ(parse_window("3,4,16,8"), (PixelWindow{3, 4, 16, 8}));
    for (const char* bad : {"", "3,4,16", "3,4,16,8,", "3,4,16,0", "-1,4,16,8", "3, 4,16,8", "3,4,16,8x", "a,4,16,8"})
        EXPECT_FALSE(parse_window(bad)) << bad;
    EXPECT_EQ(format_windows({{1, 2, 3, 4}, {5, 6, 7, 8}}), "1,2,3,4;5,6,7,8");
    EXPECT_EQ(parse_windows("1,2,3,4;5,6,7,8"), (std::vector<PixelWindow>{{1, 2, 3, 4}, {5, 6, 7, 8}}));
    EXPECT_FALSE(parse_windows(""));
    EXPECT_EQ(check_windows({{0, 0, 8, 8}, {8, 0, 8, 8}}, 16, 8), "");
    EXPECT_NE(check_windows({{0, 0, 8, 8}, {7, 0, 8, 8}}, 16, 8).find("overlaps window 1"), std::string::npos);
    EXPECT_NE(check_windows({{10, 0, 8, 8}}, 16, 8).find("does not lie inside the 16x8 frame"), std::string::npos);
    EXPECT_NE(check_windows({}, 16, 8), "");
}

// Windows side by side, top-aligned: packing a frame and taking window i back gives the crop.
TEST(WindowedImage, TheAtlasHoldsEachWindowAsItsCrop) {
    const int w = 9, h = 7;
    std::vector<float> frame(3 * w * h);
    for (size_t i = 0; i < frame.size(); ++i) frame[i] = static_cast<float>(i);
    const WindowAtlas atlas({{1, 1, 3, 2}, {5, 2, 4, 5}});
    EXPECT_EQ(atlas.width, 7);
    EXPECT_EQ(atlas.height, 5);
    EXPECT_EQ(atlas.column, (std::vector<int>{0, 3}));
    const std::vector<float> packed = atlas.pack(frame, w);
    ASSERT_EQ(packed.size(), 3u * 7 * 5);
    for (size_t i = 0; i < 2; ++i) EXPECT_EQ(atlas.window(packed, i), crop(frame, w, atlas.windows[i]));
    EXPECT_EQ(packed[3 * (2 * 7 + 0)], 0.0f);  // under the 2-row window
    EXPECT_EQ(packed[3 * (0 * 7 + 3)], frame[3 * (2 * w + 5)]);  // window 2's first pixel
}

TEST(WindowedImage, TheHeaderReadsBackAndMalformedOnesAreNamed) {
    ReferenceHeader h;
    h.frame_width = 960, h.frame_height = 540, h.windows = {{0, 0, 64, 64}, {100, 50, 64, 64}}, h.spp = 8192, h.seed = 7;
    h.scene = "builtin:cornell", h.scene_hash = "0123456789abcdef", h.crex = "(TTMRSGD)*", h.commands = "a\nb", h.runs = "4096+4096";
    h.render_seconds = 12.5, h.exposure = 0.731, h.context = "16 spp";
    std::string error;
    auto back = reference_header(reference_metadata(h), error);
    ASSERT_TRUE(back) << error;
    EXPECT_EQ(back->windows, h.windows);
    EXPECT_EQ(back->frame_width, 960);
    EXPECT_EQ(back->spp, 8192u);
    EXPECT_EQ(back->seed, 7u);
    EXPECT_EQ(back->scene_hash, h.scene_hash);
    EXPECT_EQ(back->commands, "a\nb");
    EXPECT_DOUBLE_EQ(back->exposure, 0.731);
    EXPECT_FALSE(back->whole_frame());
    EXPECT_FALSE(reference_header({{"crex:spp", "4"}}, error));  // not a reference crex wrote: no error
    EXPECT_EQ(error, "");
    ImageMetadata bad = reference_metadata(h);
    for (auto& [k, v] : bad)
        if (k == "crex:windows") v = "0,0,64,64;900,500,64,64";  // outside the frame
    EXPECT_FALSE(reference_header(bad, error));
    EXPECT_NE(error.find("crex:windows"), std::string::npos) << error;
}

TEST(WindowedImage, AccumulationIsTheMeanOfAllSamples) {
    const std::vector<float> a = {1, 2, 0}, b = {3, 2, 4};
    EXPECT_EQ(accumulate_samples(a, 1, b, 3), (std::vector<float>{2.5f, 2.0f, 3.0f}));
    EXPECT_EQ(accumulate_samples(a, 2, b, 2), (std::vector<float>{2.0f, 2.0f, 2.0f}));
}

// The rule on the furnished room: every kind it has is there, inside the frame, none
// overlapping; the task window holds the laptop and the distractor window the poster.
TEST(ReferenceWindows, TheRuleCoversEveryKindTheRoomHas) {
    SceneSources sources;
    DiagnosticSink sink;
    SceneLoadFailure failure;
    auto scene = load_scene(std::string(CREX_SOURCE_DIR) + "/examples/scenes/room/scene.json", sources, sink, failure);
    ASSERT_TRUE(scene);
    DiagnosticSink crex_sink;
    SourceFile crex("<test>", "(TTMRSGD)*");
    auto program = compile_crex(crex, crex_sink).program;
    ASSERT_TRUE(program);
    const int w = 96, h = 54, size = 12;
    const FrameContext context = render_frame_context(*scene, *program, w, h, 1, 1);
    const std::vector<ChosenWindow> chosen = choose_reference_windows(*scene, context, size, 1);
    std::map<std::string, PixelWindow> by_kind;
    for (const ChosenWindow& c : chosen) {
        EXPECT_GT(c.window.width, 0) << c.kind << ": " << c.why;
        by_kind[c.kind] = c.window;
    }
    for (const char* kind : {"task", "distractor", "lamp", "caustic", "salient", "plain"}) EXPECT_TRUE(by_kind.count(kind)) << kind;
    std::vector<PixelWindow> all;
    for (const ChosenWindow& c : chosen) {
        all.push_back(c.window);
        EXPECT_EQ(c.window.width, size);
        EXPECT_EQ(c.window.height, size);
    }
    EXPECT_EQ(check_windows(all, w, h), "");
    // The laptop and the poster are seen inside their windows.
    RenderScene rs(*scene);
    const PixelProbe probe = probe_pixels(rs, w, h);
    auto pixels_of = [&](const PixelWindow& win, auto&& tagged) {
        size_t n = 0;
        for (int y = win.y; y < win.y + win.height; ++y)
            for (int x = win.x; x < win.x + win.width; ++x)
                if (const int32_t s = probe.shape[static_cast<size_t>(y * w + x)]; s >= 0 && scene->shapes[static_cast<size_t>(s)].tag)
                    n += tagged(*scene->shapes[static_cast<size_t>(s)].tag);
        return n;
    };
    EXPECT_GT(pixels_of(by_kind["task"], [](const Tag& t) { return t.task > 0; }), 10u);
    EXPECT_GT(pixels_of(by_kind["distractor"], [](const Tag& t) { return t.distractor; }), 10u);
}

// A reference's scene as this build finds it: built in, in the repository, or written by the
// build (the living room's glTF, made by make_scene.py into build/<type>/examples/scenes/...):
// `build/<any type>/X` is X in this build's own folder, so an ASan build checks it as well.
std::string committed_scene_spec(const std::string& scene) {
    namespace fs = std::filesystem;
    if (scene.rfind("builtin:", 0) == 0) return scene;
    const fs::path path(scene);
    auto part = path.begin();
    if (part != path.end() && *part == "build" && ++part != path.end() && ++part != path.end()) {
        fs::path rest;
        for (; part != path.end(); ++part) rest /= *part;
        return (fs::path(CREX_BINARY_DIR) / rest).string();
    }
    return (fs::path(CREX_SOURCE_DIR) / path).string();
}

// Every reference committed under bench/refs/ (windows of the frame-size tables) and
// bench/peer/refs/ (the peer comparison's, docs/peer.md) was rendered from its scene as it is
// now: the hash of the scene's content it records still matches (a changed scene makes it stale).
TEST(CommittedReferences, EachStillMatchesItsScenesHash) {
    namespace fs = std::filesystem;
    size_t checked = 0;
    for (const char* folder : {"bench/refs", "bench/peer/refs"})
    for (const auto& entry : fs::directory_iterator(fs::path(CREX_SOURCE_DIR) / folder)) {
        if (entry.path().extension() != ".exr") continue;
        int w = 0, h = 0;
        ImageMetadata metadata;
        ASSERT_EQ(read_image_metadata(entry.path().string(), w, h, metadata), "");
        std::string error;
        auto header = reference_header(metadata, error);
        ASSERT_TRUE(header) << entry.path() << ": " << error;
        const std::string spec = committed_scene_spec(header->scene);
        SceneSources sources;
        DiagnosticSink sink;
        SceneLoadFailure failure;
        auto scene = load_scene(spec, sources, sink, failure);
        ASSERT_TRUE(scene) << entry.path() << ": cannot load " << spec << " " << failure.message;
        EXPECT_EQ(scene_content_hash(*scene), header->scene_hash)
            << entry.path() << " was rendered from another version of " << header->scene << ": render it again (bench/refs/README.md)";
        // Committed from 2048 spp on and grown by --accumulate (bench/refs/README.md): every
        // session starts from a fresh clone, so a reference kept outside the repo was lost.
        EXPECT_GE(header->spp, 2048u) << entry.path();
        ++checked;
    }
    // None committed yet: say so rather than pass silently.
    if (checked == 0) GTEST_SKIP() << "no reference committed under bench/refs or bench/peer/refs yet";
}

}  // namespace
}  // namespace crex
