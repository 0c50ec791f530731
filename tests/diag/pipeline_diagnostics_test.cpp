// The pipeline checker: one case per code with its line and column, and the normative example
// of spec/pipeline.md section 6 checks clean.
#include <gtest/gtest.h>

#include "tests/support/diagnostic_helpers.h"

#include <fstream>
#include <sstream>

#include "compiler/pipeline/check.h"
#include "compiler/pipeline/parse.h"

namespace crex {
namespace {

struct Result : testing::Diagnosed {
    std::unique_ptr<SourceFile> file;
};

Result check(const std::string& text) {
    Result r;
    r.file = std::make_unique<SourceFile>("p.pipe", text);
    DiagnosticSink sink;
    if (auto f = pipeline::parse_pipeline_file(*r.file, sink)) pipeline::check_pipeline_file(*f, sink);
    r.diagnostics = sink.sorted();
    r.errors = sink.error_count();
    return r;
}

TEST(PipelineCheck, NormativeExampleChecksClean) {
    std::ifstream in(CREX_SOURCE_DIR "/examples/pipelines/cornell_prog.pipe");
    std::stringstream text;
    text << in.rdbuf();
    Result r = check(text.str());
    EXPECT_EQ(r.errors, 0u) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    EXPECT_TRUE(r.diagnostics.empty()) << r.diagnostics[0].code << " " << r.diagnostics[0].message;
}

TEST(PipelineCheck, PipelinesThatExecuteFullyGetNoW403) {
    Result r = check("pipeline p {\n  preselective { crex \"(TTMRSGD)*\" spp 4 }\n}\n");
    EXPECT_TRUE(r.diagnostics.empty());
    Result sel = check("pipeline p {\n  guidance { s = saliency(preview) }\n  selective { vary spp 1 .. 8 by s\n"
                       "    vary shadow_rays 1 .. 4 by s }\n}\n");
    EXPECT_TRUE(sel.diagnostics.empty()) << sel.diagnostics[0].message;
    // media_samples executes now: without a scene nothing is said.
    Result media = check("pipeline p {\n  guidance { s = saliency(preview) }\n  selective { vary media_samples 1 .. 8 by s }\n}\n");
    EXPECT_TRUE(media.diagnostics.empty()) << media.diagnostics[0].message;
}

TEST(PipelineCheck, StdlibBasesAreInherited) {
    // prog_dis_all defines sal, ic and dl; a child may use them without redefining them.
    Result child = check("pipeline p extends prog_dis_all {\n  selective { vary spp 1 .. 4 by dl }\n}\n");
    EXPECT_EQ(child.errors, 0u) << (child.diagnostics.empty() ? "" : child.diagnostics[0].message);
    // capict's per-component variables are inherited and can be overridden one by one.
    Result capict = check("pipeline p extends capict {\n  selective { vary subsample(D) 4 .. 1 by dd }\n}\n");
    EXPECT_EQ(capict.errors, 0u) << (capict.diagnostics.empty() ? "" : capict.diagnostics[0].message);
    EXPECT_EQ(capict.find("W202"), nullptr);
}

struct Case {
    const char* name;
    const char* body;  // statements inside `pipeline p { ... }`, starting on line 2
    const char* code;
    uint32_t line, col;
    const char* message_part;
};

class PipelineDiagnostic : public ::testing::TestWithParam<Case> {};

TEST_P(PipelineDiagnostic, HasCodeLineAndColumn) {
    const Case& c = GetParam();
    Result r = check(std::string("pipeline p {\n") + c.body + "\n}\n");
    testing::expect_diagnostic(r, c.name, c.code, c.line, c.col, c.message_part);
}

INSTANTIATE_TEST_SUITE_P(
    EveryCode, PipelineDiagnostic,
    ::testing::Values(
        Case{"syntax", "  guidance { a = }", "E201", 2, 18, "unexpected '}'"},
        Case{"unknown_section", "  guidence { }", "E202", 2, 3, "unknown section 'guidence'"},
        Case{"unknown_setting", "  imgae 512 x 512", "E202", 2, 3, "unknown setting 'imgae'"},
        Case{"bad_size", "  image 512 512", "E203", 2, 9, "WIDTH x HEIGHT"},
        Case{"unknown_operator", "  guidance { sal = saliancy(preview) }", "E204", 2, 20, "unknown guidance operator 'saliancy'"},
        Case{"use_before_definition", "  guidance { a = edges(b)\n b = saliency(preview) }", "E205", 2, 24, "'b' is not defined"},
        Case{"wrong_type", "  guidance { t = task_map(preview) }", "E206", 2, 27, "expected a set of tagged objects"},
        Case{"bad_op", "  guidance { a = saliency(preview)\n  i = importance(a 1, op \"-\") }", "E206", 3, 26, "op is"},
        // A fovea of 1e30 deg said "expects a angle like 2 deg": the range, and the article.
        Case{"angle_out_of_range", "  guidance { t = task_map(tagged(), fovea 1e30 deg) }", "E206", 2, 43,
             "task_map(): 'fovea' expects an angle above 0 and below 180 deg, like 2 deg"},
        Case{"unknown_variable", "  selective { vary spp_max 1 .. 2 by constant(1) }", "E207", 2, 20, "unknown selective variable"},
        // capict's per-component variable: only subsample takes a component, and only D G S T R M.
        Case{"component_of_spp", "  selective { vary spp(D) 1 .. 2 by constant(1) }", "E207", 2, 24, "only subsample takes one"},
        Case{"not_a_component", "  selective { vary subsample(X) 8 .. 1 by constant(1) }", "E207", 2, 30, "'X' is not a component"},
        Case{"refine_without_component", "  selective { vary subsample 8 .. 1 by constant(1) refine 0.5 }", "E207", 2, 59,
             "refine applies to one component"},
        Case{"refine_range", "  selective { vary subsample(D) 8 .. 1 by constant(1) refine 0 }", "E208", 2, 62, "refine: expected"},
        Case{"component_varied_twice", "  selective { vary subsample(D) 8 .. 1 by constant(1)\n  vary subsample(D) 4 .. 1 by constant(0) }",
             "E211", 3, 8, "given twice"},
        Case{"range", "  selective { vary spp 1 .. 2.5 by constant(1) }", "E208", 2, 29, "out of range"},
        Case{"budget_unit", "  budget 10 deg", "E209", 2, 10, "needs a unit"},
        // Settings out of the range of settings_table.cpp (the same as crex run's flags).
        Case{"spp_zero", "  preselective { spp 0 }", "E203", 2, 22, "whole number from 1 to 1048576"},
        Case{"spp_huge", "  selective { spp 1e9 }", "E203", 2, 19, "whole number from 1 to 1048576"},
        Case{"image_fraction", "  image 32.5 x 32", "E203", 2, 9, "image: width: 32.5 is not a whole number"},
        Case{"image_height_zero", "  image 32 x 0", "E203", 2, 14, "image: height: 0 is out of range"},
        Case{"budget_infinite", "  budget 1e400 s", "E209", 2, 10, "a time in (0, 1e+06] s"},
        Case{"budget_over_100_percent", "  budget 101 %", "E209", 2, 10, "(0, 100] %"},
        Case{"av_negative", "  av -1", "E203", 2, 6, "a number from 0 to 1e30"},
        Case{"lw_above_one", "  lw 2", "E203", 2, 6, "a number from 0 to 1"},
        Case{"max_depth_huge", "  max_depth 1e12", "E203", 2, 13, "whole number from 0 to 65535"},
        Case{"ab_huge", "  ab 100000", "E203", 2, 6, "whole number from 1 to 64"},
        Case{"aa_zero", "  aa 0", "E203", 2, 6, "a number from 0.001 to 1"},
        Case{"seed_fraction", "  seed 1.5", "E203", 2, 8, "whole number from 0 to 9007199254740992"},
        Case{"unknown_policy", "  policy \"nosuch\"", "E203", 2, 10, "unknown scheduling policy 'nosuch'"},
        Case{"duplicate_map", "  guidance { a = saliency(preview)\n  a = edges(direct) }", "E211", 3, 3, "already defined"},
        Case{"duplicate_setting", "  image 8 x 8\n  image 16 x 16", "E211", 3, 3, "given twice"},
        Case{"braces_in_preselective", "  preselective { crex \"T{R}\" }", "E212", 2, 24, "may not contain"},
        Case{"crex_error_at_file_column", "  selective { crex \"{TD*}\" }", "E004", 2, 24, "inside '{ }'"},
        Case{"unused_map", "  guidance { a = saliency(preview) }", "W201", 2, 14, "no selective variable or crex uses it"}),
    [](const ::testing::TestParamInfo<Case>& p) { return std::string(p.param.name); });

TEST(PipelineCheck, ExtendsUnknownBaseIsE210) {
    Result r = check("pipeline a extends gold_standard { }\n");
    const Diagnostic* d = r.find("E210");
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(r.file->position(d->span.begin).col, 20u);
    Result ok = check("pipeline a { }\npipeline b extends a { }\n");
    EXPECT_EQ(ok.errors, 0u);
}

TEST(PipelineCheck, CommentsAndUtf8AreFine) {
    Result r = check("// caf\xC3\xA9\npipeline p { /* \xC3\xA9 */ scene \"sc\xC3\xA8ne.json\" }\n");
    EXPECT_EQ(r.errors, 0u) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(PipelineCheck, UnknownModulationFunctionIsE206AtItsName) {
    Result r = check("pipeline p {\n  guidance { m = constant(1) }\n  selective { vary spp 1 .. 4 by m using sqr }\n}\n");
    const Diagnostic* d = r.find("E206");
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(r.file->position(d->span.begin).line, 3u);
    EXPECT_EQ(r.file->position(d->span.begin).col, 42u);
    EXPECT_NE(d->help.find("sqrt"), std::string::npos) << d->help;
    Result ok = check("pipeline p {\n  guidance { m = constant(1) }\n  selective { vary spp 1 .. 4 by m using sqrt }\n}\n");
    EXPECT_EQ(ok.errors, 0u);
}

TEST(PipelineCheck, SettingsAtTheEdgesOfTheirRangesAreAccepted) {
    Result r = check("pipeline p {\n  image 1 x 16384\n  seed 0\n  budget 1000000 s\n  policy \"queues\"\n  lw 0\n  max_depth 65535\n"
                     "  ab 64\n  ad 65536\n  av 0\n  aa 0.001\n  preselective { spp 1048576 }\n  selective { spp 1 }\n}\n");
    EXPECT_EQ(r.errors, 0u) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    Result percent = check("pipeline p {\n  budget 100 %\n  policy \"tasks\"\n}\n");
    EXPECT_EQ(percent.errors, 0u) << (percent.diagnostics.empty() ? "" : percent.diagnostics[0].message);
}

TEST(PipelineCheck, UnitWordsAndXAreStillUsableAsMapNames) {
    Result r = check("pipeline p {\n  image 16 x 8\n  budget 2 s\n  guidance { s = constant(1)  x = blur(s, sigma 2)  deg = normalise(x) }\n"
                     "  selective { vary spp 1 .. 4 by deg }\n}\n");
    EXPECT_EQ(r.errors, 0u) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(PipelineNesting, DeepBlocksAndCallsAreALocatedErrorNotAStackOverflow) {
    // ~8,000 nested blocks or ~10,000 nested calls used to overflow the parser's stack.
    std::string blocks = "pipeline p {\n";
    for (int i = 0; i < 20000; ++i) blocks += "preselective {";
    Result b = check(blocks);
    ASSERT_EQ(b.errors, 1u);
    EXPECT_EQ(b.diagnostics[0].code, "E213");
    // The 65th '{' overall is the 64th of line 2, each "preselective {" 14 columns wide.
    EXPECT_EQ(b.where("E213").line, 2u);
    EXPECT_EQ(b.where("E213").col, 14u * 64);
    std::string calls = "pipeline p {\n  guidance { m = ";
    for (int i = 0; i < 20000; ++i) calls += "blur(";
    Result c = check(calls);
    ASSERT_EQ(c.errors, 1u);
    EXPECT_EQ(c.diagnostics[0].code, "E213");
    // Sixty levels are still fine syntax-wise (the checker may say what it thinks of them).
    std::string fine = "pipeline p {\n  guidance { m = ";
    for (int i = 0; i < 60; ++i) fine += "blur(";
    fine += "edges(preview)";
    for (int i = 0; i < 60; ++i) fine += ")";
    fine += " }\n}\n";
    for (const auto& d : check(fine).diagnostics) EXPECT_NE(d.code, "E213");
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(PipelineNesting, AChainOfMapsIsBoundedToo) {
    // 29,000 maps each blurring the last crashed `crex plan` (recursion per level).
    std::string text = "pipeline p {\n  guidance {\n    m0 = saliency(preview)\n";
    for (int i = 1; i <= 300; ++i) text += "    m" + std::to_string(i) + " = blur(m" + std::to_string(i - 1) + ")\n";
    text += "  }\n  selective { vary spp 1 .. 4 by m300 }\n}\n";
    Result r = check(text);
    ASSERT_NE(r.find("E214"), nullptr);
    EXPECT_EQ(r.where("E214").line, 3u + 256);  // m256 is the 257th map: a chain of 257
    EXPECT_EQ(r.where("E214").col, 5u);
    EXPECT_EQ(r.errors, 1u);
}

}  // namespace
}  // namespace crex

#include "tests/support/plan_helpers.h"

namespace crex {
namespace {

TEST(PipelineAgainstScene, ATagNoObjectHasIsW203AtTheTag) {
    std::vector<std::string> tags = {"book", "exit_sign"};
    auto r = testing::plan_text("p.pipe", R"(pipeline p {
  guidance {
    task = task_map(tagged("exit_sgn"), fovea 2 deg)
  }
  selective { vary spp 1 .. 4 by task }
})",
                                std::nullopt, "", "", &tags);
    ASSERT_TRUE(r.plan);
    ASSERT_EQ(r.diagnostics.size(), 1u);
    const Diagnostic& d = r.diagnostics[0];
    EXPECT_EQ(d.code, "W203");
    EXPECT_EQ(r.file->position(d.span.begin).line, 3u);
    EXPECT_EQ(r.file->position(d.span.begin).col, 28u);
    EXPECT_NE(d.help.find("'exit_sign'"), std::string::npos) << d.help;
    // The right tag, or no scene known: nothing to say.
    std::vector<std::string> right = {"exit_sgn"};
    auto ok = testing::plan_text("p.pipe", R"(pipeline p {
  guidance { task = task_map(tagged("exit_sgn")) }
  selective { vary spp 1 .. 4 by task }
})",
                                 std::nullopt, "", "", &right);
    EXPECT_TRUE(ok.diagnostics.empty());
}

TEST(PipelineAgainstScene, AComponentBufferThePreviewNeverFillsIsW204AtTheCall) {
    std::vector<std::string> tags;
    auto r = testing::plan_text("p.pipe", R"(pipeline p {
  preselective { crex "TT" }
  guidance { ic = edges(component(D)) }
  selective { vary spp 1 .. 4 by ic }
})",
                                std::nullopt, "", "", &tags);
    ASSERT_TRUE(r.plan);
    ASSERT_EQ(r.diagnostics.size(), 1u);
    EXPECT_EQ(r.diagnostics[0].code, "W204");
    EXPECT_EQ(r.file->position(r.diagnostics[0].span.begin).line, 3u);
    EXPECT_EQ(r.file->position(r.diagnostics[0].span.begin).col, 25u);
    auto filled = testing::plan_text("p.pipe", R"(pipeline p {
  preselective { crex "TTD" }
  guidance { ic = edges(component(D)) }
  selective { vary spp 1 .. 4 by ic }
})",
                                     std::nullopt, "", "", &tags);
    EXPECT_TRUE(filled.diagnostics.empty());
}

