// RADIANCE's data files and the function language's evaluation as patterns use them
// (issue 39): a table's interpolation and what lies beyond it, located errors in a malformed
// file, and names resolved once (Program::bind) giving what looking them up each time gives.
#include <gtest/gtest.h>

#include "runtime/scene/data_table.h"
#include "runtime/scene/radiance/calc.h"
#include "runtime/scene/radiance/data_file.h"

namespace crex::radiance {
namespace {

DataTable parse(const std::string& text) {
    DataTable t;
    DataFileError e;
    EXPECT_TRUE(parse_data_file(text, t, e)) << e.message;
    return t;
}

TEST(RadianceDataFile, InterpolatesLinearlyOnAnEvenGrid) {
    const DataTable t = parse("# comment\n1\n0 90 4   # 0, 30, 60, 90\n1 .5 .25 0\n");
    auto at = [&](double x) { return data_value(t, &x); };
    EXPECT_DOUBLE_EQ(at(0), 1);
    EXPECT_DOUBLE_EQ(at(15), 0.75);
    EXPECT_DOUBLE_EQ(at(45), 0.375);
    EXPECT_DOUBLE_EQ(at(90), 0);
    // One grid step beyond the end the line goes on (60 -> 90 falls 0.25 a step) ...
    EXPECT_DOUBLE_EQ(at(120), -0.25);
    // ... then falls off harmonically: at x steps, (2 y1 - y0) / (x - (i - 1)) with i = 2.
    EXPECT_DOUBLE_EQ(at(180), (2 * 0 - 0.25) / (6 - 1));
}

TEST(RadianceDataFile, ListedPointsAndTwoDimensions) {
    // Rows at 0 and 10 (even), columns at the listed 0, 1, 3; the last dimension fastest.
    const DataTable t = parse("2\n0 10 2\n0 0 3 0 1 3\n0 1 3\n10 11 13\n");
    double p[2] = {5, 2};  // halfway between the rows, halfway between columns 1 and 3
    EXPECT_DOUBLE_EQ(data_value(t, p), 0.5 * (2 + 12));
    double q[2] = {0, 0.5};
    EXPECT_DOUBLE_EQ(data_value(t, q), 0.5);
}

TEST(RadianceDataFile, AMalformedFileSaysWhereAndWhat) {
    DataTable t;
    DataFileError e;
    EXPECT_FALSE(parse_data_file("1\n0 90 3\n1 x 2\n", t, e));
    EXPECT_EQ(e.line, 3);
    EXPECT_EQ(e.column, 3);
    EXPECT_NE(e.message.find("'x' is not a number"), std::string::npos) << e.message;
    EXPECT_FALSE(parse_data_file("1\n0 90 3\n1 2\n", t, e));
    EXPECT_NE(e.message.find("ends"), std::string::npos) << e.message;
    EXPECT_FALSE(parse_data_file("9\n", t, e));
    EXPECT_NE(e.message.find("from 1 to 5"), std::string::npos) << e.message;
    EXPECT_FALSE(parse_data_file("1\n0 0 3 0 2 1\n1 2 3\n", t, e));  // listed points must rise or fall
    EXPECT_NE(e.message.find("order"), std::string::npos) << e.message;
}

TEST(RadianceCalc, BoundNamesEvaluateAsLookedUpNames) {
    // A function file with forward references, a constant, a recursive function, the library
    // and the arguments, evaluated before and after bind().
    const char* kDefs = "f(x) = if(x - 1, x * f(x - 1), 1); g = h + A2; h : 2 * PI;\n"
                        "phi = mod(Atan2(-Dy, -Dx) / DEGREE, 360); q = tri(phi, 90) + select(2, 1, AC, 3);";
    const char* kExprs[] = {"f(5) + g", "phi", "q", "max(1, 2, Dx) - min(Dy, 0)", "arg(0) + A1"};
    calc::Program a, b;
    calc::Error e;
    ASSERT_TRUE(a.define(kDefs, e)) << e.message;
    ASSERT_TRUE(b.define(kDefs, e)) << e.message;
    b.bind();
    calc::Environment env;
    env.args = {0.5, 7};
    env.variable = [](const std::string& n) -> std::optional<double> {
        if (n == "Dx") return 0.3;
        if (n == "Dy") return -0.8;
        return std::nullopt;
    };
    for (const char* text : kExprs) {
        auto ea = a.parse(text, e), eb = b.parse(text, e);
        ASSERT_TRUE(ea && eb) << text;
        auto va = a.evaluate(*ea, env, e), vb = b.evaluate(*eb, env, e);
        ASSERT_TRUE(va && vb) << text << ": " << e.message;
        EXPECT_EQ(*va, *vb) << text;
    }
    auto f5 = b.parse("f(5)", e);
    EXPECT_EQ(*b.evaluate(*f5, env, e), 120);
    // A definition after bind() takes effect for what is parsed after it.
    ASSERT_TRUE(b.define("h : 1;", e));
    auto g = b.parse("g", e);
    EXPECT_EQ(*b.evaluate(*g, env, e), 8);
}

}  // namespace
}  // namespace crex::radiance
