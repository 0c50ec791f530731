// `crex run`: render a scene with a crex on the component-bin renderer.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "apps/crex/commands.h"
#include "apps/crex/exit_codes.h"
#include "apps/crex/progress.h"
#include "compiler/base/render_text.h"
#include "apps/crex/input_files.h"
#include "apps/crex/pipeline_input.h"
#include "compiler/crex/compile.h"
#include "compiler/plan/read_plan.h"
#include "runtime/scene/census.h"
#include "compiler/sched/print.h"
#include "runtime/base/atomic_file.h"
#include "runtime/io/image_io.h"
#include "runtime/render/profile.h"
#include "runtime/render/render.h"
#include "runtime/pipeline/run_pipeline.h"
#include "apps/crex/run_pictures.h"
#include "apps/crex/run_report.h"
#include "apps/crex/run_summary.h"
#include "compiler/plan/emit_plan.h"
#include "compiler/plan/plan_pipeline.h"
#include "runtime/report/reference_cache.h"
#include "runtime/cache/irradiance_cache.h"

namespace crex::app {
namespace {

constexpr const char* kDefaultCrex = "(TTMRSGD)*";

struct RunOptions {
    std::string plan;
    bool size_given = false, spp_given = false;
    std::string scene;
    std::string crex;
    std::string size = "256x256";
    uint32_t spp = 16;
    std::vector<std::string> outputs;
    bool components = false;
    int threads = 0;
    uint64_t seed = 0;
    uint32_t shadow_rays = 1;
    double lw = 1e-3;
    uint32_t max_depth = 256;
    bool no_roulette = false;
    double ambient = 0;
    double importance = 1;
    uint32_t star_cap = sched::kDefaultStarCap;
    std::string format = "text";
    bool quiet = false;
    std::string budget;
    std::string profile_in;
    std::string profile_out;
    std::string maps_dir;
    std::string reference;     ///< image path, or "auto": the cached `crex reference` of this scene and size
    std::string report_dir;
    double checkpoint_interval = 0.1;
    bool ic = false;
    double aa = 0.15;
    uint32_t ad = 256, ab = 4;
    std::string ic_file;
    std::string filter = "box";
    bool seed_given = false, lw_given = false, max_depth_given = false, ambient_given = false, aa_given = false, ab_given = false;
};

// "10s", "500ms", "2.5" (seconds) or "25%" (of the full render time in the profile).
bool parse_budget(const std::string& text, double& value, bool& percent) {
    std::string t = text;
    percent = false;
    double scale = 1;
    if (t.size() > 2 && t.substr(t.size() - 2) == "ms") t.resize(t.size() - 2), scale = 1e-3;
    else if (!t.empty() && t.back() == 's') t.pop_back();
    else if (!t.empty() && t.back() == '%') t.pop_back(), percent = true;
    try {
        size_t used = 0;
        value = std::stod(t, &used) * scale;
        return used == t.size() && value > 0 && std::isfinite(value) && (!percent || value <= 1000);
    } catch (...) {
        return false;
    }
}

bool parse_size(const std::string& s, int& w, int& h) {
    char x = 0;
    std::istringstream in(s);
    if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || !in.eof()) return false;
    return w > 0 && h > 0 && w <= 16384 && h <= 16384;
}

int run(RunOptions opt) {

    // What to execute: a crex, or a plan made earlier by `crex plan`.
    if (!opt.plan.empty() && !opt.crex.empty()) {
        std::cerr << "crex run: error: give either a plan file or -e/--crex, not both\n";
        return kExitUsage;
    }
    DiagnosticSink sink;
    std::optional<sched::Program> program;
    std::string scene_spec = opt.scene;
    std::string expected_census;
    std::unique_ptr<SourceFile> source;
    PlanSettings settings;                         // from a pipeline or a pipeline plan
    PlanOutputs plan_outputs;
    std::unique_ptr<SceneInput> scene_in;          // a pipeline's scene is loaded while planning it
    std::optional<PipelinePlan> pipeline_plan;     // a pipeline (file or plan): guidance and svt run too
    bool is_pipeline = opt.plan.size() > 5 && opt.plan.substr(opt.plan.size() - 5) == ".pipe";
    if (is_pipeline) {
        auto in = load_pipeline_input(opt.plan, "", opt.scene, sink);
        if (!in->failure.empty()) {
            std::cerr << render_text(sink.sorted()) << "crex run: error: " << in->failure << "\n";
            return kExitFailure;
        }
        if (in->plan) {
            program = in->plan->program;
            pipeline_plan = *in->plan;
            scene_spec = in->scene_spec;
            settings = in->plan->settings;
            plan_outputs = in->plan->outputs;
            // W403 (guidance and selective variables do not execute yet) comes from the checker.
        }
        scene_in = std::move(in->scene);
        source = std::move(in->source);
    } else if (!opt.plan.empty()) {
        std::string read_error;
        auto text = read_input(opt.plan, read_error);
        if (!text) {
            std::cerr << "crex run: error: " << read_error << "\n";
            return kExitFailure;
        }
        source = std::make_unique<SourceFile>(opt.plan, std::move(*text));
        if (auto plan = read_plan(*source, sink)) {
            program = plan->program;
            if (scene_spec.empty()) scene_spec = plan->scene;
            expected_census = plan->census_hash;
            if (plan->pipeline) {
                settings = plan->pipeline->settings;
                plan_outputs = plan->pipeline->outputs;
                pipeline_plan = std::move(plan->pipeline);
            }
        }
    } else {
        source = std::make_unique<SourceFile>("<crex>", opt.crex.empty() ? kDefaultCrex : opt.crex);
        LowerOptions lower;
        lower.star_cap = opt.star_cap;
        program = compile_crex(*source, sink, lower).program;
    }
    if (scene_spec.empty()) scene_spec = "builtin:cornell";
    // A pipeline's settings apply unless a flag says otherwise (spec/pipeline.md §7).
    // The plan's settings are typed and range-checked (compiler/pipeline/settings_table.h).
    if (!opt.size_given && settings.width && settings.height) opt.size = fmt::format("{}x{}", *settings.width, *settings.height);
    if (!opt.spp_given && pipeline_plan) opt.spp = settings.spp;
    if (opt.budget.empty() && settings.budget) opt.budget = fmt::format("{}{}", settings.budget->amount, settings.budget->percent ? "%" : "s");
    if (opt.outputs.empty() && !plan_outputs.images.empty()) opt.outputs = plan_outputs.images;
    if (pipeline_plan) {
        if (!opt.seed_given && settings.seed) opt.seed = *settings.seed;
        if (!opt.lw_given && settings.lw) opt.lw = *settings.lw;
        if (!opt.max_depth_given && settings.max_depth) opt.max_depth = *settings.max_depth;
        if (!opt.aa_given && settings.aa) opt.aa = *settings.aa;
        if (!opt.ab_given && settings.ab) opt.ab = *settings.ab;
        if (!opt.ambient_given && settings.av) opt.ambient = *settings.av;
    }
    int width = 0, height = 0;
    if (!parse_size(opt.size, width, height)) {
        std::cerr << fmt::format("crex run: error: image size '{}': expected WIDTHxHEIGHT, e.g. 512x512\n", opt.size);
        return kExitUsage;
    }
    std::vector<std::string> outputs = opt.outputs;
    if (outputs.empty()) outputs = {"out/render.exr", "out/render.png"};
    // The scene.
    auto t_load = std::chrono::steady_clock::now();
    if (!scene_in) scene_in = load_scene_input(scene_spec, sink);
    double load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();
    const std::optional<Scene>& scene = scene_in->scene;
    // A plan is only valid for a scene with the census it was made for (spec 5).
    if (scene && !expected_census.empty()) {
        std::string actual = census_hash_hex(take_census(*scene).hash);
        if (actual != expected_census)
            sink.report("E402", {source.get(), 0, 0},
                        fmt::format("the plan was made for a scene with census {}, but {} has census {}", expected_census,
                                    scene_spec, actual))
                .help = "plan again for this scene: crex plan -e '...' --scene " + scene_spec;
    }
    std::cerr << render_text(sink.sorted());
    if (!scene_in->failure.empty()) {
        std::cerr << "crex run: error: " << scene_in->failure << "\n";
        return kExitFailure;
    }
    if (sink.has_errors() || !program || !scene) {
        std::cerr << fmt::format("crex run: {} error{}; nothing rendered\n", sink.error_count(), sink.error_count() == 1 ? "" : "s");
        return kExitInputErrors;
    }
    // The budget and the profile it is predicted from.
    Profile profile;
    double full_render_seconds = 0;
    if (!opt.profile_in.empty()) {
        std::ifstream in(opt.profile_in);
        std::stringstream text;
        text << in.rdbuf();
        if (!in) {
            std::cerr << fmt::format("crex run: error: cannot read profile '{}'\n", opt.profile_in);
            return kExitFailure;
        }
        std::string error = Profile::from_json_text(text.str(), profile);
        if (!error.empty()) {
            std::cerr << fmt::format("crex run: error: profile '{}': {}\n", opt.profile_in, error);
            return kExitInputErrors;
        }
        auto j = nlohmann::json::parse(text.str(), nullptr, false);
        full_render_seconds = j.value("full_render_seconds", 0.0);
    }
    double budget = 0;
    if (!opt.budget.empty()) {
        bool percent = false;
        if (!parse_budget(opt.budget, budget, percent)) {
            std::cerr << fmt::format("crex run: error: --budget '{}': expected e.g. 10s, 500ms or 25%\n", opt.budget);
            return kExitUsage;
        }
        if (percent) {
            if (!(full_render_seconds > 0)) {
                std::cerr << "crex run: error: --budget in % needs the time of a full render: render once without a "
                             "budget with --save-profile FILE, then pass --profile FILE\n";
                return kExitUsage;
            }
            budget = budget / 100 * full_render_seconds;
        }
    }

    std::unique_ptr<tbb::global_control> threads;
    if (opt.threads > 0)
        threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(opt.threads));