// A missing '}' is found at the end of the file, but the note points at the '{' left open
// (guidance's, not the pipeline's, which the last '}' closed instead); a '(' closed by a '}' is
// named; a lone '"' is an unterminated string.
TEST(PipelineSyntax, UnclosedBracketsAndStringsAreNamedWhereTheyOpen) {
    auto unclosed = testing::plan_text("p.pipe", "pipeline p {\n  guidance {\n    sal = saliency(preview)\n"
                                                 "  selective { vary spp 1 .. 4 by sal }\n}\n", std::nullopt);
    ASSERT_EQ(unclosed.diagnostics.size(), 1u);
    ASSERT_EQ(unclosed.diagnostics[0].notes.size(), 1u);
    const DiagnosticNote& n = unclosed.diagnostics[0].notes[0];
    EXPECT_EQ(n.message, "this '{' is never closed");
    EXPECT_EQ(unclosed.file->position(n.span.begin).line, 2u);
    EXPECT_EQ(unclosed.file->position(n.span.begin).col, 12u);

    auto paren = testing::plan_text("p.pipe", "pipeline p {\n  guidance {\n    sal = blur(saliency(preview), sigma 2\n  }\n}\n",
                                    std::nullopt);
    ASSERT_FALSE(paren.diagnostics.empty());
    ASSERT_EQ(paren.diagnostics[0].notes.size(), 1u);
    EXPECT_EQ(paren.diagnostics[0].notes[0].message, "this '(' is not closed before the '}'");
    EXPECT_EQ(paren.file->position(paren.diagnostics[0].notes[0].span.begin).col, 15u);

    auto str = testing::plan_text("p.pipe", "pipeline p {\n  preselective { crex \"TT  spp 1 }\n}\n", std::nullopt);
    ASSERT_FALSE(str.diagnostics.empty());
    EXPECT_EQ(str.diagnostics[0].code, "E201");
    EXPECT_NE(str.diagnostics[0].message.find("unterminated string"), std::string::npos) << str.diagnostics[0].message;
    EXPECT_EQ(str.file->position(str.diagnostics[0].span.begin).col, 23u);

    // A file that ends before its '}' is reported at the end, with a span inside the text (it
    // was one past the end: the pipeline fuzzer's first finding).
    const std::string cut = "pipeline p {\n  guidance { sal = saliency(preview) }\n";
    auto eof = testing::plan_text("p.pipe", cut, std::nullopt);
    ASSERT_FALSE(eof.diagnostics.empty());
    for (const auto& d : eof.diagnostics) {
        EXPECT_LE(d.span.end, cut.size());
        EXPECT_LE(d.span.begin, d.span.end);
    }

    // Balanced brackets: no note on an ordinary syntax error.
    auto plain = testing::plan_text("p.pipe", "pipeline p {\n  guidance { sal = = saliency(preview) }\n}\n", std::nullopt);
    ASSERT_FALSE(plain.diagnostics.empty());
    EXPECT_TRUE(plain.diagnostics[0].notes.empty());
}

