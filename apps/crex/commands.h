/// \file commands.h
/// Each subcommand registers itself on the CLI11 app and returns a runner that is called only
/// if it was selected. Runners return an ExitCode.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace crex::app {

using Runner = std::function<int()>;

Runner add_check_command(CLI::App& app);
Runner add_scene_info_command(CLI::App& app);
Runner add_run_command(CLI::App& app);
Runner add_plan_command(CLI::App& app);
Runner add_compare_command(CLI::App& app);
Runner add_reference_command(CLI::App& app);

}  // namespace crex::app
