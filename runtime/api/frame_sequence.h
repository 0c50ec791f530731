/// \file frame_sequence.h
/// A sequence of frames along a camera path (issue 36, docs/animation.md): frame f is the
/// render with the path's camera at time f / fps, written to `NAME.%04d.EXT` for every image
/// `NAME.EXT` of the run, each frame's files all or none. A frame whose files all exist is
/// skipped (a sequence stopped half way restarts where it stopped) unless `force`. The
/// irradiance cache is carried from frame to frame in the process: the records of a static
/// scene do not depend on the camera, so a frame only makes the records its new view lacks.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "runtime/api/run.h"
#include "runtime/api/run_inputs.h"
#include "runtime/api/run_outputs.h"
#include "runtime/driver/process_group.h"
#include "runtime/scene/camera_path.h"

namespace crex {

/// Frames first, first + step, ... up to last (inclusive).
struct FrameRange {
    int64_t first = 0, last = 0, step = 1;
    std::vector<int64_t> frames() const;
    bool contains(int64_t frame) const { return step > 0 && frame >= first && frame <= last && (frame - first) % step == 0; }
};

/// "FIRST..LAST", "FIRST..LAST:STEP" or one frame "N" (`--frames`); "" or what is wrong.
std::string parse_frame_range(const std::string& text, FrameRange& range);
/// Ranges separated by commas (`--high-quality-frames 0..9,20`); "" or what is wrong, with the item.
std::string parse_frame_ranges(const std::string& text, std::vector<FrameRange>& ranges);

/// The largest frame number: `--frames` takes at most seven digits (frame 9,999,999 at 30 fps
/// is over three days in), and a sequence's frames are listed in memory.
inline constexpr int64_t kMaxFrame = 9'999'999;

/// The frames a path at `fps` covers: those whose time f / fps lies within its keys' span,
/// the last no later than kMaxFrame + 1 (a longer path, or one whose end overflows, says so
/// there rather than through an integer out of range).
FrameRange path_frames(const CameraPath& path, double fps);

/// "" when a sequence can render every frame of the path at `fps` (what it renders without
/// `--frames`), else what is wrong: it holds no whole frame, or more than kMaxFrame.
std::string check_path_frames(const CameraPath& path, double fps);

/// The frames a sequence renders into `out`: `given` (`--frames`) when set, each on the path,
/// else every frame of the path (check_path_frames). "" or what is wrong.
std::string sequence_frames(const CameraPath& path, double fps, const std::optional<FrameRange>& given, FrameRange& out);

/// "" when every frame of `range` is on the path at `fps`, else what is wrong (with the
/// frames the path has).
std::string check_frame_range(const FrameRange& range, const CameraPath& path, double fps);

/// "" when the camera of every frame in `range` can view `scene` (camera_problem: finite, and
/// within float rays' reach of the scene), else the first frame that cannot and why. A path's
/// keys can be anywhere its file allows; the scene decides how far is too far.
std::string check_path_cameras(const CameraPath& path, double fps, const FrameRange& range, const Scene& scene);

/// `out/walk.png`, 7 -> `out/walk.0007.png` (more digits past 9999).
std::string frame_file_name(const std::string& path, int64_t frame);

struct SequenceOptions {
    const CameraPath* path = nullptr;
    FrameRange frames;
    double fps = 30;
    bool force = false;        ///< render frames whose files exist too
    bool carry_cache = true;   ///< false: every frame starts from the cache the sequence started with
    std::string plan_file;     ///< the pipeline or plan file run, for the images' headers ("" for a crex)
    bool flicker = true;       ///< measure each frame's flicker against the frame rendered before it (frame_flicker.h)
    /// Case II of the thesis (4.5): frames tagged high quality render with every selective
    /// variable at its maximum (as `--uniform max`), the others selectively. Tagged by range,
    /// and, with `high_quality_without_distractors`, every frame that shows no shape tagged
    /// as an on-screen distractor (where nothing draws the eye away, the viewer would see
    /// what selective rendering leaves out).
    std::vector<FrameRange> high_quality;
    bool high_quality_without_distractors = false;
    /// A time budget for the whole sequence, wall clock (0: none; each process has all of it
    /// for its share of the frames): each frame's budget is frame_budget().
    double budget_seconds = 0;
    /// A budget in % without a profile to take it of (`--budget 25%` and no --profile): the
    /// first frame each process renders renders whole, and its profile (its full time, its
    /// stages, and every later frame's measurements folded in) sizes each later frame's
    /// budget, as the thesis's profile spans an animation (5.4). The options the budget is
    /// resolved from (their budget, floor rule, stride); unset: none.
    std::optional<RunOptions> budget_of_first_frame;
    /// A reference sequence named as `-o` names frames (ref.exr: ref.0000.exr, ...): each
    /// frame it has is scored against (FLIP and relMSE, through the reference's exposure, as
    /// `crex compare` does). "" for none; check_sequence_reference() before rendering.
    std::string reference;
    /// `--reuse-frames N` (frame_reuse.h): every frame after the first inherits the one
    /// before's light where its pixels see the same point, up to N frames' worth of the
    /// pixel's own samples, and takes that many fewer of its own (at least one, and at least
    /// a (N + 1)th of what it asks for). 0: none; each frame renders alone.
    float reuse_frames = 0;
    /// `--seed-per-frame`: each frame its own seed (the run's and the frame number mixed), so
    /// its noise is new every frame rather than a pattern fixed to the screen that the scene
    /// moves behind. Always so for frames that inherit (reuse_frames): their own samples must
    /// not repeat the ones they inherit. A frame's seed depends on its number alone, so a frame
    /// rendered by itself is the frame of the walk.
    bool seed_per_frame = false;
    /// With reuse_frames: a pixel that inherits nothing draws its samples at new positions in
    /// every frame too, as before RunSettings::position_seed (for comparing the two; no flag).
    bool new_positions_every_frame = false;
};

/// "" when `reference` (SequenceOptions::reference) has at least one frame of `range`, each
/// of them a linear image (EXR or HDR) of width x height with finite pixels; else what is
/// wrong, and `bad_pixels` true when that is a frame's NaN or Inf (an input error, where the
/// rest are files missing or unreadable).
std::string check_sequence_reference(const std::string& reference, const FrameRange& range, int width, int height, bool& bad_pixels);

/// A frame's render budget under a sequence budget of `total` seconds: what is left after
/// the `spent` seconds of the frames before, over the `frames_left` (this one included), less
/// `overhead` (a frame's set-up and writing, as the last frame measured it); at least a
/// thousandth of an even share, so that a late sequence still renders each frame's preview.
double frame_budget(double total, double spent, double overhead, size_t frames_left, size_t frames);

/// What one frame did.
struct FrameRun {
    int64_t frame = 0;
    double time = 0;             ///< on the path, seconds
    bool skipped = false;        ///< its files existed
    double seconds = 0;          ///< the whole frame: scene set-up, render, files written
    double render_seconds = 0;   ///< from its first camera ray
    /// Of those: set-up (scene, BVH, caustic map) and a pipeline's stages (0 for a plain crex).
    double setup_seconds = 0, preview_seconds = 0, guidance_seconds = 0, selective_seconds = 0;
    size_t records_reused = 0;   ///< cache records it started with (carried, or from the cache file)
    size_t records_made = 0;
    uint64_t rays = 0;
    /// The share of pixels that inherited samples from the frame before (reuse_frames), and
    /// their mean inherited count.
    double inherited_pixels = 0, inherited_samples = 0;
    /// Mean display difference from the frame rendered just before it, warped onto this one
    /// (frame_flicker.h), and the fraction of pixels that could be matched; none for the first
    /// frame rendered, after a skipped one, or where no pixel matched.
    std::optional<double> flicker;
    double flicker_matched = 0;
    bool high_quality = false;                  ///< rendered as `--uniform max` (SequenceOptions::high_quality)
    std::optional<bool> distractor_on_screen;   ///< looked for (high_quality_without_distractors)
    std::vector<std::string> files;
    double budget_seconds = 0;          ///< its render budget under a sequence budget (0: none)
    /// Against its frame of SequenceOptions::reference, where that has one.
    std::optional<double> flip, relmse;
    std::string reference;
    std::vector<Diagnostic> warnings;   ///< the frame's runtime warnings
    std::vector<std::string> notes;     ///< and notes (RunResult::notes)
};

/// A frame's files could not be written; the frames before it are kept.
struct FrameWriteError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The frames [first, end) of a sequence of `frames` that process `index` of `processes`
/// renders: contiguous shares of (nearly) equal length, so that each process's cache carries
/// from a frame to its neighbour, and its flicker is measured between neighbours.
std::pair<size_t, size_t> frame_share(size_t frames, int processes, int index);

/// Renders the frames of `options` with `run`'s settings, each frame's images in
/// `files.images` renamed by frame_file_name() (only images: maps, reports and profiles are
/// not per frame yet). `in`'s scene camera is set per frame and restored before returning.
/// `observer` watches each frame's render; `done(frame, index, count)` is called after each
/// frame, skipped ones too. With `group` (several processes, e.g. under mpirun), each process
/// renders its frame_share() whole, carrying its own cache; the lead alone saves the cache
/// file, hears of every frame (`done` there is called for all, as they end) and returns them
/// all, the others return their own. When `observer` asks to stop (Ctrl-C in one process),
/// the frame under way is left out, not written: the frames returned are the finished ones,
/// whose files are whole, and the same command goes on from there. Throws what run_resolved()
/// throws, and FrameWriteError.
std::vector<FrameRun> render_frames(RunInputs& in, const ResolvedRun& run, const RunFiles& files, const SequenceOptions& options,
                                    RunObserver& observer,
                                    const std::function<void(const FrameRun&, size_t index, size_t count)>& done = nullptr,
                                    ProcessGroup* group = nullptr);

/// What a sequence of `total` frames that was stopped (render_frames) says of the finished
/// `frames`: how many, how many of them rendered now, and that the same command goes on.
std::string stopped_sequence_text(const std::vector<FrameRun>& frames, size_t total);

/// One frame as `--format json` gives it.
nlohmann::json frame_json(const FrameRun& f);
/// One frame as a process tells the lead (frame_json with its index in the sequence, its
/// warnings and notes), and back.
nlohmann::json frame_to_json(const FrameRun& f, size_t index);
FrameRun frame_from_json(const nlohmann::json& j);

/// The sequence as `--format json` gives it: per frame its seconds, records made and reused,
/// rays and files; with totals.
nlohmann::json frames_json(const std::vector<FrameRun>& frames, double fps);

/// "frame 3/60 (0007): 0.66 s, 1,147 new records, 13,850 reused": a frame's progress line.
std::string frame_line(const FrameRun& f, size_t index, size_t count);

/// A summary for people: frames rendered and skipped, the first frame against the mean of
/// the rest, records made; the sequence's budget against the time it `took` when it had one
/// (`budget_seconds` > 0), and the processes it ran on when more than one.
std::string frames_summary_text(const std::vector<FrameRun>& frames, double budget_seconds = 0, double took = 0, int processes = 1);

}  // namespace crex