// The plan's one diagnostic, checked to be warning `code` at line:col (the plan exists).
const Diagnostic& only_warning(const testing::PlannedPipeline& r, const std::string& code, size_t line, size_t col) {
    static const Diagnostic none{};
    EXPECT_TRUE(r.plan);
    EXPECT_EQ(r.diagnostics.size(), 1u);
    if (r.diagnostics.size() != 1) return none;
    const Diagnostic& d = r.diagnostics[0];
    EXPECT_EQ(d.code, code);
    EXPECT_EQ(d.severity, Severity::kWarning);
    EXPECT_EQ(r.file->position(d.span.begin).line, line);
    EXPECT_EQ(r.file->position(d.span.begin).col, col);
    return d;
}

// noise() compares a pixel's even and odd samples: with one sample a pixel before guidance
// the map is 0 everywhere, which a run under a budget only said as a note. Said at the call.
TEST(PipelineAgainstScene, NoiseOfAOneSamplePreviewIsW206AtTheCall) {
    std::vector<std::string> tags;
    auto text = [](const std::string& preselective, const std::string& selective) {
        return "pipeline p {\n  preselective { " + preselective + " }\n  guidance { err = blur(noise(preview), sigma 1) }\n"
               "  selective { " + selective + "vary spp 1 .. 8 by err }\n}\n";
    };
    auto r = testing::plan_text("p.pipe", text("spp 1", ""), std::nullopt, "", "", &tags);
    const Diagnostic& d = only_warning(r, "W206", 3, 25);
    EXPECT_NE(d.help.find("spp 2"), std::string::npos) << d.help;
    // Two samples a pixel from the preview, or from the selective floor: nothing to say.
    for (auto [pre, sel] : {std::pair{"spp 2", ""}, std::pair{"spp 1", "spp 2  "}})
        EXPECT_TRUE(testing::plan_text("p.pipe", text(pre, sel), std::nullopt, "", "", &tags).diagnostics.empty()) << pre << sel;
}

