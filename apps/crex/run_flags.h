/// \file run_flags.h
/// The flags of `crex run` as the command line gives them (cmd_run.cpp defines them), with
/// which of them were given: a pipeline's settings apply unless a flag says otherwise
/// (spec/pipeline.md §7). run_command.cpp turns them into the library's typed options.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "compiler/sched/program.h"
#include "runtime/api/run_inputs.h"
#include "runtime/driver/run_plan.h"

namespace crex::app {

struct RunFlags {
    std::string plan;          ///< a .pipe file or a plan JSON
    std::string scene;
    std::string crex;
    bool crex_given = false;
    std::string size = "256x256";
    uint32_t spp = 16;
    std::vector<std::string> outputs;
    bool components = false;
    int threads = 0;
    uint64_t seed = 0;
    uint32_t shadow_rays = 1;
    uint32_t media_samples = 1;  ///< single-scatter samples per camera ray (scenes with a medium)
    double lw = 1e-3;
    uint32_t max_depth = 256;
    bool no_roulette = false;
    double clamp = 0;          ///< --clamp L: indirect contributions at most L (0: off; biased)
    std::string ambient_text;  ///< --ambient: a radiance, or "auto"
    double importance = 1;
    uint32_t star_cap = sched::kDefaultStarCap;
    std::string format = "text";
    bool quiet = false;
    bool verbose = false;  ///< -v: the inputs and settings in effect, before the render
    std::string progress = "auto";  ///< --progress auto|bar|plain|none
    std::string budget;
    bool no_budget = false;
    bool compare_policies = false;
    bool equal_time = false;
    std::string ic_share = "component";  ///< under mpirun with a cache: none, central, broadcast or component
    double rank_timeout = 600;  ///< under mpirun: seconds a rank waits for another before the run is aborted
    std::string resume;  ///< --resume NAME.partial.exr: render only the rows that file does not hold
    std::string policy;  ///< "" : the pipeline's, else the default
    std::string view;    ///< --view FILE.vf
    std::string camera;  ///< --camera NAME|INDEX (a scene's named cameras)
    std::string profile_in;
    std::string profile_out;
    std::string maps_dir;
    std::string reference;     ///< image path, or "auto": the cached `crex reference` of this scene and size
    std::string report_dir;
    double checkpoint_interval = 0.1;
    bool ic = false;
    double aa = 0.15;
    uint32_t ad = 256, ab = 8;  // ab 8: at 4, interiors lost their light beyond the 4th bounce (issue 14)
    uint32_t caustic_photons = 200000;
    double ar = 128;
    std::string ic_file;
    std::string filter = "box";
    std::string uniform = "off";
    double max_memory_mib = double(kDefaultMaxMemory >> 20);
    uint32_t pass_samples = 0;
    uint32_t rounds = 0;
    uint32_t preview_stride = 0;  ///< 0: every pixel, or under a budget what the profile sizes
    std::string budget_floor = "refuse";  ///< refuse | ok: render a budget below the pipeline's floor anyway
    std::string camera_path;  ///< --camera-path FILE: render frames along it
    std::string frames;       ///< --frames A..B[:STEP] ("": every frame of the path)
    double fps = 30;
    bool force = false;       ///< render frames whose files exist too
    bool no_carry_cache = false;
    double reuse_frames = 0;  ///< --reuse-frames N: frames' worth of its own samples a pixel may inherit
    bool seed_per_frame = false;  ///< --seed-per-frame: new noise every frame
    std::string high_quality_frames;          ///< --high-quality-frames A..B[:S],... (Case II)
    bool high_quality_without_distractors = false;  ///< --high-quality-without-distractors
    std::string sequence_budget;              ///< --sequence-budget TIME: the whole sequence's
    std::string video;                        ///< --video FILE: the sequence as a video (ffmpeg)
    // Which flags were given (they override the pipeline's settings).
    bool size_given = false, spp_given = false, seed_given = false, lw_given = false, max_depth_given = false,
         aa_given = false, ab_given = false, ad_given = false, shadow_rays_given = false;
};

}  // namespace crex::app
