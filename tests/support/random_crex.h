/// \file random_crex.h
/// Random well-formed crex trees of every construct, for property tests and the benchmark.
/// "Well-formed" means no errors (warnings allowed): no '*' inside `{ }` or `[ ]`, no `{ }`
/// or `[ ]` inside `{ }`, no integer directly after an integer, counts in 1 .. 2^31-1.
#pragma once

#include <random>
#include <string>

#include "compiler/crex/ast.h"

namespace crex::testing {

class RandomCrex {
public:
    explicit RandomCrex(uint64_t seed) : rng_(seed) {}

    ast::Sequence sequence(int depth = 0, bool in_modulate = false, bool in_budget = false) {
        ast::Sequence seq;
        int n = uniform(0, depth == 0 ? 6 : 4);
        for (int i = 0; i < n; ++i) seq.push_back(item(depth, in_modulate, in_budget));
        return seq;
    }

    /// Canonical text with random whitespace between tokens (never inside an integer, and
    /// never gluing two integers together).
    std::string spaced_text(const ast::Sequence& seq) {
        std::string out;
        for (const auto& it : seq) {
            space(out);
            if (it.kind == ast::ItemKind::kComponent) {
                out += component_letter(it.component);
            } else {
                out += ast::group_open_char(it.group);
                out += spaced_text(it.body);
                space(out);
                out += ast::group_close_char(it.group);
            }
            for (const auto& r : it.repeats) {
                space(out);
                out += r.star ? std::string("*") : std::to_string(r.count);
            }
        }
        return out;
    }

private:
    int uniform(int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng_); }

    void space(std::string& out) {
        static const char* kSpaces[] = {"", "", "", " ", "\t", "  "};
        out += kSpaces[uniform(0, 5)];
    }

    ast::Item item(int depth, bool in_modulate, bool in_budget) {
        ast::Item it;
        bool group = depth < 5 && uniform(0, 2) == 0;
        if (!group) {
            it.kind = ast::ItemKind::kComponent;
            it.component = kComponentTable[static_cast<size_t>(uniform(0, 5))].component;
        } else {
            it.kind = ast::ItemKind::kGroup;
            for (;;) {
                it.group = static_cast<ast::GroupKind>(uniform(0, 3));
                if (in_modulate && (it.group == ast::GroupKind::kModulate || it.group == ast::GroupKind::kBudget))
                    continue;
                break;
            }
            it.body = sequence(depth + 1, in_modulate || it.group == ast::GroupKind::kModulate,
                               in_budget || it.group == ast::GroupKind::kBudget);
        }
        int repeats = uniform(0, 5) < 3 ? 0 : uniform(1, 2);
        bool last_integer = false;
        for (int r = 0; r < repeats; ++r) {
            ast::Repeat rep;
            bool star_allowed = !in_modulate && !in_budget;
            rep.star = star_allowed && (last_integer || uniform(0, 1) == 0);
            if (!rep.star && last_integer) break;
            if (!rep.star) {
                int kind = uniform(0, 9);
                rep.count = kind == 0 ? 2147483647u : kind == 1 ? 1u : static_cast<uint64_t>(uniform(2, 9));
            }
            last_integer = !rep.star;
            it.repeats.push_back(rep);
        }
        return it;
    }

    std::mt19937_64 rng_;
};

}  // namespace crex::testing
