// Random mutations of real scene files: every loader either returns a scene without errors or
// reports errors whose spans lie inside the text; never a crash, never a NaN in a scene.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "runtime/scene/shapes.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

std::string read(const std::string& path) {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string mutate(std::string text, std::mt19937_64& rng) {
    std::uniform_int_distribution<int> op(0, 4);
    int edits = std::uniform_int_distribution<int>(1, 4)(rng);
    static const std::string pieces[] = {"nan", "inf", "-1", "1e999", "\"", "[", "]", "{", "}", ",", "0", "\x80",
                                         "\n", "!", "#", "void", "polygon", "-0", "1e-320", "\"type\"", ":"};
    for (int e = 0; e < edits && !text.empty(); ++e) {
        size_t at = std::uniform_int_distribution<size_t>(0, text.size() - 1)(rng);
        switch (op(rng)) {
        case 0: text.erase(at, std::uniform_int_distribution<size_t>(1, 8)(rng)); break;
        case 1: text.insert(at, pieces[std::uniform_int_distribution<size_t>(0, std::size(pieces) - 1)(rng)]); break;
        case 2: text[at] = static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng)); break;
        case 3: text.resize(at); break;  // truncation
        default: std::swap(text[at], text[std::uniform_int_distribution<size_t>(0, text.size() - 1)(rng)]); break;
        }
    }
    return text;
}

void expect_sane(const testing::SceneResult& r, const std::string& text) {
    for (const auto& d : r.diagnostics) {
        ASSERT_FALSE(d.code.empty());
        if (d.span.valid() && d.span.file->text() == text) {
            EXPECT_LE(d.span.begin, d.span.end);
            EXPECT_LE(d.span.end, text.size());
        }
    }
    if (!r.scene) {
        EXPECT_GT(r.errors, 0u);
        return;
    }
    EXPECT_EQ(r.errors, 0u);
    for (const auto& s : r.scene->shapes) {
        Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
        expand_bounds(s, lo, hi);
        EXPECT_TRUE(is_finite(lo) && is_finite(hi));
    }
    EXPECT_TRUE(is_finite(r.scene->camera.position));
}

TEST(SceneRandomInput, MutatedJsonNeverCrashes) {
    std::string base = read(CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json");
    ASSERT_FALSE(base.empty());
    std::mt19937_64 rng(11);
    for (int i = 0; i < 1500; ++i) {
        std::string text = mutate(base, rng);
        testing::SceneResult r;
        ASSERT_NO_THROW(r = testing::load_json_text(text)) << text;
        expect_sane(r, text);
    }
}

TEST(SceneRandomInput, MutatedRadianceNeverCrashes) {
    std::string base = read(CREX_SOURCE_DIR "/examples/scenes/cornell/scene.rad");
    std::string view = read(CREX_SOURCE_DIR "/examples/scenes/cornell/scene.vf");
    ASSERT_FALSE(base.empty());
    std::mt19937_64 rng(12);
    for (int i = 0; i < 1500; ++i) {
        std::string text = mutate(base, rng);
        std::string v = i % 3 == 0 ? mutate(view, rng) : view;
        testing::SceneResult r;
        ASSERT_NO_THROW(r = testing::load_rad_text(text, v)) << text;
        expect_sane(r, text);
    }
}

}  // namespace
}  // namespace crex