    RenderOptions ro;
    ro.width = width;
    ro.height = height;
    ro.spp = opt.spp;
    ro.seed = opt.seed;
    ro.filter = opt.filter == "gaussian" ? PixelFilter::kGaussian : PixelFilter::kBox;
    ro.ambient = {opt.ambient, opt.ambient, opt.ambient};
    ro.executor.shade.shadow_rays = opt.shadow_rays;
    ro.executor.shade.weight_limit = opt.lw;
    ro.executor.shade.max_depth = opt.max_depth;
    ro.executor.shade.roulette = !opt.no_roulette;
    ro.executor.constant_importance = opt.importance;
    ro.executor.budget_seconds = budget;
    ro.executor.profile = &profile;
    Progress progress(!opt.quiet);
    ro.executor.progress = [&](const std::string& what, uint64_t rays) { progress.update(what, rays); };

    // Checkpoints for the error-against-time curve: with a reference, or for a report.
    if (opt.report_dir.empty()) opt.report_dir = plan_outputs.report;
    if (opt.reference.empty()) opt.reference = settings.reference;
    std::optional<metrics::Image> reference;
    std::string reference_file = opt.reference;
    if (!opt.reference.empty() || !opt.report_dir.empty()) {
        bool automatic = opt.reference.empty() || opt.reference == "auto";
        if (automatic) {
            ReferenceSettings rs;
            rs.width = width, rs.height = height;
            reference_file = find_cached_reference(*scene, rs);
        }
        if (!automatic || !reference_file.empty()) {
            metrics::Image img;
            std::string error = read_image(reference_file, img.width, img.height, img.rgb);
            if (!error.empty()) {
                std::cerr << "crex run: error: reference: " << error << "\n";
                return kExitFailure;
            }
            if (img.width != width || img.height != height) {
                std::cerr << fmt::format("crex run: error: the reference {} is {}x{} but the render is {}x{}\n", reference_file, img.width,
                                         img.height, width, height);
                return kExitInputErrors;
            }
            reference = std::move(img);
        } else if (opt.reference == "auto") {
            std::cerr << fmt::format("crex run: error: no cached reference of {} at {}x{}: make one with 'crex reference {} --size "
                                     "{}x{}'\n",
                                     scene_spec, width, height, scene_spec, width, height);
            return kExitFailure;
        }
    }
    // The irradiance cache: --ic, or a pipeline that varies ic_radius (or sets aa).
    bool wants_cache = opt.ic || !opt.ic_file.empty();
    if (pipeline_plan)
        for (const auto& n : pipeline_plan->nodes) wants_cache |= n.id == "irradiance_cache";
    if (wants_cache) {
        IcSettings ics;
        ics.accuracy = opt.aa, ics.divisions = opt.ad, ics.bounces = opt.ab;
        ics.ambient = ro.ambient;
        ics.seed = opt.seed;
        ro.irradiance_cache = ics;
        if (!opt.ic_file.empty() && std::filesystem::exists(opt.ic_file)) {
            RenderScene probe_scene(*scene);  // records are validated against the scene's extent
            IrradianceCache loader(probe_scene, ics);
            std::string error = loader.load(opt.ic_file);
            if (!error.empty()) {
                std::cerr << "crex run: error: irradiance cache: " << error << "\n";
                return kExitInputErrors;
            }
            ro.ic_records = loader.records();
        }
    }
    std::optional<CheckpointRecorder> recorder;
    if (reference || !opt.report_dir.empty()) {
        recorder.emplace(opt.checkpoint_interval);
        ro.recorder = &*recorder;
    }

