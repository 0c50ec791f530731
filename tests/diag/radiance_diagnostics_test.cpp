// Every refusal of the RADIANCE reader (issue 39) is a located error that names what it
// refuses: commands crex does not run, shell syntax, the types it does not render, bad
// arguments of its built-in generators and views, and its own #@crex comments.
#include <gtest/gtest.h>

#include "tests/support/scene_helpers.h"

namespace crex {
namespace {

using RadCase = testing::DiagnosticCase;

class RadianceDiagnostic : public ::testing::TestWithParam<RadCase> {};

TEST_P(RadianceDiagnostic, IsLocatedAndNamesItsCause) {
    const RadCase& c = GetParam();
    auto r = testing::load_rad_text(c.text);
    if (c.code[0] == 'E') {
        EXPECT_FALSE(r.scene) << c.name;
    }
    testing::expect_diagnostic(r, c.name, c.code, c.line, c.col, c.message_part);
}

#define L "void light l 0 0 3 1 1 1\n"

INSTANTIATE_TEST_SUITE_P(
    Refusals, RadianceDiagnostic,
    ::testing::Values(
        // Commands and shell syntax.
        RadCase{"other_program", L "!pkgBSDF -s blinds.xml | xform -rz 90\n", "E307", 2, 2, "the command 'pkgBSDF' is not supported"},
        RadCase{"after_a_pipe", L "!genbox l b 1 1 1 | sort\n", "E307", 2, 21, "the command 'sort' after a '|'"},
        RadCase{"semicolon", L "!genbox l b 1 1 1; rm x\n", "E307", 2, 18, "';' in a '!' command needs a shell"},
        RadCase{"dollar", L "!xform -t $X 0 0 a.rad\n", "E307", 2, 11, "a '$' expansion"},
        RadCase{"backquote", L "!xform `cat list`\n", "E307", 2, 8, "'`'"},
        RadCase{"unquoted_parenthesis", L "!genrev l r sin(t) 1 4\n", "E307", 2, 16, "unquoted '('"},
        RadCase{"empty_command", L "!\n", "E301", 2, 1, "an empty '!' command"},
        RadCase{"xform_stdin", L "!xform -t 1 0 0\n", "E301", 2, 2, "standard input"},
        RadCase{"xform_after_pipe_with_files", L "!genbox l b 1 1 1 | xform -t 1 0 0 other.rad\n", "E307", 2, 36, "naming files too"},
        RadCase{"xform_option_after_transform", L "!xform -t 1 0 0 -n late a.rad\n", "E303", 2, 17, "'-n' is not an option here"},
        RadCase{"xform_bad_number", L "!xform -rz ninety a.rad\n", "E302", 2, 12, "expected a number, got 'ninety'"},
        RadCase{"xform_bad_array", L "!xform -a 0 -t 1 0 0 a.rad\n", "E303", 2, 11, "count of copies"},
        RadCase{"xform_arrays_of_arrays", L "!xform -a 1000 -t 1 0 0 -a 1000 -t 0 1 0 -a 3 -t 0 0 1 a.rad\n", "E303", 2, 8,
                "its -a arrays make 3e+06 copies, more than 1000000"},
        RadCase{"xform_arg_file", L "!xform -f args.txt\n", "E307", 2, 8, "xform -f"},
        // Generators.
        RadCase{"genbox_size", L "!genbox l b 1 0 1\n", "E303", 2, 15, "sizes must be > 0"},
        RadCase{"genbox_option", L "!genbox l b 1 1 1 -x\n", "E303", 2, 19, "unknown option '-x'"},
        RadCase{"genbox_polygon_rounding", L "!genbox l b 1 1 1 -r .1 -n 8\n", "E307", 2, 25, "genbox -n"},
        RadCase{"genprism_count", L "!genprism l p 4 0 0 1 0 1 1\n", "E301", 2, 2, "4 vertices need 8 coordinates"},
        RadCase{"genprism_flat", L "!genprism l p 3 0 0 1 0 0 1 -l 1 0 0\n", "E303", 2, 36, "must leave the z = 0 plane"},
        RadCase{"genprism_rounding", L "!genprism l p 3 0 0 1 0 0 1 -r .1\n", "E307", 2, 29, "genprism -r"},
        RadCase{"genrev_syntax", L "!genrev l r 't*' 1 4\n", "E302", 2, 13, "z(t)"},
        RadCase{"genrev_segments", L "!genrev l r t 1 0\n", "E303", 2, 17, "number of segments"},
        RadCase{"genrev_negative_radius", L "!genrev l r t '-1' 4\n", "E303", 2, 15, "must not be negative"},
        RadCase{"gensky_month", L "!gensky 13 1 12\n", "E303", 2, 9, "month must be 1 .. 12"},
        RadCase{"gensky_time", L "!gensky 6 21 noon\n", "E302", 2, 14, "cannot read the time 'noon'"},
        RadCase{"gensky_zone", L "!gensky 6 21 12XYZ\n", "E302", 2, 14, "time zone"},
        RadCase{"gensky_option", L "!gensky 6 21 12 -q\n", "E303", 2, 17, "unknown option '-q'"},
        // Types crex does not render, where they are defined, when a surface needs them.
        RadCase{"texture", L "void texfunc wavy 4 dx dy dz . 0 0\nwavy plastic p 0 0 5 .5 .5 .5 0 0\np sphere s 0 0 4 0 0 0 1\n", "E307", 3, 1,
                "modified by a texfunc 'wavy'"},
        RadCase{"pattern_as_material", L "void colorfunc c 4 r g b . 0 0\nc sphere s 0 0 4 0 0 0 1\n", "E307", 2, 6,
                "a colorfunc (a pattern), not a material"},
        RadCase{"mist_not_a_box", L "void mist fog 0 0 3 .1 .1 .1\nfog sphere s 0 0 4 0 0 0 1\n", "E307", 3, 5,
                "mist 'fog': crex's medium fills the whole scene or one axis-aligned box"},
        RadCase{"mist_arguments", L "void mist fog 0 0 4 .1 .1 .1 .5\n!genbox fog b 1 1 1\n", "E303", 2, 6,
                "mist 'fog' takes 0, 3, 6 or 7 real arguments"},
        RadCase{"mist_albedo", L "void mist fog 0 0 6 .1 .1 .1 2 2 2\n!genbox fog b 1 1 1\n", "E302", 2, 6, "albedo in [0, 1]"},
        RadCase{"mist_two", L "void mist fog 0 0 3 .1 .1 .1\n!genbox fog b 1 1 1\nvoid mist haze 0 0 3 .2 .2 .2\n!genbox haze c 1 1 1\n", "E307", 4,
                6, "crex renders one medium"},
        RadCase{"bsdf_data", L "void BSDF b 6 0 file.xml 0 0 1 . 0 0\nb polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n", "E307", 2, 6, "'BSDF'"},
        RadCase{"brtdfunc_directional", L "void BRTDfunc f 10 0 0 0 0 0 0 br 0 0 . 0 9 0 0 0 0 0 0 0 0 0\nf sphere s 0 0 4 0 0 0 1\n", "E307",
                2, 32, "directional-diffuse function 'br' is not supported"},
        RadCase{"prism_unknown_function", L "void prism1 p 5 wob(Dx) 1 0 0 . 0 1 1.5\np ring r 0 0 8 0 0 0 0 0 1 0 1\n", "E307", 2, 17,
                "prism1 'p': 'wob(Dx)' calls the function 'wob'"},
        RadCase{"directional_function_arity", L "void plasfunc f 2 erf . 0 4 .5 .5 .5 .1\nf sphere s 0 0 4 0 0 0 1\n", "E307", 2, 19,
                "'erf' is not a function of three or four arguments"},
        RadCase{"sky_function_file", L "void brightfunc f 2 mysky my.cal 0 0\nf glow g 0 0 4 1 1 1 0\ng source s 0 0 4 0 0 1 180\n", "E308", 2, 27,
                "cannot read the function file 'my.cal'"},
        // Patterns on emitters: every name they use is checked where it is written.
        RadCase{"pattern_unknown_function", L "void brightfunc b 2 wobble(Dx) . 0 0\nb light m 0 0 3 1 1 1\nm sphere s 0 0 4 0 0 0 1\n", "E307", 2,
                21, "calls the function 'wobble'"},
        RadCase{"pattern_unknown_variable", L "void brightfunc b 2 Qx+1 . 0 0\nb light m 0 0 3 1 1 1\nm sphere s 0 0 4 0 0 0 1\n", "E307", 2, 21,
                "uses 'Qx', which neither its file nor the ray defines"},
        RadCase{"pattern_data_file", L "void brightdata d 4 noop none.dat . Dx 0 0\nd light m 0 0 3 1 1 1\nm sphere s 0 0 4 0 0 0 1\n", "E308", 2,
                26, "cannot read the data file 'none.dat'"},
        RadCase{"pattern_picture", L "void colorpict c 5 red green blue sky.hdr . 0 0\nc glow m 0 0 4 1 1 1 0\nm sphere s 0 0 4 0 0 0 1\n",
                "E308", 2, 35, "cannot find the picture 'sky.hdr'"},
        RadCase{"pattern_chain", L "void texfunc t 4 dx dy dz . 0 0\nt brightfunc b 2 1 . 0 0\nb light m 0 0 3 1 1 1\nm sphere s 0 0 4 0 0 0 1\n",
                "E307", 4, 1, "crex evaluates the patterns brightfunc, colorfunc"},
        RadCase{"tipped_sky", L "void brightfunc f 4 skybr skybright.cal -rx 90 0 3 2 1 .2\nf glow g 0 0 4 1 1 1 0\ng source s 0 0 4 0 0 1 180\n",
                "E307", 2, 45, "a sky tipped away from +z"},
        RadCase{"orientation_varies", L "void plastic2 p 4 Px 0 1 . 0 6 .5 .5 .5 .05 .1 .2\np sphere s 0 0 4 0 0 0 1\n", "E307", 2, 19,
                "cannot be evaluated once for the whole surface"},
        // Arguments of the types crex does render.
        RadCase{"zero_roughness", L "void metal2 m 4 0 0 1 . 0 6 .5 .5 .5 .9 0 .1\n", "E303", 2, 41, "roughness must be in (0, 1]"},
        RadCase{"spot_angle", L "void spotlight s 0 0 7 1 1 1 0 0 0 -1\n", "E303", 2, 30, "cone angle"},
        RadCase{"source_angle", L "l source sun 0 0 4 0 0 1 0\n", "E303", 2, 26, "the angle must be in (0, 360]"},
        RadCase{"source_material", "void plastic p 0 0 5 .5 .5 .5 0 0\np source sun 0 0 4 0 0 1 1\n", "E303", 2, 1,
                "needs a light or glow material"},
        RadCase{"interface_ior", L "void interface w 0 0 8 1 1 1 1.33 1 1 1 0\n", "E303", 2, 41, "outside index of refraction"},
        RadCase{"alternate_undefined", L "void illum i 1 glass 0 3 1 1 1\n", "E305", 2, 16, "the alternate material 'glass'"},
        // Views and tags.
        RadCase{"view_type", "#@crex view -vtq\n" L, "E307", 1, 13, "not a RADIANCE view type"},
        RadCase{"fisheye_angle", "#@crex view -vta -vh 400\n" L, "E303", 1, 22, "(0, 360]"},
        RadCase{"perspective_angle", "#@crex view -vh 200\n" L, "E303", 1, 17, "(0, 180)"},
        RadCase{"tag_without_name", "#@crex tag task=2\n" L, "E304", 1, 1, "name=NAME is missing"},
        RadCase{"tag_two_scopes", "#@crex tag name=a begin prefix=x\n" L, "E303", 1, 1, "'begin' tags what follows"},
        RadCase{"tag_blocks_nest", "#@crex tag name=a begin\n#@crex tag name=b begin\n" L, "E303", 2, 1, "blocks do not nest"},
        RadCase{"tag_nothing", L "#@crex tag name=lonely\n", "W307", 2, 1, "tags no surface"},
        RadCase{"self_crossing_polygon", L "l polygon bow 0 0 12 0 0 0 2 2 0 2 0 0 0 1 0\n", "W308", 2, 3, "crosses itself"},
        RadCase{"mirror_alternate", "void plastic pink 0 0 5 .9 .5 .6 .8 .015\nvoid mirror m 1 pink 0 3 .8 .8 .8\nm polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n" L
                "l sphere s 0 0 4 0 0 5 1\n", "W306", 2, 17, "renders its surfaces as 'pink'"}),
    [](const ::testing::TestParamInfo<RadCase>& p) { return std::string(p.param.name); });

// Errors in a file's text: each located, naming what stops it, and no scene.
INSTANTIATE_TEST_SUITE_P(
    Errors, RadianceDiagnostic,
    ::testing::Values(
        RadCase{"unknown_command", "void light l 0 0 3 1 1 1\n!obj2rad chair.obj\n", "E307", 2, 2, "the command 'obj2rad' is not supported"},
        RadCase{"shell_syntax", "void light l 0 0 3 1 1 1\n!genbox l b 1 1 1 > box.rad\n", "E307", 2, 19, "'>' in a '!' command needs a shell"},
        RadCase{"missing_include", "void light l 0 0 3 1 1 1\n!xform -t 1 0 0 nowhere.rad\n", "E308", 2, 17, "cannot read the scene file 'nowhere.rad'"},
        RadCase{"instance", "void light l 0 0 3 1 1 1\nl instance car 1 car.oct 0 0\n", "E308", 2, 18,
                "instance 'car': cannot read the octree 'car.oct': no such file"},
        RadCase{"mesh_file", "void light l 0 0 3 1 1 1\nl mesh vase 1 vase.rtm 0 0\n", "E308", 2, 15, "cannot read the compiled mesh 'vase.rtm': no such file"},
        RadCase{"unknown_type", "void light l 0 0 3 1 1 1\nl teapot t 0 0 0\n", "E307", 2, 3, "unknown RADIANCE type 'teapot'"},
        RadCase{"pattern_modifier_file", "void brightfunc b 2 x y 0 0\nb plastic p 0 0 5 1 1 1 0 0\np sphere s 0 0 4 0 0 0 1\n", "E308", 1,
                23, "cannot read the function file 'y'"},
        RadCase{"unsupported_material", "void plasdata a 4 f d.dat x.cal y 0 4 .5 .5 .5 0\na ring r 0 0 8 0 0 0 0 0 1 0 1\n", "E307", 1, 6,
               "RADIANCE material type 'plasdata' ('a') is not supported"},
        RadCase{"antimatter_unknown", "void antimatter a 1 wall 0 0\na ring r 0 0 8 0 0 0 0 0 1 0 1\n", "E305", 1, 21,
               "antimatter 'a' uses the modifier to clip 'wall', which is not defined above it"},
        RadCase{"mixtext_font", "void plastic w 0 0 5 1 1 1 0 0\nvoid mixtext m 4 w void nofont.fnt . 0 9 0 0 0 0 1 0 0 0 -1\nm sphere s 0 0 4 0 0 0 1\n",
               "E308", 2, 25, "mixtext 'm': cannot read the font file 'nofont.fnt'"},
        RadCase{"mixture_light", "void plastic w 0 0 5 1 1 1 0 0\nvoid light l 0 0 3 1 1 1\nvoid mixfunc m 4 w l x .  0 0\nm sphere s 0 0 4 0 0 0 1\n",
                "E307", 3, 20, "'l' is a light source direct lighting samples"},
        RadCase{"mixture_other", "void plastic w 0 0 5 1 1 1 0 0\nvoid mixpict m 7 w w grey p.hdr . u v 0 0\nm sphere s 0 0 4 0 0 0 1\n", "E307", 2, 6,
                "mixpict 'm' (a mixture of materials"},
        RadCase{"unclosed_quote", "void light 'l 0 0 3 1 1 1\n", "E301", 1, 12, "never closed"},
        RadCase{"undefined_alias", "void alias a nothing\n", "E305", 1, 14, "'nothing', which is not defined"},
        RadCase{"truncated", "void light l 0 0 3 1 1\n", "E301", 2, 1, "real argument 3 of 3 is missing"},
        RadCase{"truncated_header", "void light\n", "E301", 2, 1, "the file ends inside"},
        RadCase{"bad_count", "void light l 0 0 x 1 1 1\n", "E302", 1, 18, "expected the number of real arguments"},
        RadCase{"not_a_number", "void light l 0 0 3 1 one 1\n", "E302", 1, 22, "expected a real number, got 'one'"},
        RadCase{"nan", "void light l 0 0 3 1 nan 1\n", "E303", 1, 22, "finite"},
        RadCase{"inf", "void light l 0 0 3 1 1 inf\n", "E303", 1, 24, "finite"},
        RadCase{"wrong_arity", "void plastic p 0 0 3 1 1 1\n", "E303", 1, 22, "takes 5 real arguments, got 3"},
        RadCase{"reflectance_range", "void plastic p 0 0 5 1 2 1 0 0\n", "E303", 1, 24, "reflectance must be in [0, 1]"},
        RadCase{"radiance_beyond_floats", "void light l 0 0 3 1 1e100 1\nl sphere s 0 0 4 0 0 0 1\n", "E303", 2, 3,
               "material 'l': radiance 1e+100 is beyond the 1e+30"},
        RadCase{"undefined_modifier", "void light l 0 0 3 1 1 1\nwhite sphere s 0 0 4 0 0 0 1\n", "E305", 2, 1,
               "modifier 'white', which is not defined"},
        RadCase{"degenerate_ring_normal", "void light l 0 0 3 1 1 1\nl ring r 0 0 8 0 0 0 0 0 0 0 1\n", "E306", 2, 3,
               "degenerate normal"},
        RadCase{"zero_radius_sphere", "void light l 0 0 3 1 1 1\nl sphere s 0 0 4 0 0 0 0\n", "E306", 2, 3, "radius must be > 0"},
        RadCase{"polygon_arity", "void light l 0 0 3 1 1 1\nl polygon p 0 0 7 0 0 0 1 1 1 2\n", "E303", 2, 3, "3 numbers per vertex"}),
    [](const ::testing::TestParamInfo<RadCase>& p) { return std::string(p.param.name); });

// An array of copies that each fail the same way (here: a file that is not there) says so
// once, and stops: a million copies were a million errors, and nested arrays ran for hours.
TEST(RadianceArrays, ACopyThatFailsIsSaidOnce) {
    auto r = testing::load_rad_text(L "!xform -a 1000 -t 1 0 0 -a 1000 -t 0 1 0 missing.rad\n");
    EXPECT_FALSE(r.scene);
    size_t e308 = 0;
    for (const auto& d : r.diagnostics) e308 += d.code == "E308";
    EXPECT_EQ(e308, 1u);
}

#undef L

}  // namespace
}  // namespace crex
