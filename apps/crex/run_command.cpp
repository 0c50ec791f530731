#include "apps/crex/run_command.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <regex>
#include <sstream>

#include "apps/crex/cli_values.h"
#include "apps/crex/guarded_rendering.h"
#include "runtime/api/interrupt.h"
#include "runtime/api/console_progress.h"
#include "base/check.h"
#include "base/exit_codes.h"
#include "base/render_text.h"
#include "runtime/api/resume.h"
#include "runtime/api/run_description.h"
#include "runtime/api/run.h"
#include "runtime/api/run_outputs.h"
#include "runtime/api/shared_inputs.h"
#include "runtime/base/output_folder.h"
#include "runtime/api/sequence_outputs.h"
#include "runtime/io/image_io.h"
#include "runtime/io/video_file.h"
#include "runtime/scene/camera_path_file.h"
#include "runtime/distributed/distributed.h"
#include "runtime/distributed/partial_rows.h"

namespace crex::app {
namespace {

// The flags as the library's typed inputs and options: what was given overrides the plan's
// settings (spec/pipeline.md §7). Usage errors are said by `say` only (under mpirun the lead).
struct Request {
    DistributedOptions distributed;
    InputSpec input;
    RunOptions options;
    RunFiles files;         // the flags' outputs; the plan's apply where none was given
    std::string reference;  // --reference: a path or "auto" ("": the plan's)
    std::string resume;     // --resume: a partial image to finish
    bool compare_policies = false, equal_time = false;
    std::string budget;     // --budget as given, for what is said about it
    std::string format;     // of the summary: text or json
    bool quiet = false, verbose = false;
    std::string progress;   // --progress
    int threads = 0;
    double checkpoint_interval = 0.1;
    // --camera-path: frames along a path instead of one image (runtime/api/frame_sequence.h).
    std::string camera_path;
    std::string video;  // --video: the sequence's frames as a video (runtime/io/video_file.h)
    std::optional<FrameRange> frames;  // unset: every frame of the path
    SequenceOptions sequence;
};

std::optional<int> make_request(const RunFlags& f, bool say, Request& r) {
    auto usage = [&](const std::string& message) -> std::optional<int> {
        if (say) std::cerr << "crex run: error: " << message << "\n";
        return kExitUsage;
    };
    if (!f.plan.empty() && f.crex_given) return usage("give either a plan file or -e/--crex, not both");
    r.distributed.ic_share = f.ic_share == "none"        ? IcShare::kNone
                             : f.ic_share == "central"   ? IcShare::kCentral
                             : f.ic_share == "broadcast" ? IcShare::kBroadcast
                                                         : IcShare::kComponent;
    r.distributed.rank_timeout = f.rank_timeout;
    r.input.file = f.plan;
    if (f.crex_given) r.input.crex = f.crex;  // an empty -e is an empty crex (camera rays only)
    r.input.scene = f.scene;
    r.input.camera = f.camera;
    r.input.view = f.view;
    r.input.star_cap = f.star_cap;
    r.input.profile = f.profile_in;
    r.input.ic_file = f.ic_file;

    RunOptions& o = r.options;
    int width = 0, height = 0;
    if (!parse_image_size(f.size, width, height))
        return usage(fmt::format("image size '{}': expected WIDTHxHEIGHT, each 1 to 16384, e.g. 512x512", f.size));
    if (f.size_given) o.width = width, o.height = height;
    if (f.spp_given) o.spp = f.spp;
    if (f.seed_given) o.seed = f.seed;
    if (f.lw_given) o.lw = f.lw;
    if (f.max_depth_given) o.max_depth = f.max_depth;
    if (f.aa_given) o.aa = f.aa;
    if (f.ab_given) o.ab = f.ab;
    if (f.ad_given) o.ad = f.ad;
    if (!f.ambient_text.empty()) {
        AmbientStandIn ambient;
        if (!parse_ambient(f.ambient_text, ambient))
            return usage(fmt::format("--ambient '{}': expected 'auto' or a radiance from 0 to 1e30", f.ambient_text));
        o.ambient = ambient;
    }
    if (!f.budget.empty()) {
        PlanBudget budget;
        if (std::string error = parse_budget(f.budget, budget); !error.empty()) return usage(fmt::format("--budget {}: {}", f.budget, error));
        o.budget = budget;
    }
    o.no_budget = f.no_budget;
    if (f.rounds) o.rounds = f.rounds;
    if (f.preview_stride) o.preview_stride = f.preview_stride;
    o.budget_floor_ok = f.budget_floor == "ok";
    o.saves_profile = !f.profile_out.empty();
    if (f.shadow_rays_given) o.shadow_rays = f.shadow_rays;
    o.media_samples = f.media_samples;
    o.roulette = !f.no_roulette;
    o.clamp = f.clamp;
    o.importance = f.importance;
    o.filter = f.filter == "gaussian" ? PixelFilter::kGaussian : PixelFilter::kBox;
    o.uniform = f.uniform == "max" ? UniformQuality::kMax : f.uniform == "min" ? UniformQuality::kMin : UniformQuality::kOff;
    o.max_memory = static_cast<size_t>(f.max_memory_mib * double(1 << 20));
    o.pass_samples = f.pass_samples;
    o.irradiance_cache = f.ic;
    o.ar = f.ar;
    o.caustic_photons = f.caustic_photons;
    o.ic_file = f.ic_file;

    r.files.images = f.outputs;
    r.files.components = f.components;
    r.files.profile = f.profile_out;
    r.files.maps_dir = f.maps_dir;
    r.files.report_dir = f.report_dir;
    r.reference = f.reference;
    r.resume = f.resume;
    r.compare_policies = f.compare_policies;
    r.equal_time = f.equal_time;
    r.budget = f.budget;
    r.format = f.format;
    r.quiet = f.quiet, r.verbose = f.verbose && !f.quiet;
    r.progress = f.progress;
    r.threads = f.threads;
    r.checkpoint_interval = f.checkpoint_interval;

    // A sequence: its flags, and what it does not write per frame yet.
    if (!f.frames.empty() && f.camera_path.empty())
        return usage("--frames needs --camera-path FILE: the camera of each frame comes from a path");
    for (const auto& [given, flag] : {std::pair{f.force, "--force"}, std::pair{f.no_carry_cache, "--no-carry-cache"},
                                      std::pair{f.reuse_frames > 0, "--reuse-frames"}, std::pair{f.seed_per_frame, "--seed-per-frame"},
                                      std::pair{!f.high_quality_frames.empty(), "--high-quality-frames"},
                                      std::pair{f.high_quality_without_distractors, "--high-quality-without-distractors"},
                                      std::pair{!f.sequence_budget.empty(), "--sequence-budget"}, std::pair{!f.video.empty(), "--video"}})
        if (given && f.camera_path.empty()) return usage(fmt::format("{} is for frames along a camera path: give --camera-path FILE", flag));
    if (std::string error = parse_frame_ranges(f.high_quality_frames, r.sequence.high_quality); !error.empty())
        return usage(fmt::format("--high-quality-frames {}: {}", f.high_quality_frames, error));
    r.sequence.high_quality_without_distractors = f.high_quality_without_distractors;
    if (!f.sequence_budget.empty()) {
        // The driver is set up as for a budget of the whole (coarse-to-fine previews, the
        // policy); each frame's own is set as the sequence goes (frame_sequence.h).
        PlanBudget budget;
        if (std::string error = parse_budget(f.sequence_budget, budget); !error.empty())
            return usage(fmt::format("--sequence-budget {}: {}", f.sequence_budget, error));
        if (budget.percent) return usage(fmt::format("--sequence-budget {}: give the sequence's time in seconds (10s, 500ms)", f.sequence_budget));
        if (!f.budget.empty() || f.no_budget)
            return usage(fmt::format("--sequence-budget does not go with {}: it sets every frame's budget", f.no_budget ? "--no-budget" : "--budget"));
        r.sequence.budget_seconds = budget.amount;
        o.budget = budget;
    }
    r.camera_path = f.camera_path;
    if (!f.frames.empty()) {
        FrameRange range;
        if (std::string error = parse_frame_range(f.frames, range); !error.empty()) return usage(fmt::format("--frames {}: {}", f.frames, error));
        r.frames = range;
    }
    // Checked after every value is parsed (cli_values.h), so that the flags pass each file once.
    if (!f.policy.empty()) o.policy = pipeline::scheduling_policy_from_name(f.policy);
    if (!f.video.empty()) {  // before anything renders: a video that cannot be made is said now
        if (std::string error = check_video_path(f.video); !error.empty()) return usage("--video " + error);
        if (find_video_encoder().empty())
            return usage("--video needs ffmpeg, which is not installed (Debian package ffmpeg); the frames alone need no --video");
        if (std::string missing = missing_output_folder(f.video); !missing.empty()) return usage("--video: " + missing);
        r.video = f.video;
    }
    r.sequence.fps = f.fps;
    r.sequence.force = f.force;
    r.sequence.carry_cache = !f.no_carry_cache;
    r.sequence.reuse_frames = static_cast<float>(f.reuse_frames);
    r.sequence.seed_per_frame = f.seed_per_frame;
    r.sequence.plan_file = f.plan;
    if (!f.camera_path.empty()) r.sequence.reference = f.reference;  // a sequence's: each frame it has is scored
    if (!f.camera_path.empty()) {
        for (const auto& [given, flag] : {std::pair{!f.view.empty(), "--view"}, std::pair{!f.resume.empty(), "--resume"},
                                          std::pair{f.compare_policies, "--compare-policies"}, std::pair{f.equal_time, "--equal-time"},
                                          std::pair{!f.maps_dir.empty(), "--maps"}, std::pair{f.reference == "auto", "--reference auto"},
                                          std::pair{!f.profile_out.empty(), "--save-profile"}})
            if (given)
                return usage(fmt::format("{} does not go with --camera-path yet: a sequence writes its images and its report{}", flag,
                                         std::string(flag) == "--view"             ? " (the path gives every frame's view)"
                                         : std::string(flag) == "--reference auto" ? " (give the reference sequence's name)"
                                                                                   : ""));
    }
    return std::nullopt;
}

// What only the lead does before anything renders: it reads the inputs and checks everything
// that can fail, so that every process learns the verdict before it starts.
struct LeadChecks {
    ReferenceInput reference;
    std::optional<ResumedRows> resumed;
    std::optional<CameraPath> path;  // --camera-path
    std::string path_text;           // its file, for the other processes
};

// The camera path, its diagnostics said; the frames checked against it (every frame of the
// path when none were given). An exit status, or kExitOk.
int read_camera_path_file(Request& r, LeadChecks& lead) {
    CameraPathInput read = read_camera_path_input(r.camera_path, r.input.camera, r.sequence.fps);
    std::cerr << read.diagnostics;
    if (!read.error.empty()) {
        std::cerr << fmt::format("crex run: error: --camera-path: {}\n", read.error);
        return kExitFailure;
    }
    if (!read.path) {
        std::cerr << fmt::format("crex run: {} error{} in the camera path; nothing rendered\n", read.errors, read.errors == 1 ? "" : "s");
        return kExitInputErrors;
    }
    lead.path = std::move(read.path), lead.path_text = std::move(read.text);
    if (std::string wrong = sequence_frames(*lead.path, r.sequence.fps, r.frames, r.sequence.frames); !wrong.empty()) {
        std::cerr << "crex run: error: " << wrong << "\n";
        return kExitUsage;
    }
    return kExitOk;
}

// A sequence with a budget in % and no profile to take it of: its first frame renders whole and
// its profile sizes the frames after (SequenceOptions::budget_of_first_frame). Decided alike on
// every process, from the plan they share.
void budget_of_first_frame(Request& r, const PipelinePlan& plan) {
    if (r.camera_path.empty() || r.options.profile || r.sequence.budget_of_first_frame) return;
    const std::optional<PlanBudget> budget = r.options.no_budget ? std::nullopt : r.options.budget ? r.options.budget : plan.settings.budget;
    if (!budget || !budget->percent) return;
    r.sequence.budget_of_first_frame = r.options;
    r.options.budget.reset();
    r.options.no_budget = true;
}

int read_and_check(Request& r, RunInputs& in, LeadChecks& lead) {
    DiagnosticSink sink;
    in = load_run_inputs(r.input, sink);
    std::cerr << render_text(sink.sorted());
    if (!in.failure.empty()) {
        std::cerr << "crex run: error: " << in.failure << "\n";
        return in.failure_is_usage ? kExitUsage : in.failure_in_content ? kExitInputErrors : kExitFailure;
    }
    if (sink.has_errors() || !in.ready()) {
        std::cerr << fmt::format("crex run: {} error{}; nothing rendered\n", sink.error_count(), sink.error_count() == 1 ? "" : "s");
        return kExitInputErrors;
    }
    r.options.profile = in.profile;
    budget_of_first_frame(r, in.plan);
    std::optional<ResolvedRun> run;
    try {
        run = resolve_run(in.plan, r.options);
    } catch (const BudgetBelowFloor& e) {  // a budget no render of this pipeline can meet: the budget is the usage error
        std::cerr << fmt::format("{}: error: budget: {}\n", e.where.empty() ? "crex run" : e.where, e.what());
        return kExitUsage;
    } catch (const RunOptionError& e) {  // said where the setting comes from: the pipeline's line, or the flag
        if (e.where.empty()) {
            std::cerr << fmt::format("crex run: error: --budget {}: {}\n", r.budget, e.what());
            return e.in_input_file ? kExitInputErrors : kExitUsage;
        }
        std::cerr << fmt::format("{}: error: budget {:g}%: {}\n", e.where, in.plan.settings.budget->amount, e.what());
        return kExitInputErrors;
    }
    const RunSettings& s = run->settings;
    // The plan's outputs where no flag names any. Their folders, and the default's, are made:
    // a pipeline shipped with `image "out/x.exr"` runs from a fresh clone. A folder in a path
    // the user typed must exist (said below, before anything renders).
    RunFiles& files = r.files;
    std::vector<std::string> defaults;  // outputs no flag named
    if (files.images.empty()) files.images = defaults = in.plan.outputs.images;
    if (files.images.empty()) files.images = defaults = {"out/render.exr", "out/render.png"};
    if (!r.camera_path.empty()) {
        if (int status = read_camera_path_file(r, lead); status != kExitOk) return status;
        if (std::string far = check_path_cameras(*lead.path, r.sequence.fps, r.sequence.frames, *in.scene->scene); !far.empty()) {
            std::cerr << fmt::format("crex run: error: --camera-path: {}; nothing rendered\n", far);
            return kExitInputErrors;
        }
        const double frames = static_cast<double>(r.sequence.frames.frames().size());
        if (r.sequence.budget_seconds > 0 && run->fixed_costs && !r.options.budget_floor_ok &&
            r.sequence.budget_seconds / frames < run->fixed_costs->floor_seconds) {
            std::cerr << fmt::format("crex run: error: --sequence-budget: {:.3g} s over {} frames is {:.3g} s a frame, below the smallest "
                                     "budget this pipeline can meet, {:.3g} s: give at least {:.3g} s, or --budget-floor ok to render "
                                     "anyway (the budget will be broken)\n",
                                     r.sequence.budget_seconds, frames, r.sequence.budget_seconds / frames, run->fixed_costs->floor_seconds,
                                     run->fixed_costs->floor_seconds * frames);
            return kExitUsage;
        }
        if ((!r.sequence.high_quality.empty() || r.sequence.high_quality_without_distractors) && !in.plan.staged) {
            std::cerr << "crex run: error: frames tagged high quality need a pipeline (a .pipe file or its kept plan): a plain "
                         "crex has no selective variables to raise\n";
            return kExitUsage;
        }
        if (in.plan.outputs.maps || !in.plan.settings.reference.empty())
            std::cerr << "crex run: note: the pipeline's maps and reference are not made per frame yet; a sequence writes its images "
                         "and its report\n";
        in.plan.outputs.maps = false;
        in.plan.settings.reference.clear();
        if (!r.reference.empty()) {  // a sequence: each frame it has is scored (frame_sequence.h)
            bool bad_pixels = false;
            if (std::string error = check_sequence_reference(r.reference, r.sequence.frames, s.width, s.height, bad_pixels); !error.empty()) {
                std::cerr << "crex run: error: --reference " << r.reference << ": " << error << "\n";
                return bad_pixels ? kExitInputErrors : kExitFailure;
            }
        }
    }
    if (files.report_dir.empty() && !in.plan.outputs.report.empty()) defaults.push_back(files.report_dir = in.plan.outputs.report);
    if (files.maps_dir.empty() && in.plan.outputs.maps)
        files.maps_dir = (std::filesystem::path(files.images.front()).parent_path() / "maps").string();
    files.components = files.components || in.plan.outputs.components;
    for (const auto& path : defaults)
        if (std::string error = make_output_folder(path); !error.empty()) {
            std::cerr << "crex run: error: " << error << "\n";
            return kExitFailure;
        }
    // Every output is checked before anything renders (run_outputs.h).
    bool usage = false;
    if (std::string refusal = outputs_refusal(files, r.input.ic_file, usage); !refusal.empty()) {
        std::cerr << "crex run: error: " << refusal << "\n";
        return usage ? kExitUsage : kExitFailure;
    }
    // The reference of the error curve: with --reference (or the pipeline's), or for a report.
    const std::string reference = r.reference.empty() ? in.plan.settings.reference : r.reference;
    if ((!reference.empty() || !files.report_dir.empty()) && r.camera_path.empty()) {
        lead.reference = load_reference(reference, *in.scene->scene, in.scene_spec, s.width, s.height);
        if (!lead.reference.error.empty()) {
            std::cerr << "crex run: error: " << lead.reference.error << "\n";
            return lead.reference.wrong_size || lead.reference.not_finite ? kExitInputErrors : kExitFailure;
        }
    }
    if (!r.resume.empty()) {
        auto refuse = [&](const std::string& why, int status) {
            std::cerr << fmt::format("crex run: error: --resume {}: {}\n", r.resume, why);
            return status;
        };
        // Outputs the partial has no rows for.
        if (files.components)
            return refuse("cannot resume a run with --components (or the pipeline's output { components true }): the partial image "
                          "holds the final rows' composite only",
                          kExitUsage);
        if (!files.maps_dir.empty())
            return refuse("cannot resume a run with --maps (or the pipeline's output { maps true }): the partial image holds the "
                          "final rows' composite only, not their samples and rays",
                          kExitUsage);
        if (!files.report_dir.empty() || !reference.empty())
            return refuse("cannot resume a run with --report and --reference: the error curve of a resumed run would measure rows "
                          "it did not render",
                          kExitUsage);
        if (r.compare_policies || r.equal_time)
            return refuse(fmt::format("cannot resume a run with {}", r.equal_time ? "--equal-time" : "--compare-policies"), kExitUsage);
        ResumeLoad load = load_resume(r.resume, in.scene_spec, in.plan, s);
        if (!load.rows) return refuse(load.error, load.io ? kExitFailure : load.bad_file ? kExitInputErrors : kExitUsage);
        r.options.final_rows = load.rows->final_rows;
        lead.resumed = std::move(load.rows);
    }
    if (r.compare_policies && (!(run->budget_seconds > 0) || !lead.reference.image)) {
        std::cerr << "crex run: error: --compare-policies needs a budget (--budget or the pipeline's) and a reference "
                     "(--reference, or --report with a cached reference)\n";
        return kExitUsage;
    }
    if (r.equal_time && (!in.plan.staged || !lead.reference.image)) {
        std::cerr << "crex run: error: --equal-time needs a pipeline (a .pipe file or its kept plan) and a reference (--reference, "
                     "the pipeline's, or --report with a cached reference)\n";
        return kExitUsage;
    }
    return kExitOk;
}

// Notes and warnings of the runtime, each note once in first-said order: every round of the
// cyclic process may say the same thing, and every frame of a sequence the same thing with its
// own figures (then the first is said, with how many said it).
void say_notes(const std::vector<std::string>& notes) {
    static const std::regex figures("[0-9][0-9.,e+-]*");
    std::vector<std::pair<std::string, int>> said;
    std::vector<std::string> shapes;
    for (const auto& note : notes) {
        const std::string shape = std::regex_replace(note, figures, "#");
        auto it = std::find(shapes.begin(), shapes.end(), shape);
        if (it == shapes.end()) said.emplace_back(note, 1), shapes.push_back(shape);
        else ++said[static_cast<size_t>(it - shapes.begin())].second;
    }
    for (const auto& [note, times] : said)
        std::cerr << "crex run: note: " << note << (times > 1 ? fmt::format(" ({} times)", times) : "") << "\n";
}

// The frames of a camera path: a progress line per frame, the sequence's summary at the end.
// Under mpirun each process renders a share of the frames (render_frames); the lead says them all.
int run_sequence(Request& r, RunInputs& in, const ResolvedRun& run, const CameraPath& path, ProcessGroup& group) {
    r.sequence.path = &path;
    const bool talk = !r.quiet && r.format != "json" && group.leads();
    // Ctrl-C or SIGTERM in one process: the frame under way is dropped, the finished ones are
    // kept, and the same command goes on from there (render_frames).
    const bool stoppable = !group.distributed();
    if (stoppable) catch_interrupt();
    ConsoleProgress progress(progress_mode(r.progress, !talk), nullptr, stoppable);
    std::vector<FrameRun> frames;
    const auto start = std::chrono::steady_clock::now();
    auto render = [&] {
        frames = render_frames(
            in, run, r.files, r.sequence, progress,
            [&](const FrameRun& f, size_t index, size_t count) {
                progress.finish();
                if (talk) std::cerr << "crex run: " << frame_line(f, index, count) << "\n";
            },
            &group);
    };
    if (group.distributed()) {  // a process that fails ends every one, named: the lead would wait for its frames
        try {
            render();
        } catch (const InternalError& e) {
            group.fail(ProcessFailure::kInternal, e.what());
        } catch (const RunInputError& e) {
            group.fail(ProcessFailure::kInput, e.what());
        } catch (const FrameWriteError& e) {
            group.fail(ProcessFailure::kRender, std::string(e.what()) + "; the frames before it are written");
        } catch (const std::exception& e) {
            group.fail(ProcessFailure::kRender, e.what());
        }
        progress.finish();
        if (!group.leads()) return kExitOk;
    } else if (const int status = guarded_rendering("crex run", progress, [&] {
                   try {
                       render();
                   } catch (const FrameWriteError& e) {
                       progress.finish();
                       std::cerr << "crex run: error: " << e.what() << "; the frames before it are written\n";
                       return kExitFailure;
                   }
                   return kExitOk;
               });
               status != kExitOk) {
        return status;
    }
    if (stoppable && interrupted()) {
        std::cerr << "crex run: " << stopped_sequence_text(frames, r.sequence.frames.frames().size()) << "\n";
        return interrupted_exit_code();
    }
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Each note and warning once, however many frames said it.
    std::vector<std::string> notes;
    DiagnosticSink warnings;
    for (const FrameRun& f : frames) {
        notes.insert(notes.end(), f.notes.begin(), f.notes.end());
        for (const Diagnostic& w : f.warnings) warnings.add(w);
    }
    say_notes(notes);
    std::cerr << render_text(warnings.sorted());
    if (r.format == "json") {
        nlohmann::json j = frames_json(frames, r.sequence.fps);
        j["camera_path"] = r.camera_path;
        j["processes"] = group.processes();
        if (r.sequence.budget_seconds > 0) j["sequence_budget"] = {{"seconds", r.sequence.budget_seconds}, {"took", took}};
        j["scene"] = in.scene_spec;
        j["warnings"] = in.load_warnings;  // each frame lists its own
        std::cout << j.dump(2) << "\n";
    } else if (!r.quiet) {
        std::cout << frames_summary_text(frames, r.sequence.budget_seconds, took, group.distributed() ? group.processes() : 1);
    }
    std::vector<std::string> wrote;
    const SequenceDescription described{r.camera_path,       r.sequence.reference, r.sequence.fps, run.settings.width, run.settings.height,
                                        group.processes(), r.sequence.budget_seconds, took};
    if (std::string error = write_sequence_outputs({r.video, r.files.report_dir}, frames, in, described, wrote); !error.empty()) {
        std::cerr << "crex run: error: " << error << "; the frames are written\n";
        return kExitFailure;
    }
    if (!r.quiet && r.format != "json")
        for (const auto& line : wrote) std::cout << "  wrote " << line << "\n";
    return kExitOk;
}

// Ctrl-C or SIGTERM: the image so far goes to NAME.partial.EXT beside each image asked for (the files the
// user had stay as they were). Maps, report and profile describe a whole render: none is written.
int write_stopped_render(const Request& r, const RunRecord& record) {
    RunFiles partial;
    partial.components = r.files.components;
    for (const auto& image : r.files.images) partial.images.push_back(distributed::partial_path(image));
    WrittenRun written;
    if (std::string error = write_run_files(partial, record, written); !error.empty()) {
        std::cerr << "crex run: error: interrupted, and the image so far could not be written: " << error << "\n";
        return kExitFailure;
    }
    const RunResult& result = *record.outcome->result;
    std::cerr << fmt::format("crex run: interrupted after {:.1f} s: wrote the image so far to {} ({} camera samples of the stage running "
                             "left out)\n",
                             result.render_seconds, fmt::join(partial.images, ", "), result.stopped_samples);
    return interrupted_exit_code();
}

// Reads, checks, renders and writes: the lead reads and checks (every process learns its
// verdict), every process renders its part, the lead writes and says what happened.
int run_request(Request& r) {
    std::unique_ptr<ProcessGroup> group = make_process_group(r.distributed);
    if (group->distributed() && (r.compare_policies || r.equal_time || !r.resume.empty())) {  // every rank refuses alike; the lead says so
        if (group->leads())
            std::cerr << (r.resume.empty() ? fmt::format("crex run: error: under mpirun, {} is not supported yet\n",
                                                         r.compare_policies ? "--compare-policies" : "--equal-time")
                                             : "crex run: error: under mpirun, --resume is not supported yet: resume in one process "
                                               "(the same command without mpirun)\n");
        return kExitUsage;
    }
    // The lead alone reads, checks and plans; the others get it as data.
    LeadChecks lead;
    RunInputs in = share_run_inputs(*group, [&] {
        RunInputs read;
        read.status = read_and_check(r, read, lead);
        return read;
    });
    if (in.status != kExitOk) return in.status;
    // The lead writes the images at the end: OpenImageIO's libraries load (0.3 s), where an
    // image needs them, while it renders, not after; once the inputs are good, so that an
    // error is said without the wait.
    const std::future<void> image_plugin = group->leads() ? preload_image_plugin(r.files.images) : std::future<void>{};
    r.options.profile = in.profile;
    r.options.ic_file_bytes = in.ic_file_bytes;
    // Every film buffer only to show components (4K: 1.9 GB, else 270 MB); from the shared plan, so alike on every rank.
    r.options.component_images =
        r.files.components || in.plan.outputs.components || !r.files.report_dir.empty() || !in.plan.outputs.report.empty();
    budget_of_first_frame(r, in.plan);
    ResolvedRun run = resolve_run(in.plan, r.options);  // the lead resolved them already: this cannot fail
    if (r.verbose && group->leads()) std::cerr << describe_run(in, run, r.threads, "crex run: ");
    std::unique_ptr<tbb::global_control> threads;
    if (r.threads > 0)
        threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(r.threads));
    if (!r.camera_path.empty()) {
        // The lead read and checked the path and chose the frames; the others take both as data.
        nlohmann::json shared;
        if (group->leads())
            shared = {{"text", lead.path_text}, {"first", r.sequence.frames.first}, {"last", r.sequence.frames.last}, {"step", r.sequence.frames.step}};
        shared = nlohmann::json::parse(group->share_from_lead(shared.dump(), "the camera path"));
        if (!group->leads()) {
            DiagnosticSink unsaid;  // said by the lead
            lead.path = read_camera_path(SourceFile(r.camera_path, shared["text"].get<std::string>()), r.sequence.fps, unsaid);
            if (!lead.path) {
                group->fail(ProcessFailure::kInternal, "the camera path the lead read does not read here");
                return kExitFailure;
            }
            r.sequence.frames = {shared["first"].get<int64_t>(), shared["last"].get<int64_t>(), shared["step"].get<int64_t>()};
        }
        return run_sequence(r, in, run, *lead.path, *group);
    }
    // One image from here: should the group fail, the lead writes the rows it finished.
    group->keep_partial_outputs(r.files.images, run.settings.width, run.settings.height,
                                partial_identity(in.scene_spec, in.plan, run.settings));
    // With a reference, each checkpoint is scored when taken (seen as the report will show it)
    // and its image freed.
    const CheckpointScorer scorer =
        lead.reference.image ? scorer_against(*lead.reference.image, report_view(&*lead.reference.image)) : CheckpointScorer{};
    std::optional<CheckpointRecorder> recorder;
    if (lead.reference.image || !r.files.report_dir.empty()) recorder.emplace(r.checkpoint_interval, scorer);
    const bool quiet = r.quiet || !group->leads();
    // Ctrl-C or SIGTERM: the image so far, as NAME.partial.EXT (interrupt.h); one process only.
    const bool stoppable = !group->distributed();
    if (stoppable) catch_interrupt();
    ConsoleProgress progress(progress_mode(r.progress, quiet || r.format == "json"), recorder ? &*recorder : nullptr, stoppable);
    RunOutcome out;
    if (int status = guarded_rendering("crex run", progress, [&] {
            out = run_resolved(in.plan, *in.scene->scene, std::move(run), *group, progress);
            return kExitOk;
        });
        status != kExitOk)
        return status;
    if (!group->leads() || !out.result) return kExitOk;  // the lead writes the outputs
    RunRecord record;
    record.inputs = &in;
    record.outcome = &out;
    record.plan_file = r.input.file;
    record.checkpoints = recorder ? &*recorder : nullptr;
    record.reference = lead.reference.image;
    record.reference_path = lead.reference.path;
    record.resumed = lead.resumed ? &*lead.resumed : nullptr;
    if (out.result->stopped) return write_stopped_render(r, record);
    if (r.compare_policies) {  // the same render under every other policy, for the report's plot of all of them
        try {
            record.other_policies = render_other_policies(in.plan, *in.scene->scene, out.run, out.result->policy, r.checkpoint_interval, scorer,
                                                          [&](std::string_view name) {
                                                              if (!quiet && r.format != "json")
                                                                  std::cerr << "crex run: rendering again under policy " << name << "\n";
                                                          });
        } catch (const std::exception& e) {
            std::cerr << "crex run: error: rendering under another policy failed: " << e.what() << "\n";
            return kExitFailure;
        }
    }
    if (r.equal_time) {  // uniform rendering given the pipeline's time, scored beside it when the files are written
        if (!quiet && r.format != "json")
            std::cerr << fmt::format("crex run: rendering uniformly in the same time ({:.2f} s)\n", out.result->render_seconds);
        record.equal_time = render_uniform_in_equal_time(*in.scene->scene, out.run.settings, out.result->render_seconds);
    }
    say_notes(out.result->notes);
    if (lead.resumed) say_resumed(*lead.resumed, out.run.settings, *out.result, std::cerr);
    std::cerr << render_text(out.result->warnings);
    WrittenRun written;
    if (std::string error = write_run_files(r.files, record, written); !error.empty()) {
        std::cerr << "crex run: error: " << error << "\n";
        return kExitFailure;
    }
    if (r.format == "json") {
        std::cout << written.summary.dump(2) << "\n";
        return kExitOk;
    }
    if (!r.quiet) print_run_summary(run_facts(r.files, record, &written), std::cout);
    if (!r.quiet && written.summary.contains("equal_time")) print_equal_time(written.summary["equal_time"], std::cout);
    return kExitOk;
}

}  // namespace

int run_command(const RunFlags& f) {
    Request r;
    if (auto exit = make_request(f, DistributedSession::leads(), r)) return *exit;  // said once under mpirun
    return run_request(r);
}

}  // namespace crex::app
