// crex: the selective-rendering pipeline compiler and runtime, one tool with subcommands.
#include <CLI/CLI.hpp>
#include <iostream>
#include <algorithm>
#include <cctype>
#include <csignal>
#include <fmt/format.h>
#include <sstream>
#include <map>
#include <string>
#include <vector>

#include "apps/crex/commands.h"
#include "base/check.h"
#include "base/exit_codes.h"
#include "base/nearest_name.h"
#include "runtime/distributed/distributed.h"

namespace {

std::string capitalised(std::string s) {
    if (!s.empty()) s[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])));
    return s;
}

// git's manner: name what was wrong, suggest the nearest right thing, say where help is.
int usage_error(const CLI::App& app, const CLI::ParseError& e, int argc, char** argv) {
    std::vector<std::string> commands;
    for (const auto* sub : app.get_subcommands({})) commands.push_back(sub->get_name());
    std::string first = argc > 1 ? argv[1] : "";
    if (!first.empty() && first[0] != '-' && std::find(commands.begin(), commands.end(), first) == commands.end()) {
        std::string hint = capitalised(crex::did_you_mean(first, commands));
        std::cerr << "crex: '" << first << "' is not a crex command." << (hint.empty() ? "" : " " + hint) << " See 'crex --help'.\n";
        return crex::kExitUsage;
    }
    const CLI::App* sub = nullptr;
    for (const auto* s : app.get_subcommands({}))
        if (s->get_name() == first) sub = s;
    std::string prefix = sub ? "crex " + sub->get_name() : "crex";
    std::string what = e.what();
    // An unknown flag: the nearest one the command has.
    const std::string unexpected = "The following argument was not expected: ";
    if (sub && what.rfind(unexpected, 0) == 0) {
        std::string arg = what.substr(unexpected.size());
        std::string flag = arg.substr(0, arg.find('='));
        std::vector<std::string> flags;
        for (const auto* o : sub->get_options())
            for (const auto& n : o->get_lnames()) flags.push_back("--" + n);
        std::string hint = flag.rfind("--", 0) == 0 ? capitalised(crex::did_you_mean(flag, flags)) : "";
        std::cerr << prefix << ": error: unknown option '" << arg << "'." << (hint.empty() ? "" : " " + hint) << " See '" << prefix
                  << " --help'.\n";
        return crex::kExitUsage;
    }
    std::cerr << prefix << ": error: " << what << ". See '" << prefix << " --help'.\n"
              << (sub && dynamic_cast<const CLI::RequiredError*>(&e) ? CLI::Formatter().make_usage(sub, prefix) : "");  // how it is called
    return crex::kExitUsage;
}

// The commands and what each does (not app.help(): within `crex help` it would show help's own).
std::string overview(const CLI::App& app) { return app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal); }

// `crex help COMMAND`: that command's --help; `crex help`: the overview; an unknown name is a
// usage error with the nearest command.
int help_command(const CLI::App& app, const std::string& topic) {
    if (topic.empty()) {
        std::cout << overview(app);
        return crex::kExitOk;
    }
    std::vector<std::string> commands;
    for (const auto* sub : app.get_subcommands({})) {
        if (sub->get_name() == topic) {
            std::cout << sub->help(app.get_name());
            return crex::kExitOk;
        }
        commands.push_back(sub->get_name());
    }
    std::string hint = capitalised(crex::did_you_mean(topic, commands));
    std::cerr << "crex help: error: '" << topic << "' is not a crex command." << (hint.empty() ? "" : " " + hint)
              << " See 'crex --help'.\n";
    return crex::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace crex;
    using namespace crex::app;
    // A file-size limit (ulimit -f) is a write failure like a full disk: write() fails with
    // EFBIG, the writer says so and removes its staged file, crex exits 3. By default SIGXFSZ
    // killed the process (exit 153) and left the staged file behind.
    std::signal(SIGXFSZ, SIG_IGN);
    DistributedSession mpi(argc, argv);  // under mpirun: MPI for the run's ranks; first, before any thread
    CLI::App app{"crex: compile and run selective-rendering pipelines", "crex"};
    app.set_version_flag("--version", std::string("crex ") + CREX_VERSION);
    app.require_subcommand(1);
    app.footer("Run 'crex help <command>' (or 'crex <command> --help') for the options and examples of each command.");

    std::map<std::string, Runner> runners;
    runners["check"] = add_check_command(app);
    runners["scene-info"] = add_scene_info_command(app);
    runners["run"] = add_run_command(app);
    runners["plan"] = add_plan_command(app);
    runners["compare"] = add_compare_command(app);
    runners["reference"] = add_reference_command(app);
    // `crex help [COMMAND]`, as git has it: the same text as `crex COMMAND --help`.
    std::string help_topic;
    CLI::App* help = app.add_subcommand("help", "Show the help of a command: crex help run (the same as crex run --help)");
    help->add_option("command", help_topic, "The command whose help to show (none: this overview)");
    runners["help"] = [&app, &help_topic] { return help_command(app, help_topic); };

    // Under mpirun every rank parses the same command line: rank 0 alone says what is wrong
    // (or prints the help), and every rank exits with the same code.
    const bool speaks = mpi.leads();
    std::ostringstream silent;
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {  // --help, --help-all, --version
        return speaks ? app.exit(e) : app.exit(e, silent, silent);
    } catch (const CLI::ParseError& e) {
        if (speaks && argc == 1) std::cerr << overview(app) << "\ncrex: error: a command is required\n";  // `crex` alone, as `git` alone
        return speaks && argc > 1 ? usage_error(app, e, argc, argv) : kExitUsage;
    }
    try {
        for (auto* sub : app.get_subcommands()) return runners.at(sub->get_name())();
    } catch (const crex::InternalError& e) {
        std::cerr << "crex: " << e.what() << "\n";
        return kExitFailure;
    } catch (const std::bad_alloc&) {  // inputs are bounded (base/input_file.h); this is a memory limit
        std::cerr << "crex: error: out of memory (a memory limit such as ulimit -v, or an image or scene too large for this machine)\n";
        return kExitFailure;
    } catch (const std::exception& e) {
        std::cerr << "crex: internal error: " << e.what() << "\n";
        return kExitFailure;
    }
    return kExitUsage;
}
