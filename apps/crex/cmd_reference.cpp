// `crex reference`: a converged gold image of a scene, cached by what determines it.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "apps/crex/commands.h"
#include "apps/crex/exit_codes.h"
#include "apps/crex/progress.h"
#include "apps/crex/run_setup.h"
#include "apps/crex/scene_input.h"
#include "base/render_text.h"
#include "compiler/crex/compile.h"
#include "runtime/io/image_io.h"
#include "apps/crex/cli_values.h"
#include "runtime/base/atomic_file.h"
#include "runtime/driver/run_plan.h"
#include "runtime/report/reference_cache.h"

namespace crex::app {
namespace {

struct ReferenceOptions {
    std::string scene = "builtin:cornell";
    std::string size = "128x128";
    uint32_t spp = 1024;
    uint64_t seed = 0;
    std::string output;
    bool force = false;
    bool quiet = false;
};

int reference(const ReferenceOptions& opt) {
    ReferenceSettings s;
    if (!parse_image_size(opt.size, s.width, s.height)) {  // sscanf took trailing junk
        std::cerr << fmt::format("crex reference: error: image size '{}': expected WIDTHxHEIGHT, each 1 to 16384, e.g. 128x128\n", opt.size);
        return kExitUsage;
    }
    s.spp = opt.spp;
    s.seed = opt.seed;
    DiagnosticSink sink;
    auto in = load_scene_input(opt.scene, sink);
    std::cerr << render_text(sink.sorted());
    if (!in->failure.empty()) {
        std::cerr << "crex reference: error: " << in->failure << "\n";
        return kExitFailure;
    }
    if (!in->scene) return kExitInputErrors;
    // -o DIR said "no image writer for 'DIR'" after the whole render.
    if (!opt.output.empty())
        if (auto failure = check_output_path(opt.output)) {
            std::cerr << "crex reference: error: " << failure->message << "\n";
            return failure->exit_code;
        }
    std::string path = opt.output.empty() ? reference_path(*in->scene, s) : opt.output;
    // An existing file counts as this reference only when it is one: the key file written
    // beside it names the same scene content and settings, and it reads as an image of the
    // requested size (-o used to take any existing file, even /etc/hostname).
    const std::string key = reference_key(*in->scene, s), key_path = path + ".key";
    auto is_this_reference = [&] {
        if (!std::filesystem::exists(path)) return false;
        if (!opt.output.empty()) {
            std::ifstream k(key_path);
            std::string stored;
            if (!(k >> stored) || stored != key) return false;
        }
        int w = 0, h = 0;
        std::vector<float> rgb;
        return read_image(path, w, h, rgb).empty() && w == s.width && h == s.height;
    };
    if (!opt.force && is_this_reference()) {
        std::cout << path << "\n";
        if (!opt.quiet) std::cerr << "crex reference: cached (key " << reference_key(*in->scene, s) << "); --force renders again\n";
        return kExitOk;
    }
    RunSettings ro;
    ro.width = s.width, ro.height = s.height, ro.spp = s.spp, ro.seed = s.seed;
    ro.executor.shade.weight_limit = s.lw;
    ro.executor.shade.max_depth = s.max_depth;
    Progress progress(!opt.quiet);
    ro.progress = [&](const RunProgress& p) { progress.update(p); };
    SourceFile crex("<reference>", s.crex);
    auto program = compile_crex(crex, sink).program;
    std::optional<RunResult> r;
    try {
        r.emplace(render(*in->scene, *program, ro));
    } catch (const std::exception& e) {
        progress.finish();
        std::cerr << "crex reference: error: rendering failed: " << e.what() << "\n";
        return kExitFailure;
    }
    progress.finish();
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    ImageMetadata metadata = {{"Software", std::string("crex ") + CREX_VERSION}, {"crex:version", CREX_VERSION},
                              {"crex:scene", opt.scene},  {"crex:crex", s.crex},
                              {"crex:spp", std::to_string(s.spp)}, {"crex:seed", std::to_string(s.seed)},
                              {"crex:render_seconds", fmt::format("{:.6g}", r->render_seconds)}, {"crex:reference", "true"}};
    std::string error = write_image(path, s.width, s.height, {{"", r->image()}}, metadata);
    if (error.empty() && !opt.output.empty()) error = write_file_atomically(key_path, key + "\n");
    if (!error.empty()) {
        std::cerr << "crex reference: error: " << error << "\n";
        return kExitFailure;
    }
    std::cout << path << "\n";
    if (!opt.quiet)
        std::cerr << fmt::format("crex reference: {} at {}x{}, {} spp with {} in {:.1f} s\n", opt.scene, s.width, s.height, s.spp, s.crex,
                                 r->render_seconds);
    return kExitOk;
}

}  // namespace

Runner add_reference_command(CLI::App& app) {
    auto opt = std::make_shared<ReferenceOptions>();
    CLI::App* cmd = app.add_subcommand("reference", "Render a converged gold reference of a scene, cached by scene and settings");
    cmd->add_option("scene", opt->scene, "Scene: file.json, file.rad, file.rif, file.obj or builtin:NAME")->capture_default_str();
    cmd->add_option("--size", opt->size, "Image size WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--spp", opt->spp, "Camera samples per pixel")->capture_default_str()->check(whole_number_in(1, 1 << 20));
    cmd->add_option("--seed", opt->seed, "Seed (0 to 2^53)")->capture_default_str()->check(seed_value());
    cmd->add_option("-o,--output", opt->output, "Write here instead of the cache");
    cmd->add_flag("--force", opt->force, "Render even if the cache has it");
    cmd->add_flag("-q,--quiet", opt->quiet, "No progress and no messages");
    cmd->footer(R"(
Renders the scene with (TTMRSGD)* and prints the image's path. The cache is
$CREX_CACHE/references, else $XDG_CACHE_HOME/crex/references, else ~/.cache/crex/references;
the key is a hash of the scene's full content (not its path) and the settings.
'crex run --reference auto' uses the cached reference of its scene at its image size with
the most samples (seed 0).

Examples:
  crex reference                                       builtin:cornell, 128x128, 1024 spp
  crex reference examples/scenes/corridor/scene.json --size 128x96 --spp 4096
  crex run stdlib/pipelines/sel_rp.pipe --size 128x128 --reference auto --report out/report

Exit status: 0 ok, 1 errors in the scene, 2 usage, 3 I/O or runtime failure.)");
    return [opt] { return reference(*opt); };
}

}  // namespace crex::app
