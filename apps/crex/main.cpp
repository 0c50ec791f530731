// crex: the selective-rendering pipeline compiler and runtime, one tool with subcommands.
#include <CLI/CLI.hpp>
#include <iostream>
#include <map>

#include "apps/crex/commands.h"
#include "apps/crex/exit_codes.h"

int main(int argc, char** argv) {
    using namespace crex::app;
    CLI::App app{"crex: compile and run selective-rendering pipelines", "crex"};
    app.set_version_flag("--version", std::string("crex 0.1.0"));
    app.require_subcommand(1);
    app.footer("Run 'crex <command> --help' for the options and examples of each command.");

    std::map<std::string, Runner> runners;
    runners["check"] = add_check_command(app);
    runners["scene-info"] = add_scene_info_command(app);
    runners["run"] = add_run_command(app);
    runners["plan"] = add_plan_command(app);
    runners["compare"] = add_compare_command(app);
    runners["reference"] = add_reference_command(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return kExitUsage;
    }
    try {
        for (auto* sub : app.get_subcommands()) return runners.at(sub->get_name())();
    } catch (const std::exception& e) {
        std::cerr << "crex: internal error: " << e.what() << "\n";
        return kExitFailure;
    }
    return kExitUsage;
}