    std::optional<RenderResult> rendered;
    std::optional<PipelineRunResult> piped;
    try {
        if (pipeline_plan) {
            PipelineRunOptions po;
            po.width = width, po.height = height;
            po.preview_spp = opt.spp;
            po.seed = opt.seed;
            po.filter = ro.filter;
            po.ambient = ro.ambient;
            po.executor = ro.executor;
            po.recorder = ro.recorder;
            po.irradiance_cache = ro.irradiance_cache;
            po.ic_records = ro.ic_records;
            piped.emplace(run_pipeline(*scene, *pipeline_plan, po));
        } else {
            rendered.emplace(render(*scene, *program, ro));
        }
    } catch (const std::exception& e) {
        progress.finish();
        std::cerr << "crex run: error: rendering failed: " << e.what() << "\n";
        return kExitFailure;
    }
    progress.finish();
    const RenderResult& result = piped ? piped->render : *rendered;
    if (piped)
        for (const auto& note : piped->notes) std::cerr << "crex run: note: " << note << "\n";
    for (const auto& w : result.warnings) std::cerr << w << "\n";
    if (!opt.ic_file.empty() && ro.irradiance_cache) {
        RenderScene rs(*scene);
        IrradianceCache saver(rs, *ro.irradiance_cache);
        for (const auto& r : result.ic_records) saver.insert(r);
        std::string error = saver.save(opt.ic_file);
        if (!error.empty()) {
            std::cerr << "crex run: error: cannot save the irradiance cache: " << error << "\n";
            return kExitFailure;
        }
    }
    if (!opt.profile_out.empty()) {
        auto j = nlohmann::json::parse(profile.to_json_text());
        j["full_render_seconds"] = budget > 0 ? full_render_seconds : result.render_seconds;
        std::string error = write_file_atomically(opt.profile_out, j.dump(2) + "\n");
        if (!error.empty()) {
            std::cerr << fmt::format("crex run: error: cannot write profile '{}': {}\n", opt.profile_out, error);
            return kExitFailure;
        }
    }

