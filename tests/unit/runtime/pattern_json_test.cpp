// RADIANCE's patterns, BRTDfunc and mixtures in crex's JSON (issue 39): a scene read from
// RADIANCE and written as JSON reads back with the same patterns (what MPI ranks and resumed
// runs receive), and a malformed table is refused with what is wrong, not read into an int.
#include <gtest/gtest.h>

#include "runtime/scene/load_scene.h"
#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

TEST(PatternJson, APatternedSceneReadsBackTheSame) {
    auto r = testing::load_rad_text(
        "void brightfunc dist 4 1-src_theta/90 source.cal -rz 90\n0\n1 2\ndist light lamp 0 0 3 10 10 10\n"
        "lamp polygon bulb 0 0 12 -.1 -.1 2 -.1 .1 2 .1 .1 2 .1 -.1 2\n"
        "void BRTDfunc pane 10 if(Rdot-.5,.2,.8) .2 .2 .3 .3 if(RdotP-.5,.3,0) 0 0 0 .\n0\n9 .1 .1 .1 .2 .2 .2 0 0 0\n"
        "void glow red 0 0 4 .8 .1 .1 0\nvoid plastic grey 0 0 5 .5 .5 .5 0 0\n"
        "void mixfunc striped 4 grey red if(Px,1,0) .\n0\n0\n"
        "void plasfunc shiny 2 grey .\n0\n7 .5 .5 .5 .1 0 0 1\nshiny sphere dome 0 0 4 3 0 1 .5\n"
        "striped sphere ball 0 0 4 0 0 1 .5\npane polygon window 0 0 12 -1 -1 0 1 -1 0 1 1 0 -1 1 0\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    auto back = testing::load_json_text(scene_to_json(*r.scene).dump());
    ASSERT_TRUE(back.scene) << (back.diagnostics.empty() ? "" : back.diagnostics[0].message);
    for (const Material& m : r.scene->materials) {
        const Material* n = back.scene->find_material(m.name);
        ASSERT_TRUE(n) << m.name;
        EXPECT_EQ(n->patterns, m.patterns) << m.name;
        EXPECT_EQ(n->surface_functions, m.surface_functions) << m.name;
        EXPECT_EQ(n->mixture, m.mixture) << m.name;
        EXPECT_EQ(n->directional, m.directional) << m.name;
    }
    EXPECT_EQ(r.scene->find_material("lamp")->patterns.size(), 1u);
    EXPECT_TRUE(r.scene->find_material("pane")->surface_functions.has_value());
    EXPECT_TRUE(r.scene->find_material("striped")->mixture.has_value());
    EXPECT_TRUE(r.scene->find_material("shiny")->directional.has_value());
}

TEST(PatternJson, ATablesCountMustBeAWholeNumberInRange) {
    for (const char* count : {"1e300", "2.5", "1", "-3"}) {
        const std::string text = std::string(R"({"materials": [{"name": "lamp", "type": "light", "color": [1, 1, 1], "patterns": [
            {"kind": "brightdata", "functions": ["noop"], "coordinates": ["Dz"],
             "tables": [{"axes": [{"origin": 0, "size": 1, "count": )") + count + R"(}], "values": [1, 2]}]}]}],
            "shapes": [{"type": "sphere", "material": "lamp", "center": [0, 0, 0], "radius": 1}]})";
        auto r = testing::load_json_text(text);
        EXPECT_FALSE(r.scene) << count;
        testing::expect_diagnostic(r, count, "E303", 1, 0, "whole 'count' from 2 to 2^24");
    }
}

}  // namespace
}  // namespace crex
