/// \file settings_table.h
/// Every pipeline setting with the shape of its value and its allowed range, in one table: the
/// pipeline checker, the plan reader and (later) the CLI check against the same numbers, so a
/// value one of them accepts is never refused or misread by another. The ranges match
/// `crex run`'s flags (apps/crex/cmd_run.cpp) and keep the work of one render bounded.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace crex::pipeline {

enum class SettingShape {
    kString,   ///< "text"
    kImages,   ///< "a.exr" "a.png" ...: one or more image paths, each with a format crex writes
    kBool,     ///< true | false
    kInteger,  ///< a whole number in [lo, hi]
    kNumber,   ///< a number in [lo, hi]
    kSize,     ///< W x H, each a whole number in [lo, hi]
    kBudget,   ///< N s | N ms (seconds in (0, hi]) or N % (in (0, 100])
    kPolicy,   ///< one of scheduling_policy_names()
    kCrex,     ///< a crex in double quotes [by MAP]
};

struct SettingRule {
    std::string_view section;  ///< "" for the top of a pipeline
    std::string_view name;
    SettingShape shape;
    double lo = 0, hi = 0;     ///< kInteger, kNumber, kSize; kBudget: hi in seconds
};

/// The whole table, section by section.
std::span<const SettingRule> setting_rules();
/// The rule of `name` in `section`; nullptr when there is no such setting.
const SettingRule* find_setting_rule(std::string_view section, std::string_view name);
/// The section names ("" first).
std::span<const std::string_view> setting_sections();

/// Empty when `v` fits `rule` (kInteger, kNumber, kSize: one side), else what is wrong with
/// the range, e.g. "0 is out of range: expected a whole number from 1 to 1048576"; NaN and
/// infinities are named (base/number_range.h, the check of every number a user gives).
std::string setting_range_error(const SettingRule& rule, double v);
/// The same for a literal as written in a pipeline file: a whole number written in digits is
/// compared exactly (`seed 9007199254740993` became 2^53 silently, which the CLI refuses).
std::string setting_literal_error(const SettingRule& rule, double v, std::string_view literal);
/// The same for a budget in seconds (`percent` false) or a share of a full render in % (true).
std::string budget_range_error(double v, bool percent);

/// Scheduling policies (spec/pipeline.md §7): whole tasks (thesis 5.4) or per-variable queues (8.3).
/// How a time budget is spent (spec/pipeline.md §7, issue 15). Every policy admits camera
/// samples pass by pass and band by band on the measured cost; they differ inside a pass:
///  tasks       whole components and [ ] groups, admitted on the profile (thesis 5.4);
///  batches     a task that does not fit runs its rays in batches ordered by pixel importance
///              while they fit (thesis 5.5, cbtcr);
///  queues      one queue per component, most important pixels first; the next batch from the
///              queue with the most luminance per second (thesis 8.3, prog_tc);
///  progressive admitted passes run their crex whole (a plain crex run's default).
enum class SchedulingPolicy { kTasks, kQueues, kBatches, kProgressive };
std::span<const std::string_view> scheduling_policy_names();
std::optional<SchedulingPolicy> scheduling_policy_from_name(std::string_view name);
std::string_view name_of(SchedulingPolicy p);

}  // namespace crex::pipeline