    std::vector<ImageLayer> layers = {{"", piped ? piped->image() : result.image()}};
    if (opt.components)
        for (size_t a = 0; a < kAovCount; ++a) layers.push_back({aov_name(a), piped ? piped->aov_image(a) : result.film.aov_image(a)});
    for (const auto& path : outputs) {
        std::error_code ec;
        auto parent = std::filesystem::path(path).parent_path();
        if (!parent.empty()) std::filesystem::create_directories(parent, ec);
        std::string error = write_image(path, width, height, layers);
        if (!error.empty()) {
            std::cerr << "crex run: error: " << error << "\n";
            return kExitFailure;
        }
    }

    PictureSummary pictures;
    std::string maps_dir = opt.maps_dir;
    if (maps_dir.empty() && plan_outputs.maps)
        maps_dir = (std::filesystem::path(outputs.front()).parent_path() / "maps").string();
    if (!maps_dir.empty()) {
        static const std::vector<std::pair<std::string, guidance::Raster>> no_maps;
        std::string error = write_run_pictures(maps_dir, result.film, piped ? &piped->preview : nullptr,
                                               piped ? piped->maps : no_maps, pictures);
        if (!error.empty()) {
            std::cerr << "crex run: error: " << error << "\n";
            return kExitFailure;
        }
    }

