// Lowering: the schedule IR says exactly what spec/crex.md §3 says the crex executes.
#include <gtest/gtest.h>

#include "compiler/sched/print.h"
#include "tests/support/compile_helpers.h"

namespace crex {
namespace {

using sched::Node;
using sched::Op;

sched::Program lower(const std::string& text) {
    auto r = testing::check(text);
    EXPECT_EQ(r.errors, 0u) << text;
    return r.compiled.program.value_or(sched::Program{});
}

// Collects the occurrence indices of every Exec under a Modulate, expanding repeats with
// their strides: the numbering of spec §3.
void occurrence_indices(const Node& n, double offset, std::vector<std::pair<char, double>>& out) {
    if (n.op == Op::kExec) out.push_back({component_letter(n.component), n.first_index + offset});
    if (n.op == Op::kRepeat && n.stride > 0) {
        for (uint64_t j = 0; j < n.count; ++j) occurrence_indices(n.children[0], offset + j * n.stride, out);
        return;
    }
    for (const auto& c : n.children) occurrence_indices(c, offset, out);
}

const Node& first_modulate(const Node& n) {
    if (n.op == Op::kModulate) return n;
    for (const auto& c : n.children) {
        const Node& m = first_modulate(c);
        if (m.op == Op::kModulate) return m;
    }
    return n;
}

TEST(CrexLower, ModulationCountsOccurrencesAfterExpandingRepeats) {
    struct Case {
        const char* crex;
        double n;
        std::string order;
    };
    for (const Case& c : {Case{"{T2}", 2, "TT"}, Case{"{(TR)2}", 4, "TRTR"}, Case{"{<RS>G}", 3, "RSG"},
                          Case{"{TTMRSGD}2", 7, "TTMRSGD"}, Case{"{D(TR2)3G}", 11, "DTRRTRRTRRG"}}) {
        sched::Program p = lower(c.crex);
        const Node& m = first_modulate(p.selective);
        ASSERT_EQ(m.op, Op::kModulate) << c.crex;
        EXPECT_EQ(m.occurrences, c.n) << c.crex;
        std::vector<std::pair<char, double>> occ;
        occurrence_indices(m, 0, occ);
        std::string order;
        for (size_t i = 0; i < occ.size(); ++i) {
            order += occ[i].first;
            EXPECT_EQ(occ[i].second, static_cast<double>(i)) << c.crex << " occurrence " << i;
        }
        EXPECT_EQ(order, c.order) << c.crex;
    }
}

TEST(CrexLower, RepeatOfTheBracesKeepsTheNumbering) {
    sched::Program p = lower("{TTMRSGD}2");
    ASSERT_EQ(p.selective.children.size(), 1u);
    const Node& rep = p.selective.children[0];
    EXPECT_EQ(rep.op, Op::kRepeat);
    EXPECT_EQ(rep.count, 2u);
    EXPECT_EQ(rep.stride, 0);  // outside the braces: the same numbering each time
}

TEST(CrexLower, PreselectiveIsTheLeadingItemsWithoutBraces) {
    EXPECT_EQ(sched::to_crex(lower("TT{TTMRSGD}2").preselective), "TT");
    EXPECT_EQ(sched::to_crex(lower("TT{TTMRSGD}2").selective), "{TTMRSGD}2");
    EXPECT_EQ(sched::to_crex(lower("[T{RS}]2").preselective), "");
    EXPECT_EQ(sched::to_crex(lower("(TT[RS]G)*D").selective), "");  // no braces: no selective stage
    EXPECT_EQ(sched::to_crex(lower("(TT[RS]G)*D").preselective), "(TT[RS]G)*D");
    // A group holding braces is selective as a whole, even where it starts with plain steps.
    EXPECT_EQ(sched::to_crex(lower("D(T{R})").preselective), "D");
    EXPECT_EQ(sched::to_crex(lower("D(T{R})")), "D(T{R})");
}

TEST(CrexLower, DeferralBelongsToTheOutermostGroup) {
    EXPECT_TRUE(sched::same_structure(lower("<(DG)S>"), lower("<DGS>")));
    EXPECT_TRUE(sched::same_structure(lower("<<DG>S>"), lower("<DGS>")));
    EXPECT_TRUE(sched::same_structure(lower("[[RS]G]"), lower("[RSG]")));
    sched::Program p = lower("<[RS]G>");
    const Node& budget = p.preselective.children[0].children[0];
    EXPECT_EQ(budget.op, Op::kBudgeted);
    EXPECT_FALSE(budget.owns_deferral);  // still a task under a budget, but `< >` defers
    EXPECT_TRUE(lower("[RS]").preselective.children[0].owns_deferral);
}

TEST(CrexLower, InheritGroupsDisappearAndRepeatsNest) {
    EXPECT_TRUE(sched::same_structure(lower("(DGS)G"), lower("DGSG")));
    sched::Program p = lower("D2*");
    const Node& star = p.preselective.children[0];
    EXPECT_EQ(star.op, Op::kRepeatUntilEmpty);
    EXPECT_EQ(star.cap, sched::kDefaultStarCap);
    EXPECT_EQ(star.children[0].op, Op::kRepeat);  // stacked repeats nest left to right
    EXPECT_EQ(sched::to_crex(lower("(D2)3")), "(D2)3");
    EXPECT_EQ(sched::to_crex(lower("D1")), "D");
}

TEST(CrexLower, ExecNodesKeepTheirSourceLocations) {
    auto r = testing::check("TT{RS}");
    const Node& s = r.compiled.program->selective.children[0].children[1];
    EXPECT_EQ(s.op, Op::kExec);
    EXPECT_EQ(s.where.file, "<expr>");
    EXPECT_EQ(s.where.line, 1u);
    EXPECT_EQ(s.where.col, 5u);
    EXPECT_EQ(s.where.end_col, 6u);
}

TEST(CrexLower, ExplainStatesTheImportanceThresholds) {
    std::string text = sched::explain(lower("TT{TTMRSGD}2"));
    EXPECT_NE(text.find("T: execute the transmitted rays waiting in bin T; needs I > 0\n"), std::string::npos)
        << text;
    EXPECT_NE(text.find("needs I > 1/7"), std::string::npos);
    EXPECT_NE(text.find("D: execute the indirect diffuse rays waiting in bin D; needs I > 6/7"), std::string::npos);
    EXPECT_NE(text.find("repeat 2 times"), std::string::npos);
}

}  // namespace
}  // namespace crex