// The issue's case: `{TTMRSGD}2` by an importance that is at most 0.5 never runs S, G, D
// (occurrence i needs i < ceil(0.5 * 7) = 4). Said at the `by` map, with the letters.
TEST(PipelineAgainstScene, BracesThatTheirMapCanNeverReachAreW205AtTheMap) {
    std::vector<std::string> tags = {"exit_sign"};
    auto text = [](const std::string& weights) {
        return "pipeline p {\n  preselective { crex \"TTD\" }\n  guidance {\n    sal  = saliency(preview)\n"
               "    task = task_map(tagged(\"exit_sign\"), fovea 2 deg)\n    imp  = importance(" + weights + ")\n  }\n"
               "  selective { crex \"{TTMRSGD}2\" by imp }\n}\n";
    };
    auto r = testing::plan_text("p.pipe", text("task 0.5, sal 0, op \"+\""), std::nullopt, "", "", &tags);
    const Diagnostic& d = only_warning(r, "W205", 8, 36);
    EXPECT_NE(d.message.find("at most 0.5"), std::string::npos) << d.message;
    EXPECT_NE(d.message.find("SGD never run"), std::string::npos) << d.message;
    // Weights that can reach 1, or "max" of two maps each able to reach 1: nothing to say.
    for (const char* ok : {"task 0.5, sal 0.5, op \"+\"", "task 1, sal 1, op \"max\""})
        EXPECT_TRUE(testing::plan_text("p.pipe", text(ok), std::nullopt, "", "", &tags).diagnostics.empty()) << ok;
    // A product of two maps each at most 0.9 is at most 0.81: ceil(0.81 * 7) = 6, so only D.
    auto prod = testing::plan_text("p.pipe", text("task 0.9, sal 0.9, op \"*\""), std::nullopt, "", "", &tags);
    ASSERT_EQ(prod.diagnostics.size(), 1u);
    EXPECT_NE(prod.diagnostics[0].message.find(": D never runs"), std::string::npos) << prod.diagnostics[0].message;
}

}  // namespace
}  // namespace crex

