// One case per diagnostic code: the code, its line and column (and end column), so that no
// test passes on a different error. A few cases also pin the full rendered text.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "base/render_json.h"
#include "base/render_text.h"
#include "compiler/crex/parse.h"

#include <set>
#include "tests/support/compile_helpers.h"

namespace crex {
namespace {

struct Expected {
    const char* crex;
    const char* code;
    uint32_t col;      // 1-based
    uint32_t end_col;  // one past the span
};

class CrexDiagnostic : public ::testing::TestWithParam<Expected> {};

TEST_P(CrexDiagnostic, HasCodeAndPosition) {
    const Expected& e = GetParam();
    auto r = testing::check(e.crex);
    const Diagnostic* found = nullptr;
    for (const auto& d : r.diagnostics)
        if (d.code == e.code) found = &d;
    ASSERT_NE(found, nullptr) << e.crex << " should report " << e.code;
    LineCol b = r.file->position(found->span.begin);
    LineCol end = r.file->position(found->span.end);
    EXPECT_EQ(b.line, 1u);
    EXPECT_EQ(b.col, e.col) << e.crex;
    EXPECT_EQ(end.col, e.end_col) << e.crex;
}

INSTANTIATE_TEST_SUITE_P(
    EveryCode, CrexDiagnostic,
    ::testing::Values(
        Expected{"TTx", "E001", 3, 4}, Expected{"T%", "E001", 2, 3}, Expected{"T\xC3\xA9", "E001", 2, 3},
        Expected{"T\xFF", "E001", 2, 3}, Expected{"(DG", "E002", 4, 4}, Expected{"<DG)", "E002", 4, 5},
        Expected{"DG)", "E002", 3, 4}, Expected{"D0", "E003", 2, 3}, Expected{"TD2147483648", "E003", 3, 13},
        Expected{"TT{TD*}", "E004", 6, 7}, Expected{"[T(G*)]", "E005", 5, 6},
        Expected{"{T(G{R})}", "E006", 5, 6}, Expected{"{T<[RS]>}", "E007", 4, 5},
        Expected{"T(*D)", "E008", 3, 4}, Expected{"D2 3", "E009", 4, 5}, Expected{"D 2\t3", "E009", 5, 6},
        Expected{"D**", "W101", 3, 4}, Expected{"(GT*)2", "W101", 6, 7},
        Expected{"<DGD>", "W102", 4, 5}, Expected{"<D2>", "W102", 3, 4}, Expected{"<{TT}>", "W102", 4, 5},
        Expected{"T()", "W104", 2, 4}, Expected{"[]", "W104", 1, 3}, Expected{"[T[R]]", "W105", 3, 4}),
    [](const ::testing::TestParamInfo<Expected>& p) {
        return std::string(p.param.code) + "_case" + std::to_string(p.index);
    });

TEST(CrexDiagnostic, TooDeepNestingIsE010NotACrash) {
    std::string deep(5000, '(');
    deep += "D";
    deep += std::string(5000, ')');
    auto r = testing::check(deep);
    EXPECT_TRUE(r.has_code("E010"));
    EXPECT_EQ(r.file->position(r.diagnostics.front().span.begin).col, kMaxCrexNesting + 1);
}

TEST(CrexDiagnostic, NestingAtTheLimitIsAccepted) {
    std::string s(kMaxCrexNesting, '(');
    s += "D";
    s += std::string(kMaxCrexNesting, ')');
    auto r = testing::check(s);
    EXPECT_EQ(r.errors, 0u);
}

// Lowering wraps an item once per repeat: `D` and 70,000 stacked '*' lowered to a tree 70,000
// deep and overflowed the stack (issue 37). Repeats count toward the depth like groups do.
TEST(CrexDiagnostic, StackedRepeatsAreE010NotACrash) {
    auto r = testing::check("D" + std::string(70000, '*'));
    ASSERT_TRUE(r.has_code("E010"));
    EXPECT_EQ(r.file->position(r.diagnostics.front().span.begin).col, kMaxCrexNesting + 1);
    EXPECT_NE(r.diagnostics.front().message.find("groups and repeats nested more than"), std::string::npos);
    auto ten_groups_deep = testing::check(std::string(10, '(') + "D" + std::string(10, ')') + std::string(300, '*'));
    EXPECT_TRUE(ten_groups_deep.has_code("E010"));  // 11 levels of groups and leaf, then 300 repeats of the outermost
    auto at_limit = testing::check("D" + std::string(kMaxCrexNesting - 1, '*'));
    EXPECT_FALSE(at_limit.has_code("E010"));
    auto digits = testing::check("(D)" + std::string(kMaxCrexNesting, '2'));  // one integer repeat, however long
    EXPECT_FALSE(digits.has_code("E010"));
}

TEST(CrexDiagnostic, AllErrorsAreReportedInOnePass) {
    auto r = testing::check("X{D*}[G*]{T{R}}*D0");
    for (const char* code : {"E001", "E003", "E004", "E005", "E006"}) EXPECT_TRUE(r.has_code(code)) << code;
}

TEST(CrexDiagnostic, DeferredGroupRulesForW102) {
    // An unmodulated earlier occurrence covers a later one; a modulated one with a lower
    // threshold covers a later modulated one; a modulated one leaves I = 0 rays for a later
    // unmodulated one, so that one is not warned about.
    EXPECT_TRUE(testing::check("<D{D}>").has_code("W102"));
    EXPECT_FALSE(testing::check("<{D}D>").has_code("W102"));
    EXPECT_FALSE(testing::check("<DG>2").has_code("W102"));
    EXPECT_FALSE(testing::check("{TT}").has_code("W102"));
    EXPECT_TRUE(testing::check("<<D>D>").has_code("W102"));
}

TEST(CrexDiagnostic, RendersLikeACompiler) {
    auto r = testing::check("TT{TD*}");
    ASSERT_EQ(r.diagnostics.size(), 1u);
    EXPECT_EQ(render_text(r.diagnostics[0]),
              "<expr>:1:6: error[E004]: '*' inside '{ }': unbounded work cannot be importance-modulated\n"
              "    1 | TT{TD*}\n"
              "      |      ^\n"
              "<expr>:1:3: note: the importance-modulated group opens here\n"
              "    1 | TT{TD*}\n"
              "      |   ^\n");
}

TEST(CrexDiagnostic, ALongLineIsShownAroundItsSpan) {
    // A minified glTF is one line of megabytes: the quote is 120 code points around the span
    // (an accent in the cut part must not split), its cut ends marked, the caret still under it.
    std::string text = "\xC3\xA9" + std::string(4999, 'a') + "XYZ" + std::string(5000, 'b');
    SourceFile file("big.gltf", text);
    Diagnostic d;
    d.code = "W311";
    d.severity = Severity::kWarning;
    d.message = "here";
    d.span = {&file, 5001, 5004};  // "XYZ": columns 5001-5003
    const std::string out = render_text(d);
    const size_t quote = out.find("    1 | ");
    ASSERT_NE(quote, std::string::npos) << out;
    const std::string line = out.substr(quote + 8, out.find('\n', quote) - quote - 8);
    EXPECT_EQ(line, "..." + std::string(40, 'a') + "XYZ" + std::string(77, 'b') + "...");
    EXPECT_NE(out.find("      | " + std::string(43, ' ') + "^~~\n"), std::string::npos) << out;
    // A span over the whole line underlines only what is shown.
    d.span = {&file, 0, static_cast<uint32_t>(text.size())};
    const std::string whole = render_text(d);
    EXPECT_NE(whole.find("    1 | \xC3\xA9" + std::string(119, 'a') + "...\n      | ^" + std::string(119, '~') + "\n"), std::string::npos) << whole;
    EXPECT_LT(whole.size(), 400u);
}

// A warning said for each of many meshes is shown five times, then counted; an error after
// them is shown, and a different warning code keeps its own five.
TEST(CrexDiagnostic, AWarningRepeatedManyTimesIsShownFiveTimesThenCounted) {
    std::vector<Diagnostic> ds;
    auto add = [&](const std::string& code, Severity severity, const std::string& message) {
        Diagnostic d;
        d.code = code, d.severity = severity, d.message = message, d.where = "model.obj";
        ds.push_back(d);
    };
    for (int i = 0; i < 300; ++i) add("W303", Severity::kWarning, fmt::format("mesh 'm{}': 1 of 12 triangles", i));
    add("W304", Severity::kWarning, "polygon: zero area");
    add("E305", Severity::kError, "shape uses material 'x', which is not defined");
    const std::string out = render_text(ds);
    auto count = [&](const std::string& what) {
        size_t n = 0;
        for (size_t at = out.find(what); at != std::string::npos; at = out.find(what, at + 1)) ++n;
        return n;
    };
    EXPECT_EQ(count("warning[W303]: mesh"), 5u) << out;
    EXPECT_NE(out.find("mesh 'm4':"), std::string::npos);
    EXPECT_EQ(out.find("mesh 'm5':"), std::string::npos);
    EXPECT_NE(out.find("warning[W303]: 295 more like it not shown (300 in all)\n"), std::string::npos) << out;
    EXPECT_EQ(count("warning[W304]"), 1u);
    EXPECT_EQ(count("error[E305]"), 1u);
    EXPECT_EQ(count("more like it"), 1u);  // W304 was said once: nothing to count
}

TEST(CrexDiagnostic, E001ListsWhatIsAllowedAndSuggestsUpperCase) {
    auto r = testing::check("d");
    ASSERT_EQ(r.diagnostics.size(), 1u);
    EXPECT_NE(r.diagnostics[0].message.find("D G S T R M"), std::string::npos);
    EXPECT_NE(r.diagnostics[0].message.find("( ) < > { } [ ]"), std::string::npos);
    EXPECT_EQ(r.diagnostics[0].help, "components are upper case: write 'D'");
}

TEST(CrexDiagnostic, E002PointsAtOpenerAndExpectedCloser) {
    auto r = testing::check("T<DG");
    ASSERT_EQ(r.diagnostics.size(), 1u);
    const Diagnostic& d = r.diagnostics[0];
    EXPECT_EQ(r.file->position(d.span.begin).col, 5u);  // just past "DG"
    ASSERT_EQ(d.notes.size(), 1u);
    EXPECT_EQ(r.file->position(d.notes[0].span.begin).col, 2u);
}

TEST(CrexDiagnostic, ColumnsCountCodePointsAndCaretsLineUp) {
    auto r = testing::check("\xC3\xA9\xC3\xA9 X");  // "éé X"
    ASSERT_GE(r.diagnostics.size(), 3u);
    const Diagnostic& x = r.diagnostics.back();
    EXPECT_EQ(r.file->position(x.span.begin).col, 4u);
    EXPECT_NE(render_text(x).find("    1 | \xC3\xA9\xC3\xA9 X\n      |    ^\n"), std::string::npos)
        << render_text(x);
}

TEST(CrexDiagnostic, EmbeddedCrexKeepsFileCoordinates) {
    // A crex inside a longer file (as a pipeline literal will be): spans are file offsets.
    SourceFile file("p.pipe", "line one\n  crex \"TT{D*}\"\n");
    uint32_t begin = static_cast<uint32_t>(file.text().find("TT{"));
    uint32_t end = static_cast<uint32_t>(file.text().find("\"\n"));
    DiagnosticSink sink;
    compile_crex(file, begin, end, sink);
    auto ds = sink.sorted();
    ASSERT_EQ(ds.size(), 1u);
    EXPECT_EQ(ds[0].code, "E004");
    EXPECT_EQ(file.position(ds[0].span.begin).line, 2u);
    EXPECT_EQ(file.position(ds[0].span.begin).col, 13u);
    EXPECT_EQ(format_location(ds[0].span), "p.pipe:2:13");
}

TEST(CrexDiagnostic, JsonHasEveryField) {
    auto r = testing::check("<DG)");
    auto j = to_json(r.diagnostics);
    ASSERT_EQ(j.size(), 1u);
    EXPECT_EQ(j[0]["code"], "E002");
    EXPECT_EQ(j[0]["severity"], "error");
    EXPECT_EQ(j[0]["file"], "<expr>");
    EXPECT_EQ(j[0]["line"], 1);
    EXPECT_EQ(j[0]["col"], 4);
    EXPECT_EQ(j[0]["end_line"], 1);
    EXPECT_EQ(j[0]["end_col"], 5);
    EXPECT_EQ(j[0]["notes"][0]["col"], 1);
}

TEST(CrexDiagnostic, EveryCodeInTheTableIsUniqueAndWellFormed) {
    std::set<std::string> seen;
    for (const auto& info : diagnostic_code_table()) {
        EXPECT_TRUE(seen.insert(std::string(info.code)).second) << info.code;
        ASSERT_EQ(info.code.size(), 4u);
        EXPECT_EQ(info.code[0] == 'E', info.severity == Severity::kError) << info.code;
    }
}

}  // namespace
}  // namespace crex
