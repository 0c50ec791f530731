// `crex run`: execute a crex, a pipeline or a kept plan through the one render driver.
// The flags are defined here; run_command.cpp turns them into the library's typed options and
// runs them (runtime/api/).
#include <memory>

#include "apps/crex/cli_values.h"
#include "apps/crex/commands.h"
#include "apps/crex/run_command.h"
#include "apps/crex/run_flags.h"
#include "compiler/pipeline/stdlib_pipelines.h"

namespace crex::app {

Runner add_run_command(CLI::App& app) {
    auto opt = std::make_shared<RunFlags>();
    CLI::App* cmd = app.add_subcommand("run", "Render a scene with a crex on the component-bin renderer");
    cmd->add_option("plan", opt->plan, "A pipeline file (.pipe), a stdlib pipeline by name (sel_quiet: listed below), or a plan made by 'crex plan --format json' (instead of -e)");
    cmd->add_option("--scene", opt->scene, "Scene: file.json, file.rad, file.rif, file.obj, file.gltf, file.glb or builtin:NAME "
                                           "(default: the plan's, else builtin:cornell)");
    cmd->add_option("--view", opt->view, "A RADIANCE view file (-vp -vd -vu -vh -vv -vo, view types -vtv -vtl -vta -vth -vts -vtc) replacing the scene's camera, as rpict -vf");
    cmd->add_option("--camera", opt->camera, "One of the scene's named cameras, by NAME or INDEX from 0 (glTF files name theirs; "
                                             "default: the first)");
    CLI::Option* crex = cmd->add_option("-e,--crex", opt->crex, std::string("The crex saying in which order bins execute (default ") +
                                                kDefaultCrex + ")")
        ->allow_extra_args(false);
    CLI::Option* size = cmd->add_option("--size", opt->size, "Image size WIDTHxHEIGHT (default: the pipeline's image, else 256x256)");
    CLI::Option* spp = cmd->add_option("--spp", opt->spp, "Camera samples per pixel; of a pipeline, its preview's (default: the "
                                                          "pipeline's, else 16)")
                           ->check(whole_number_in(1, 1 << 20));
    cmd->add_option("-o,--output", opt->outputs, "Output image(s): .exr (float), .hdr, .png (tone-mapped); repeatable; the folder "
                                                 "must exist (default: the pipeline's output images, else out/render.exr and "
                                                 "out/render.png, whose folders are made)")
        ->allow_extra_args(false);
    cmd->add_flag("--components", opt->components, "EXR: add one layer per component AOV (camera, D, G, S, T, R, M); also "
                                                    "a pipeline's output { components true }");
    cmd->add_option("--threads", opt->threads, "Worker threads (default: all cores)")->check(whole_number_in(1, 1024));
    CLI::Option* seed = cmd->add_option("--seed", opt->seed, "Seed of every random number (0 to 2^53)")->capture_default_str()->check(seed_value());
    CLI::Option* shadow_rays = cmd->add_option("--shadow-rays", opt->shadow_rays, "Shadow rays per hit on a surface the camera sees, directly or through mirrors and glass (deeper hits take one); a pipeline's `preselective { shadow_rays N }` unless given")->capture_default_str()->check(whole_number_in(1, 1024));
    cmd->add_option("--media-samples", opt->media_samples, "Single-scatter samples along each camera ray, in a scene with a medium "
                                                           "(a pipeline's media_samples varies it per pixel)")
        ->capture_default_str()
        ->check(whole_number_in(1, 1024));
    CLI::Option* lw = cmd->add_option("--lw", opt->lw, "Weight limit: rays below it face Russian roulette")
        ->capture_default_str()
        ->check(number_in(0.0, 1.0));
    CLI::Option* max_depth = cmd->add_option("--max-depth", opt->max_depth, "No ray is spawned beyond this depth")->capture_default_str()->check(whole_number_in(0, 65535));
    cmd->add_flag("--no-roulette", opt->no_roulette, "Drop rays below --lw instead of Russian roulette (biased)");
    cmd->add_option("--clamp", opt->clamp, "Clamp every indirect contribution (a ray of D G S T R M, per camera sample) to at most L "
                                           "in its largest channel, keeping its hue: fewer fireflies, but biased (darker); off by default")
        ->check(number_in(1e-6, 1e30));
    cmd->add_option("--ambient", opt->ambient_text, "Ambient value av standing in for unexecuted D work "
                                                                           "(default 0), or 'auto': every unexecuted ray stands in "
                                                                           "with what its component's rays brought back on average "
                                                                           "(the default of pipelines)");
    cmd->add_option("--importance", opt->importance, "Constant importance I for '{ }' of a crex without guidance maps")
        ->capture_default_str()
        ->check(number_in(0.0, 1.0));
    cmd->add_option("--star-cap", opt->star_cap, "Iteration cap of '*' per entry (W401 when hit)")
        ->capture_default_str()
        ->check(whole_number_in(1, 4294967295.0));
    cmd->add_option("--budget", opt->budget, "Time budget: 10s, 500ms, or 25% of the full render time in --profile (along a camera path without "
                                              "one: of the first frame, rendered whole; docs/animation.md)")
        ->allow_extra_args(false);
    cmd->add_flag("--no-budget", opt->no_budget, "Ignore the pipeline's budget: render everything");
    cmd->add_option("--budget-floor", opt->budget_floor, "A budget below the pipeline's floor (its coarsest preview and guidance, "
                                                         "from --profile): refuse it naming the floor (exit 2), or ok: render anyway "
                                                         "and report it broken")
        ->capture_default_str()
        ->check(CLI::IsMember({"refuse", "ok"}));
    cmd->add_option("--preview-stride", opt->preview_stride, "A pipeline's preview at every K-th pixel of every K-th row, the others "
                                                             "interpolated for guidance and rendered by the selective stage (default: "
                                                             "1, or under a budget with --profile the K whose preview fits 15 % of it)")
        ->check(whole_number_in(1, 64));
    cmd->add_option("--ic-share", opt->ic_share, "Under mpirun with a cache, how ranks share it: none (each its own), central "
                                                 "(records go through rank 0, also during the render), broadcast (records go to "
                                                 "every rank after the preview and before each later round), component (the highest "
                                                 "max(1, N/4) ranks answer all irradiance queries with one cache, the others render "
                                                 "rows; deterministic for a fixed N)")
        ->capture_default_str()
        ->check(CLI::IsMember({"none", "central", "broadcast", "component"}));
    cmd->add_option("--rank-timeout", opt->rank_timeout, "Under mpirun: seconds a rank waits for another (for rank 0's inputs, "
                                                         "at an exchange of rows or records, for irradiance answers) before the run "
                                                         "is aborted naming it; rank 0 first writes the rows it finished to "
                                                         "NAME.partial.EXT beside each -o (--resume finishes them)")
        ->capture_default_str()
        ->check(number_in(0.1, 1e6));
    cmd->add_option("--resume", opt->resume, "Finish a run that failed under mpirun: NAME.partial.exr (the rows rank 0 finished) "
                                             "with the same inputs and options; only the other rows are rendered and -o gets the "
                                             "whole image (one process; not with a cache, a budget or subsample)")
        ->allow_extra_args(false);
    cmd->add_flag("--compare-policies", opt->compare_policies, "Under a budget with a reference: render again under every other "
                                                               "--policy and plot all their errors against time in the report");
    cmd->add_flag("--equal-time", opt->equal_time, "A pipeline with a reference: render uniformly (the default crex) in the pipeline's "
                                                   "render time and score both against the reference (FLIP, and aFLIP by the pipeline's "
                                                   "task map, else the reference's saliency); the report shows them side by side");
    cmd->add_option("--policy", opt->policy,
                    "How a budget is spent: tasks (whole components, thesis 5.4), batches (rays by pixel importance, 5.5), "
                    "queues (8.3: the next batch from the component whose rays bring the most light per second), progressive (whole passes); default: the pipeline's, else tasks for a "
                    "pipeline without vary, queues with, progressive for a plain crex")
        ->check(CLI::IsMember({"tasks", "batches", "queues", "progressive"}));
    cmd->add_option("--profile", opt->profile_in, "Profile (cost per ray per component) to predict from");
    cmd->add_option("--save-profile", opt->profile_out, "Write the measured profile (and this render's time) to FILE");
    cmd->add_option("--format", opt->format, "Summary as text or json (stdout)")->check(CLI::IsMember({"text", "json"}));
    cmd->add_flag("-q,--quiet", opt->quiet, "No progress and no summary");
    cmd->add_flag("-v,--verbose", opt->verbose, "Say first what the run will do: the scene as read, the plan, every setting in effect");
    cmd->add_option("--progress", opt->progress, "Progress on stderr: a redrawn line on a terminal (bar), a line every 10 s once past 5 s elsewhere (plain), or none; auto picks bar or plain")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "bar", "plain", "none"}));
    cmd->add_option("--reference", opt->reference, "Reference image to measure error against during the render (checkpoints), or "
                                                   "'auto' for the cached 'crex reference' of the scene at this size. With "
                                                   "--camera-path: a reference sequence (ref.exr: ref.0000.exr, ...), each frame it "
                                                   "has scored");
    cmd->add_option("--report", opt->report_dir, "Write a report to DIR: checkpoints (JSON, CSV), error plot (SVG), images, plan, "
                                                 "and one self-contained index.html (with --camera-path: time, flicker and error per "
                                                 "frame, the frames, the video). It replaces DIR whole, so DIR must be new, "
                                                 "empty or an earlier report");
    cmd->add_option("--checkpoint-interval", opt->checkpoint_interval, "Seconds between checkpoints within long steps (also at "
                                                                       "every step and stage boundary)")
        ->capture_default_str()
        ->check(number_in(1e-4, 1e6));
    cmd->add_option("--filter", opt->filter, "Pixel filter: box, or gaussian (sigma 0.5 px, radius 1.5, by filter importance sampling)")
        ->capture_default_str()
        ->check(CLI::IsMember({"box", "gaussian"}));
    cmd->add_flag("--ic", opt->ic, "Indirect diffuse (D) through a Ward irradiance cache instead of path tracing");
    CLI::Option* aa = cmd->add_option("--aa", opt->aa, "Irradiance cache accuracy (smaller is finer; a pipeline's ic_radius varies it per pixel)")
        ->capture_default_str()
        ->check(number_in(1e-3, 1.0));
    CLI::Option* ad = cmd->add_option("--ad", opt->ad, "Hemisphere rays per irradiance record (later bounces use ad/2^k, at least 16)")
        ->capture_default_str()
        ->check(whole_number_in(1, 65536));
    CLI::Option* ab = cmd->add_option("--ab", opt->ab, "Ambient bounces through the cache (then --ambient)")->capture_default_str()->check(whole_number_in(1, 64));
    cmd->add_option("--ar", opt->ar, "Irradiance cache resolution (RADIANCE -ar): records no closer than the scene's extent / ar; "
                                     "0 for the old floor, extent / 2000")
        ->capture_default_str()
        ->check(number_in(0.0, 1e6));
    cmd->add_option("--caustic-photons", opt->caustic_photons,
                    "Photons aimed at mirrors, glass and dielectrics for a caustic map: the light of lamps through them onto "
                    "diffuse surfaces, for the cache and for path tracing alike (0: found by rays, with fireflies)")
        ->capture_default_str()
        ->check(whole_number_in(0, 20000000));
    cmd->add_option("--ic-file", opt->ic_file, "Load the irradiance cache from FILE if it exists, save it there after the render (implies --ic)");
    cmd->add_option("--uniform", opt->uniform, "Every selective variable of a pipeline at its base (min) or its maximum (max) in "
                                               "every pixel, guidance skipped: max is the pipeline's own gold")
        ->capture_default_str()
        ->check(CLI::IsMember({"off", "min", "max"}));
    cmd->add_option("--rounds", opt->rounds, "Rounds of guidance and selective rendering (the cyclic process): each round "
                                             "recomputes the maps on the image so far (default: the pipeline's, else 1)")
        ->check(whole_number_in(1, 1024));
    cmd->add_option("--max-memory", opt->max_memory_mib, "Memory the render's sample passes are sized for, in MiB: camera samples "
                                                         "go in passes (or bands of rows) that fit")
        ->capture_default_str()
        ->check(number_in(64.0, 1048576.0));
    cmd->add_option("--pass-samples", opt->pass_samples, "At most this many samples per pixel in one pass (default: as many as "
                                                         "--max-memory allows)")
        ->check(whole_number_in(1, 1 << 20));
    cmd->add_option("--maps", opt->maps_dir, "Write every guidance map, the preview and per-pixel pictures (samples, rays, "
                                             "components) to DIR (default with 'output { maps true }': beside the image)");
    cmd->add_option("--camera-path", opt->camera_path, "Render frames along a camera path: a JSON path of keys (time, position, "
                                                       "look_at or direction, up, vfov) or a RADIANCE file of one view per line "
                                                       "(docs/animation.md); each -o NAME.EXT becomes NAME.0000.EXT, NAME.0001.EXT, ...")
        ->allow_extra_args(false);
    cmd->add_option("--frames", opt->frames, "The frames to render, FIRST..LAST[:STEP] (frame f at f / fps seconds on the path; "
                                             "default: every frame of the path); frames whose files exist are skipped; under mpirun each process "
                                             "renders a run of consecutive frames")
        ->allow_extra_args(false);
    cmd->add_option("--fps", opt->fps, "Frames per second along the camera path (a view file's line k is frame k at any fps)")
        ->capture_default_str()
        ->check(number_in(1e-3, 1e4));
    cmd->add_flag("--force", opt->force, "With --frames: render frames whose files exist too");
    cmd->add_flag("--no-carry-cache", opt->no_carry_cache, "With --frames: start every frame from an empty irradiance cache (or "
                                                           "the --ic-file's) instead of the frame before's: what carrying it saves");
    cmd->add_option("--reuse-frames", opt->reuse_frames, "With --frames: each frame inherits the one before's light where its pixels "
                                                         "see the same diffuse or glossy point, up to N frames' worth of its own samples, and takes that many "
                                                         "fewer of its own (at least one): faster frames, less flicker, a lag of up to N frames; implies "
                                                         "--seed-per-frame, but a pixel inheriting nothing (an outline) keeps its samples' places")
        ->check(number_in(0, 1e4));
    cmd->add_flag("--seed-per-frame", opt->seed_per_frame, "With --frames: new noise every frame (the seed mixed with the frame "
                                                           "number) instead of a noise pattern fixed to the screen");
    cmd->add_option("--high-quality-frames", opt->high_quality_frames,
                    "With a pipeline's --frames: these frames (FIRST..LAST[:STEP] or N, comma-separated) render at high quality, "
                    "every selective variable at its maximum (as --uniform max); the others selectively (the thesis's Case II)")
        ->allow_extra_args(false);
    cmd->add_option("--sequence-budget", opt->sequence_budget,
                    "With --frames: a time budget for the whole sequence (10s, 500ms; wall clock, each process its share's): "
                    "each frame gets what is left over the frames left, less a frame's set-up and writing as last measured")
        ->allow_extra_args(false);
    cmd->add_option("--video", opt->video,
                    "With --frames: also a preview video of the sequence (.mp4, .mov or .mkv; H.264 by ffmpeg, which must be "
                    "installed), made from the first -o image of every frame, at --fps")
        ->allow_extra_args(false);
    cmd->add_flag("--high-quality-without-distractors", opt->high_quality_without_distractors,
                  "With a pipeline's --frames: a frame that shows no shape tagged as an on-screen distractor renders at high "
                  "quality, one that shows one selectively (Case II: the distractor draws the eye)");
    cmd->footer([] { return R"(
Camera rays are traced first; then the crex runs over the component bins (D G S T R M) and
rays still waiting when it ends are dropped (--ambient stands in for waiting D rays).
A pipeline file (or its plan) runs all three stages: the preview at the base spp, the guidance
maps, then the selective pass with its variables per pixel (docs/guidance.md); --spp then sets
the preview's samples, and flags override the pipeline's settings.
)" + pipeline::stdlib_pipelines_said(); });  // when shown: the install moves the stdlib
    cmd->footer(R"(Examples:
  crex run                                          built-in Cornell box, (TTMRSGD)*, 256x256
  crex run -e 'TT' --spp 4 -o tt.png                direct light plus two glass interfaces
  crex run --scene examples/scenes/corridor/scene.json -e '(DGSTR)*' --size 320x240
  crex run -e '(TTMRSGD)*' --components -o out/cornell.exr   one EXR layer per component
  crex plan -e '(TTMRSGD)*' --scene S --format json -o p.json && crex run p.json   a kept plan
  crex run -e '(TT[RS]G)*D' --save-profile p.json            measure, then render in 25 % of the time:
  crex run -e '(TT[RS]G)*D' --profile p.json --budget 25%
  crex run sel_rp --maps out/maps                   the stdlib's saliency-driven rays per pixel, with its maps
  crex run examples/pipelines/cornell_prog.pipe              writes what its output { } block names
  crex run examples/pipelines/cornell_prog.pipe --size 128x128 --format json
  crex run --size 512x512 --resume out/render.partial.exr   finish a run that failed under mpirun
  crex run --scene examples/scenes/corridor/scene.json --camera-path examples/paths/corridor_walk.json \
      --frames 0..59 --ic --size 320x240 --spp 4 -o out/walk.png          a walk, NAME.0000.png to NAME.0059.png
  crex run prog_all --scene examples/scenes/corridor/scene.json \
      --camera-path examples/paths/corridor_walk.json --frames 0..59 --high-quality-without-distractors -o out/walk.png
                                                    Case II: frames without the poster on screen at high quality
  crex run prog_all --scene examples/scenes/corridor/scene.json \
      --camera-path examples/paths/corridor_walk.json --frames 0..59 --reuse-frames 8 -o out/walk.exr
                                                    each frame inherits up to 8 samples from the one before

Exit status: 0 ok or warnings only, 1 errors in the crex or scene, 2 usage, 3 I/O or runtime failure;
130 after Ctrl-C (143 after SIGTERM): the image so far as NAME.partial.EXT, or along a camera
path the finished frames (the same command goes on from them).)");
    return [opt, crex, size, spp, seed, lw, max_depth, aa, ab, ad, shadow_rays] {
        RunFlags o = *opt;
        o.crex_given = crex->count() > 0;
        o.aa_given = aa->count() > 0;
        o.ab_given = ab->count() > 0;
        o.ad_given = ad->count() > 0;
        o.shadow_rays_given = shadow_rays->count() > 0;
        o.seed_given = seed->count() > 0;
        o.lw_given = lw->count() > 0;
        o.max_depth_given = max_depth->count() > 0;
        o.size_given = size->count() > 0;
        o.spp_given = spp->count() > 0;
        return run_command(o);
    };
}

}  // namespace crex::app
