// The furnished room example: every component can occur, both kinds of lamp are sampled, and
// the task object and the distractor are tagged.
#include <gtest/gtest.h>

#include <algorithm>

#include "base/components.h"
#include "runtime/scene/census.h"
#include "runtime/scene/load_scene.h"

namespace crex {
namespace {

TEST(RoomExample, AllSixComponentsTwoLampsAndTags) {
    SceneSources sources;
    DiagnosticSink sink;
    SceneLoadFailure failure;
    auto scene = load_scene(CREX_SOURCE_DIR "/examples/scenes/room/scene.json", sources, sink, failure);
    ASSERT_TRUE(scene) << failure.message;
    EXPECT_FALSE(sink.has_errors());
    Census c = take_census(*scene);
    for (char letter : std::string("DGSTRM")) EXPECT_TRUE(c.can_occur(*component_from_letter(letter))) << letter;
    EXPECT_EQ(c.sampled_emitters, 2u);  // the ceiling panel and the sphere lamp
    for (const char* tag : {"laptop", "poster"})
        EXPECT_TRUE(std::find(c.tags.begin(), c.tags.end(), tag) != c.tags.end()) << tag;
}

}  // namespace
}  // namespace crex