    const ExecutorStats& st = result.stats;
    uint64_t total_rays = st.camera.rays;
    for (const auto& c : st.components) total_rays += c.rays;
    RunFacts facts;
    facts.scene = scene->source;
    facts.program = &*program;
    facts.width = width, facts.height = height;
    facts.spp = opt.spp;
    facts.load_seconds = load_seconds;
    facts.result = &result;
    facts.piped = piped ? &*piped : nullptr;
    facts.plan = pipeline_plan ? &*pipeline_plan : nullptr;
    facts.outputs = outputs;
    facts.budget = budget;
    facts.recorder = recorder ? &*recorder : nullptr;
    facts.ic = ro.irradiance_cache ? &*ro.irradiance_cache : nullptr;
    facts.ic_loaded = ro.ic_records.size();
    facts.maps_dir = maps_dir;
    facts.pictures = &pictures;
    facts.report_dir = opt.report_dir;
    nlohmann::json j = run_summary_json(facts);  // printed with --format json, and the report's
    std::vector<CurvePoint> curve;
    if (!opt.report_dir.empty() || reference) {
        RunReport report;
        report.dir = opt.report_dir;
        report.title = fmt::format("crex run: {} on {}", piped ? "pipeline " + pipeline_plan->name : sched::to_crex(*program), scene->source);
        report.width = width, report.height = height;
        report.checkpoints = &recorder->checkpoints();
        report.reference = reference;
        report.reference_path = reference_file;
        report.view = {true, reference ? display_exposure(reference->rgb) : 1.0};
        if (budget > 0) report.budget_seconds = budget;
        report.summary = j;
        report.images.push_back({"final image", layers.front().rgb});
        if (piped) report.images.push_back({"preview", piped->preview});
        if (reference) report.images.push_back({"reference", reference->rgb});
        for (size_t a = 0; a < kAovCount; ++a)
            report.images.push_back({"component " + aov_name(a), piped ? piped->aov_image(a) : result.film.aov_image(a)});
        if (piped) report.maps = piped->maps;
        report.pictures = pictures.written;
        if (pipeline_plan) {
            report.plan_dot = pipeline_plan_to_dot(*pipeline_plan);
        } else {
            CrexPlan cp;
            cp.source = source->text();
            cp.program = *program;
            report.plan_dot = plan_to_dot(cp);
        }
        if (opt.report_dir.empty()) {  // a reference without a report: the curve only, in the summary
            curve = error_curve(recorder->checkpoints(), *reference, report.view);
        } else if (std::string error = write_run_report(report, curve); !error.empty()) {
            std::cerr << "crex run: error: report: " << error << "\n";
            return kExitFailure;
        }
        if (!curve.empty()) {
            j["error_curve"] = curve_json(curve);
            j["reference"] = reference_file;
        }
        if (!opt.report_dir.empty()) j["report"] = (std::filesystem::path(opt.report_dir) / "index.html").string();
    }
    if (opt.format == "json") {
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    if (opt.quiet) return kExitOk;
    facts.curve = &curve;
    facts.reference = reference_file;
    print_run_summary(facts, std::cout);
    return kExitOk;
}

}  // namespace