namespace crex {
namespace {

TEST(PipelineExtends, ALongChainInheritsItsRootsMapsAndChecksInLinearTime) {
    // 4,000 pipelines each extending the last took 25 s (every base resolved afresh); the
    // maps each pipeline has are now carried down the chain.
    std::string text = "pipeline p0 { guidance { m = saliency(preview) } }\n";
    for (int i = 1; i < 4000; ++i) text += "pipeline p" + std::to_string(i) + " extends p" + std::to_string(i - 1) + " { }\n";
    text += "pipeline last extends p3999 { selective { vary spp 1 .. 4 by m } }\n";
    Result r = check(text);
    EXPECT_EQ(r.errors, 0u) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    // Using a map no pipeline of the chain defines is still E205.
    Result bad = check(text + "pipeline other extends p3999 { selective { vary spp 1 .. 4 by nosuch } }\n");
    EXPECT_NE(bad.find("E205"), nullptr);
}

TEST(SourcePositions, ColumnsCountCodePointsOnUtf8LinesAndBytesOnAsciiOnes) {
    SourceFile f("t", "abc\ncaf\xC3\xA9 x\n" + std::string(100000, 'D') + "Z\n");
    EXPECT_EQ(f.position(2).col, 3u);
    EXPECT_EQ(f.position(4 + 6).line, 2u);
    EXPECT_EQ(f.position(4 + 6).col, 6u);  // 'x' after the two-byte e-acute: code point 6
    EXPECT_EQ(f.position(4 + 8 + 100000).col, 100001u);
}

}  // namespace
}  // namespace crex
