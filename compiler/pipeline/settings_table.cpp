#include "compiler/pipeline/settings_table.h"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "base/number_range.h"

namespace crex::pipeline {
namespace {

using S = SettingShape;

// 2^53: the largest whole number a JSON plan (a double) holds exactly.
constexpr double kMaxExactInteger = 9007199254740992.0;
// Budgets up to 10^6 s (11.6 days): longer is a typo, and keeps clock arithmetic exact.
constexpr double kMaxBudgetSeconds = 1e6;

constexpr std::array kRules = {
    SettingRule{"", "scene", S::kString},
    SettingRule{"", "image", S::kSize, 1, 16384},
    SettingRule{"", "seed", S::kInteger, 0, kMaxExactInteger},
    SettingRule{"", "budget", S::kBudget, 0, kMaxBudgetSeconds},
    SettingRule{"", "policy", S::kPolicy},
    SettingRule{"", "lw", S::kNumber, 0, 1},                 // crex run --lw
    SettingRule{"", "max_depth", S::kInteger, 0, 65535},     // --max-depth
    SettingRule{"", "ab", S::kInteger, 1, 64},               // --ab
    SettingRule{"", "ad", S::kInteger, 1, 65536},            // --ad
    SettingRule{"", "av", S::kNumber, 0, 1e30},              // --ambient
    SettingRule{"", "aa", S::kNumber, 1e-3, 1},              // --aa
    SettingRule{"", "reference", S::kString},
    SettingRule{"preselective", "crex", S::kCrex},
    SettingRule{"preselective", "spp", S::kInteger, 1, 1 << 20},  // --spp
    SettingRule{"preselective", "shadow_rays", S::kInteger, 1, 1024},  // --shadow-rays
    SettingRule{"selective", "crex", S::kCrex},
    SettingRule{"selective", "spp", S::kInteger, 1, 1 << 20},
    SettingRule{"selective", "rounds", S::kInteger, 1, 64},  // the cyclic process; --rounds
    SettingRule{"output", "image", S::kImages},  // as repeated -o: "out/x.exr" "out/x.png"
    SettingRule{"output", "components", S::kBool},
    SettingRule{"output", "maps", S::kBool},
    SettingRule{"output", "report", S::kString},
};

constexpr std::array<std::string_view, 5> kSections = {"", "preselective", "guidance", "selective", "output"};
// In SchedulingPolicy order.
constexpr std::array<std::string_view, 4> kPolicies = {"tasks", "queues", "batches", "progressive"};

}  // namespace

std::span<const SettingRule> setting_rules() { return kRules; }
std::span<const std::string_view> setting_sections() { return kSections; }

const SettingRule* find_setting_rule(std::string_view section, std::string_view name) {
    for (const auto& r : kRules)
        if (r.section == section && r.name == name) return &r;
    return nullptr;
}

namespace {
NumberRange range_of(const SettingRule& rule) { return {rule.lo, rule.hi, rule.shape == S::kInteger || rule.shape == S::kSize}; }
}  // namespace

std::string setting_range_error(const SettingRule& rule, double v) { return number_range_error(v, range_of(rule)); }

std::string setting_literal_error(const SettingRule& rule, double v, std::string_view literal) {
    if (std::string e = setting_range_error(rule, v); !e.empty()) return e;
    const NumberRange range = range_of(rule);
    const bool digits = !literal.empty() && literal.find_first_not_of("0123456789") == std::string_view::npos;
    return range.whole && digits ? number_text_error(literal, range) : "";
}

std::string budget_range_error(double v, bool percent) {
    double hi = percent ? 100 : kMaxBudgetSeconds;
    if (std::isfinite(v) && v > 0 && v <= hi) return "";
    return percent ? "a share in (0, 100] %" : fmt::format("a time in (0, {:g}] s", kMaxBudgetSeconds);
}

std::span<const std::string_view> scheduling_policy_names() { return kPolicies; }

std::optional<SchedulingPolicy> scheduling_policy_from_name(std::string_view name) {
    for (size_t i = 0; i < kPolicies.size(); ++i)
        if (kPolicies[i] == name) return static_cast<SchedulingPolicy>(i);
    return std::nullopt;
}

std::string_view name_of(SchedulingPolicy p) { return kPolicies[static_cast<size_t>(p)]; }

}  // namespace crex::pipeline