Runner add_run_command(CLI::App& app) {
    auto opt = std::make_shared<RunOptions>();
    CLI::App* cmd = app.add_subcommand("run", "Render a scene with a crex on the component-bin renderer");
    cmd->add_option("plan", opt->plan, "A pipeline file (.pipe), or a plan made by 'crex plan --format json' (instead of -e)");
    cmd->add_option("--scene", opt->scene, "Scene: file.json, file.rad, file.obj or builtin:NAME (default: the plan's, "
                                           "else builtin:cornell)");
    cmd->add_option("-e,--crex", opt->crex, std::string("The crex saying in which order bins execute (default ") +
                                                kDefaultCrex + ")")
        ->allow_extra_args(false);
    CLI::Option* size = cmd->add_option("--size", opt->size, "Image size WIDTHxHEIGHT (default: the pipeline's image, else 256x256)");
    CLI::Option* spp = cmd->add_option("--spp", opt->spp, "Camera samples per pixel; of a pipeline, its preview's (default: the "
                                                          "pipeline's, else 16)")
                           ->check(CLI::Range(1u, 1u << 20));
    cmd->add_option("-o,--output", opt->outputs, "Output image(s): .exr (float), .hdr, .png (tone-mapped); repeatable "
                                                 "(default out/render.exr and out/render.png)")
        ->allow_extra_args(false);
    cmd->add_flag("--components", opt->components, "EXR: add one layer per component AOV (camera, D, G, S, T, R, M)");
    cmd->add_option("--threads", opt->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
    CLI::Option* seed = cmd->add_option("--seed", opt->seed, "Seed of every random number")->capture_default_str();
    cmd->add_option("--shadow-rays", opt->shadow_rays, "Shadow rays per hit")->capture_default_str()->check(CLI::Range(1u, 1024u));
    CLI::Option* lw = cmd->add_option("--lw", opt->lw, "Weight limit: rays below it face Russian roulette")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    CLI::Option* max_depth = cmd->add_option("--max-depth", opt->max_depth, "No ray is spawned beyond this depth")->capture_default_str()->check(CLI::Range(0u, 65535u));
    cmd->add_flag("--no-roulette", opt->no_roulette, "Drop rays below --lw instead of Russian roulette (biased)");
    CLI::Option* ambient = cmd->add_option("--ambient", opt->ambient, "Ambient value av standing in for unexecuted D work")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1e30));
    cmd->add_option("--importance", opt->importance, "Constant importance I for '{ }' until guidance maps exist")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--star-cap", opt->star_cap, "Iteration cap of '*' per entry (W401 when hit)")->capture_default_str();
    cmd->add_option("--budget", opt->budget, "Time budget: 10s, 500ms, or 25% of the full render time in --profile")
        ->allow_extra_args(false);
    cmd->add_option("--profile", opt->profile_in, "Profile (cost per ray per component) to predict from");
    cmd->add_option("--save-profile", opt->profile_out, "Write the measured profile (and this render's time) to FILE");
    cmd->add_option("--format", opt->format, "Summary as text or json (stdout)")->check(CLI::IsMember({"text", "json"}));
    cmd->add_flag("-q,--quiet", opt->quiet, "No progress and no summary");
    cmd->add_option("--reference", opt->reference, "Reference image to measure error against during the render (checkpoints), or "
                                                   "'auto' for the cached 'crex reference' of the scene at this size");
    cmd->add_option("--report", opt->report_dir, "Write a report to DIR: checkpoints (JSON, CSV), error plot (SVG), images, plan, "
                                                 "and one self-contained index.html");
    cmd->add_option("--checkpoint-interval", opt->checkpoint_interval, "Seconds between checkpoints within long steps (also at "
                                                                       "every step and stage boundary)")
        ->capture_default_str()
        ->check(CLI::Range(1e-4, 1e6));
    cmd->add_option("--filter", opt->filter, "Pixel filter: box, or gaussian (sigma 0.5 px, radius 1.5, by filter importance sampling)")
        ->capture_default_str()
        ->check(CLI::IsMember({"box", "gaussian"}));
    cmd->add_flag("--ic", opt->ic, "Indirect diffuse (D) through a Ward irradiance cache instead of path tracing");
    CLI::Option* aa = cmd->add_option("--aa", opt->aa, "Irradiance cache accuracy (smaller is finer; a pipeline's ic_radius varies it per pixel)")
        ->capture_default_str()
        ->check(CLI::Range(1e-3, 1.0));
    cmd->add_option("--ad", opt->ad, "Hemisphere rays per irradiance record (later bounces use ad/2^k, at least 16)")
        ->capture_default_str()
        ->check(CLI::Range(1u, 65536u));
    CLI::Option* ab = cmd->add_option("--ab", opt->ab, "Ambient bounces through the cache (then --ambient)")->capture_default_str()->check(CLI::Range(1u, 64u));
    cmd->add_option("--ic-file", opt->ic_file, "Load the irradiance cache from FILE if it exists, save it there after the render (implies --ic)");
    cmd->add_option("--maps", opt->maps_dir, "Write every guidance map, the preview and per-pixel pictures (samples, rays, "
                                             "components) to DIR (default with 'output { maps true }': beside the image)");
    cmd->footer(R"(
Camera rays are traced first; then the crex runs over the component bins (D G S T R M) and
rays still waiting when it ends are dropped (--ambient stands in for waiting D rays).
A pipeline file (or its plan) runs all three stages: the preview at the base spp, the guidance
maps, then the selective pass with its variables per pixel (docs/guidance.md); --spp then sets
the preview's samples, and flags override the pipeline's settings.

Examples:
  crex run                                          built-in Cornell box, (TTMRSGD)*, 256x256
  crex run -e 'TT' --spp 4 -o tt.png                direct light plus two glass interfaces
  crex run --scene examples/scenes/corridor/scene.json -e '(DGSTR)*' --size 320x240
  crex run -e '(TTMRSGD)*' --components -o out/cornell.exr   one EXR layer per component
  crex plan -e '(TTMRSGD)*' --scene S --format json -o p.json && crex run p.json   a kept plan
  crex run -e '(TT[RS]G)*D' --save-profile p.json            measure, then render in 25 % of the time:
  crex run -e '(TT[RS]G)*D' --profile p.json --budget 25%
  crex run stdlib/pipelines/sel_rp.pipe --maps out/maps      saliency-driven rays per pixel, with its maps
  crex run examples/pipelines/cornell_prog.pipe --size 128x128 --format json

Exit status: 0 ok or warnings only, 1 errors in the crex or scene, 2 usage, 3 I/O or runtime failure.)");
    return [opt, size, spp, seed, lw, max_depth, ambient, aa, ab] {
        RunOptions o = *opt;
        o.aa_given = aa->count() > 0;
        o.ab_given = ab->count() > 0;
        o.seed_given = seed->count() > 0;
        o.lw_given = lw->count() > 0;
        o.max_depth_given = max_depth->count() > 0;
        o.ambient_given = ambient->count() > 0;
        o.size_given = size->count() > 0;
        o.spp_given = spp->count() > 0;
        return run(o);
    };
}

}  // namespace crex::app
