// `crex reference`: a converged gold image of a scene, cached by what determines it; or the
// windows of a frame only, and more samples for a reference made before (issue 32).
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "apps/crex/commands.h"
#include "runtime/api/console_progress.h"
#include "runtime/api/interrupt.h"
#include "base/exit_codes.h"
#include "base/render_text.h"
#include "compiler/crex/compile.h"
#include "runtime/io/image_io.h"
#include "apps/crex/cli_values.h"
#include "apps/crex/guarded_rendering.h"
#include "runtime/api/run_inputs.h"
#include "runtime/api/run_outputs.h"
#include "runtime/base/atomic_file.h"
#include "runtime/driver/run_plan.h"
#include "runtime/reference/reference_render.h"
#include "runtime/reference/reference_windows.h"
#include "runtime/reference/windowed_image.h"
#include "runtime/distributed/partial_rows.h"
#include "runtime/report/reference_cache.h"

namespace crex::app {
namespace {

struct ReferenceOptions {
    std::string scene = "builtin:cornell";
    bool scene_given = false;
    std::string size = "128x128";
    uint32_t spp = 1024;
    uint64_t seed = 0;
    std::string output;
    bool force = false;
    bool quiet = false;
    std::string progress = "auto";
    std::vector<std::string> windows;  ///< --window X,Y,W,H, repeatable
    std::string windows_rule;          ///< --windows auto
    int window_size = 64;
    uint32_t context_spp = 16;
    std::string accumulate;            ///< --accumulate FILE
    bool size_given = false, seed_given = false;
};

const ImageMetadata kSoftware = {{"Software", std::string("crex ") + CREX_VERSION}, {"crex:version", CREX_VERSION}};

// What the run was, as a command anyone can type again (windows as given: `--windows auto`
// chooses the same ones again for the same scene and size).
std::string command_line(const ReferenceOptions& opt, const std::string& scene, const std::string& output) {
    std::string c = "crex reference " + scene;
    if (!opt.accumulate.empty()) c += " --accumulate " + opt.accumulate;
    else c += fmt::format(" --size {} --seed {}", opt.size, opt.seed);
    c += fmt::format(" --spp {}", opt.spp);
    for (const auto& w : opt.windows) c += " --window " + w;
    if (!opt.windows_rule.empty()) c += fmt::format(" --windows {} --window-size {}", opt.windows_rule, opt.window_size);
    if (opt.accumulate.empty() && (!opt.windows.empty() || !opt.windows_rule.empty())) c += fmt::format(" --context-spp {}", opt.context_spp);
    if (!output.empty() && output != opt.accumulate) c += " -o " + output;
    return c;
}

struct LoadedScene {
    std::unique_ptr<SceneInput> input;
    int exit = kExitOk;
};

LoadedScene load_scene(const std::string& scene) {
    DiagnosticSink sink;
    LoadedScene out;
    out.input = load_scene_input(scene, sink);
    std::cerr << render_text(sink.sorted());
    if (!out.input->failure.empty()) {
        std::cerr << "crex reference: error: " << out.input->failure << "\n";
        out.exit = kExitFailure;
    } else if (!out.input->scene) {
        out.exit = kExitInputErrors;
    }
    return out;
}

// The reference's crex compiled (nullopt if it does not compile: a header's, edited).
std::optional<sched::Program> reference_program(const std::string& crex_text) {
    DiagnosticSink sink;
    SourceFile crex("<reference>", crex_text);
    return compile_crex(crex, sink).program;
}

int write_and_say(const std::string& path, const ReferenceImage& image, const ReferenceOptions& opt, const std::string& what) {
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    if (std::string error = write_reference_image(path, image, kSoftware); !error.empty()) {
        std::cerr << "crex reference: error: " << error << "\n";
        return kExitFailure;
    }
    std::cout << path << "\n";
    if (!opt.quiet) std::cerr << "crex reference: " << what << "\n";
    return kExitOk;
}

// Ctrl-C or SIGTERM (catch_interrupt in reference()): the render stops after the pass in flight.
bool stop_asked() { return interrupted(); }

// A stop before every pixel had the same samples leaves no reference: nothing is written.
int nothing_written(double seconds, const std::string& what) {
    std::cerr << fmt::format("crex reference: interrupted after {:.1f} s, before every pixel had the same samples: {}\n", seconds, what);
    return interrupted_exit_code();
}

// A new reference whose render was stopped: what every pixel got goes to NAME.partial.EXT
// (the file asked for, or the cache's, is not a reference of the samples asked), with that
// count in its header, so that --accumulate can go on from it.
int write_stopped_reference(const std::string& path, const ReferenceImage& image, const ReferenceOptions& opt) {
    const ReferenceHeader& h = image.header;
    if (h.spp == 0) return nothing_written(h.render_seconds, "nothing written");
    const std::string partial = distributed::partial_path(path);
    const int status = write_and_say(partial, image, opt,
                                     fmt::format("interrupted after {:.1f} s: {} of the {} samples a pixel asked for; "
                                                 "'crex reference --accumulate {} --spp N' adds more",
                                                 h.render_seconds, h.spp, opt.spp, partial));
    return status == kExitOk ? interrupted_exit_code() : status;
}

// --accumulate FILE: more samples for a reference crex wrote, continuing its sample indices.
int accumulate(const ReferenceOptions& opt) {
    if (opt.size_given || opt.seed_given || !opt.windows.empty() || !opt.windows_rule.empty()) {
        std::cerr << "crex reference: error: --accumulate takes the size, the windows and the seed from the reference it adds to; "
                     "give only the scene (optional), --spp and -o\n";
        return kExitUsage;
    }
    std::optional<ReferenceImage> ref;
    if (std::string error = read_reference_image(opt.accumulate, ref); !error.empty()) {
        std::cerr << "crex reference: error: " << error << "\n";
        return kExitFailure;
    }
    if (!ref) {
        std::cerr << fmt::format("crex reference: error: {} has no reference header (crex:windows, crex:spp, crex:scene_hash): it was not "
                                 "written by this crex's `crex reference`, so what it holds cannot be added to\n", opt.accumulate);
        return kExitInputErrors;
    }
    ReferenceHeader& h = ref->header;
    const std::string scene_name = opt.scene_given ? opt.scene : h.scene;
    LoadedScene loaded = load_scene(scene_name);
    if (loaded.exit != kExitOk) return loaded.exit;
    const Scene& scene = *loaded.input->scene;
    if (const std::string hash = scene_content_hash(scene); hash != h.scene_hash) {
        std::cerr << fmt::format("crex reference: error: {} was rendered from a scene with hash {}, but {} now hashes to {}: the scene has "
                                 "changed, so new samples would not add up with the old; render the reference again\n",
                                 opt.accumulate, h.scene_hash.empty() ? "(none recorded)" : h.scene_hash, scene_name, hash);
        return kExitInputErrors;
    }
    if (uint64_t{h.spp} + opt.spp > UINT32_MAX) {
        std::cerr << "crex reference: error: more than 2^32 - 1 samples a pixel in all\n";
        return kExitUsage;
    }
    ReferencePixels s = more_samples_of(h, opt.spp);
    const std::optional<sched::Program> program = reference_program(h.crex.empty() ? ReferenceSettings{}.crex : h.crex);
    if (!program) {
        std::cerr << fmt::format("crex reference: error: {}'s header names the crex '{}', which does not compile\n", opt.accumulate, h.crex);
        return kExitInputErrors;
    }
    ConsoleProgress progress(progress_mode(opt.progress, opt.quiet));
    s.progress = [&](const RunProgress& p) { progress.update(p); };
    s.stop = stop_asked;
    RenderedPixels more;
    if (int status = guarded_rendering("crex reference", progress, [&] { more = render_reference_pixels(scene, *program, s); }); status != kExitOk) return status;
    if (more.spp == 0) return nothing_written(more.seconds, opt.accumulate + " is as it was");  // stopped: else fewer samples, as many in every pixel
    add_samples(*ref, more);
    const std::string path = opt.output.empty() ? opt.accumulate : opt.output;
    h.commands += (h.commands.empty() ? "" : "\n") + command_line(opt, scene_name, path);
    const int status = write_and_say(path, *ref, opt,
                                     fmt::format("{}{} samples added to {} in {:.1f} s: {} spp in all ({}); its own RMSE is about {:.3g} "
                                                 "(from how far the new samples' mean is from the old)",
                                                 more.stopped ? "interrupted: " : "", more.stopped ? fmt::format("{} of the {}", more.spp, opt.spp)
                                                                                                   : std::to_string(more.spp),
                                                 opt.accumulate, more.seconds, h.spp, h.runs, h.own_rmse));
    return status == kExitOk && more.stopped ? interrupted_exit_code() : status;
}

// --window / --windows auto: those pixels of the frame only, and a cheap look at all of it.
int windowed(const ReferenceOptions& opt, int width, int height) {
    if (opt.output.empty()) {
        std::cerr << "crex reference: error: a windowed reference is not cached: give -o FILE.exr\n";
        return kExitUsage;
    }
    std::vector<PixelWindow> windows;
    for (const auto& text : opt.windows) {
        auto w = parse_window(text);
        if (!w) {
            std::cerr << fmt::format("crex reference: error: --window '{}': expected X,Y,W,H (whole numbers, W and H at least 1), e.g. 96,64,64,64\n", text);
            return kExitUsage;
        }
        windows.push_back(*w);
    }
    if (!opt.windows_rule.empty() && opt.window_size > std::min(width, height)) {
        std::cerr << fmt::format("crex reference: error: --window-size {} does not fit in the {}x{} frame\n", opt.window_size, width, height);
        return kExitUsage;
    }
    if (!opt.windows_rule.empty() && opt.context_spp == 0) {
        std::cerr << "crex reference: error: --windows auto reads the whole frame's context: --context-spp must be at least 1\n";
        return kExitUsage;
    }
    if (!windows.empty())
        if (std::string why = check_windows(windows, width, height); !why.empty()) {
            std::cerr << "crex reference: error: " << why << "\n";
            return kExitUsage;
        }
    LoadedScene loaded = load_scene(opt.scene);
    if (loaded.exit != kExitOk) return loaded.exit;
    const Scene& scene = *loaded.input->scene;
    const ReferenceSettings defaults;
    const std::optional<sched::Program> program = reference_program(defaults.crex);
    ConsoleProgress progress(progress_mode(opt.progress, opt.quiet));
    ReferencePixels s;
    s.width = width, s.height = height, s.spp = opt.spp, s.seed = opt.seed;
    s.progress = [&](const RunProgress& p) { progress.update(p); };
    s.stop = stop_asked;
    FrameContext context;
    RenderedPixels pixels;
    const int status = guarded_rendering("crex reference", progress, [&] {
        if (opt.context_spp > 0) context = render_frame_context(scene, *program, width, height, opt.context_spp, opt.seed, s.progress);
        if (!opt.windows_rule.empty()) {
            progress.finish();
            for (const ChosenWindow& c : choose_reference_windows(scene, context, opt.window_size, opt.seed)) {
                if (c.window.width) windows.push_back(c.window);
                if (!opt.quiet)
                    std::cerr << fmt::format("  {:<10} {:<18} {}\n", c.kind,
                                             c.window.width ? fmt::format("{},{},{},{}", c.window.x, c.window.y, c.window.width, c.window.height) : "-",
                                             c.why);
            }
            if (std::string why = check_windows(windows, width, height); !why.empty()) throw std::runtime_error(why);
        }
        s.windows = windows;
        pixels = render_reference_pixels(scene, *program, s);
    });
    if (status != kExitOk) return status;
    const bool stopped = pixels.stopped;
    ReferenceImage image = reference_image_of(s, std::move(pixels), opt.scene, scene_content_hash(scene), defaults.crex, &context);
    image.header.commands = command_line(opt, opt.scene, opt.output);
    if (stopped) return write_stopped_reference(opt.output, image, opt);
    return write_and_say(opt.output, image, opt,
                         fmt::format("{} window{} of {} at {}x{}, {} spp in {:.1f} s (the frame's context: {:.1f} s)", windows.size(),
                                     windows.size() == 1 ? "" : "s", opt.scene, width, height, opt.spp, image.header.render_seconds, context.seconds));
}

int reference(const ReferenceOptions& opt) {
    catch_interrupt();  // a converged reference takes hours: Ctrl-C keeps what every pixel has
    if (!opt.accumulate.empty()) return accumulate(opt);
    ReferenceSettings s;
    if (!parse_image_size(opt.size, s.width, s.height)) {  // sscanf took trailing junk
        std::cerr << fmt::format("crex reference: error: image size '{}': expected WIDTHxHEIGHT, each 1 to 16384, e.g. 128x128\n", opt.size);
        return kExitUsage;
    }
    // -o DIR said "no image writer for 'DIR'" after the whole render.
    if (!opt.output.empty())
        if (std::string failure = check_output_path(opt.output); !failure.empty()) {
            std::cerr << "crex reference: error: " << failure << "\n";
            return kExitFailure;
        }
    if (!opt.windows.empty() || !opt.windows_rule.empty()) return windowed(opt, s.width, s.height);
    s.spp = opt.spp;
    s.seed = opt.seed;
    LoadedScene loaded = load_scene(opt.scene);
    if (loaded.exit != kExitOk) return loaded.exit;
    const Scene& scene = *loaded.input->scene;
    std::string path = opt.output.empty() ? reference_path(scene, s) : opt.output;
    const std::string key = reference_key(scene, s), key_path = path + ".key";
    if (!opt.force && holds_reference(path, scene, s, !opt.output.empty())) {
        std::cout << path << "\n";
        if (!opt.quiet) std::cerr << "crex reference: cached (key " << key << "); --force renders again\n";
        return kExitOk;
    }
    ConsoleProgress progress(progress_mode(opt.progress, opt.quiet));
    ReferencePixels rp;
    rp.width = s.width, rp.height = s.height, rp.spp = s.spp, rp.seed = s.seed, rp.lw = s.lw, rp.max_depth = s.max_depth;
    rp.progress = [&](const RunProgress& p) { progress.update(p); };
    rp.stop = stop_asked;
    RenderedPixels pixels;
    if (int status = guarded_rendering("crex reference", progress, [&] { pixels = render_reference_pixels(scene, *reference_program(s.crex), rp); });  // it compiles
        status != kExitOk)
        return status;
    const bool stopped = pixels.stopped;
    ReferenceImage image = reference_image_of(rp, std::move(pixels), opt.scene, scene_content_hash(scene), s.crex);
    image.header.commands = command_line(opt, opt.scene, opt.output);
    if (stopped) return write_stopped_reference(path, image, opt);  // no key: the cache's file is not it
    int status = write_and_say(path, image, opt,
                               fmt::format("{} at {}x{}, {} spp with {} in {:.1f} s", opt.scene, s.width, s.height, s.spp, s.crex, image.header.render_seconds));
    if (status == kExitOk && !opt.output.empty())
        if (std::string error = write_file_atomically(key_path, key + "\n"); !error.empty()) {
            std::cerr << "crex reference: error: " << error << "\n";
            return kExitFailure;
        }
    return status;
}

}  // namespace

Runner add_reference_command(CLI::App& app) {
    auto opt = std::make_shared<ReferenceOptions>();
    CLI::App* cmd = app.add_subcommand("reference", "Render a converged gold reference of a scene, cached by scene and settings");
    CLI::Option* scene = cmd->add_option("scene", opt->scene, "Scene: file.json, file.rad, file.rif, file.obj, file.gltf, file.glb or builtin:NAME")->capture_default_str();
    CLI::Option* size = cmd->add_option("--size", opt->size, "Image size WIDTHxHEIGHT (with windows: of the whole frame)")->capture_default_str();
    cmd->add_option("--spp", opt->spp, "Camera samples per pixel (with --accumulate: to add)")->capture_default_str()->check(whole_number_in(1, 1 << 20));
    CLI::Option* seed = cmd->add_option("--seed", opt->seed, "Seed (0 to 2^53)")->capture_default_str()->check(seed_value());
    cmd->add_option("-o,--output", opt->output, "Write here instead of the cache (required with windows)");
    cmd->add_option("--window", opt->windows,
                    "Render only this window X,Y,W,H of the frame (columns X..X+W-1, rows Y..Y+H-1); repeatable");
    cmd->add_option("--windows", opt->windows_rule, "auto: choose the windows by the stated rule (see below)")
        ->check(CLI::IsMember({"auto"}));
    cmd->add_option("--window-size", opt->window_size, "Side of each window --windows auto chooses, in pixels")
        ->capture_default_str()
        ->check(whole_number_in(1, 16384));
    cmd->add_option("--context-spp", opt->context_spp,
                    "Samples of the cheap cached render of the whole frame a windowed reference keeps (0: none; then the windows' own "
                    "exposure, and no saliency)")
        ->capture_default_str()
        ->check(whole_number_in(0, 4096));
    cmd->add_option("--accumulate", opt->accumulate, "Add --spp independent samples to this reference (windowed or not) and record the total");
    cmd->add_flag("--force", opt->force, "Render even if the cache has it");
    cmd->add_flag("-q,--quiet", opt->quiet, "No progress and no messages");
    cmd->add_option("--progress", opt->progress, "Progress on stderr: a redrawn line on a terminal (bar), a line every 10 s once past 5 s elsewhere (plain), or none; auto picks bar or plain")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "bar", "plain", "none"}));
    cmd->footer(R"(
Renders the scene with (TTMRSGD)* and prints the image's path. The cache is
$CREX_CACHE/references, else $XDG_CACHE_HOME/crex/references, else ~/.cache/crex/references;
the key is a hash of the scene's full content (not its path) and the settings.
'crex run --reference auto' uses the cached reference of its scene at its image size with
the most samples (seed 0).

Windows (references that scale with the frame): --window renders only those pixels of the
--size frame, each exactly as a render of the whole frame at the same seed would give it
(same camera, filter and sample pattern). The file holds the windows side by side, with the
frame and windows in its header, the whole frame's exposure and (layer 'attention') its
saliency at the windows' pixels, both from a cheap cached render of the whole frame
(--context-spp); 'crex compare' scores an image of the whole frame on the windows alone.
--windows auto chooses square windows of --window-size by one rule, in this order: the
tagged task object, a tagged distractor, a lamp's edge, the brightest caustic, the most
salient and the plainest region, none overlapping; it prints each choice and why.
--accumulate FILE renders --spp more samples of FILE's pixels, continuing its sample
indices (so they are independent of the ones it has), and writes the mean of all of them
with the total in its header (to -o, else over FILE), and an estimate of its own error
(crex:own_rmse, from how far the new samples' mean is from the old one; 'crex compare'
prints it beside the error it measures). Every reference records its seed,
samples, the commands that made it and a hash of the scene's content; accumulation refuses
a scene that has changed since.

Examples:
  crex reference                                       builtin:cornell, 128x128, 1024 spp
  crex reference examples/scenes/corridor/scene.json --size 128x96 --spp 4096
  crex reference builtin:cornell --size 960x540 --windows auto --spp 4096 --seed 1 -o ref.exr
  crex reference --accumulate ref.exr --spp 4096           8192 spp in all
  crex compare render.exr ref.exr                        scored on the windows
  crex run sel_rp --size 128x128 --reference auto --report out/report

Exit status: 0 ok, 1 errors in the scene (or a reference of another scene), 2 usage, 3 I/O
or runtime failure; 130 after Ctrl-C (143 after SIGTERM): the samples every pixel has so far
as NAME.partial.exr, which --accumulate takes further.)");
    return [opt, scene, size, seed] {
        opt->scene_given = scene->count() > 0;
        opt->size_given = size->count() > 0;
        opt->seed_given = seed->count() > 0;
        return reference(*opt);
    };
}

}  // namespace crex::app
