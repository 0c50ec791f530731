#include "runtime/api/frame_sequence.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <cstring>
#include <memory>
#include <sstream>
#include <tuple>
#include <type_traits>

#include "runtime/api/frame_flicker.h"
#include "runtime/api/frame_reuse.h"
#include "runtime/api/frame_writer.h"
#include "runtime/driver/process_group.h"
#include "runtime/base/file_extension.h"
#include "runtime/base/sampling.h"
#include "runtime/io/image_io.h"
#include "runtime/metrics/image_comparison.h"
#include "runtime/texture/surface_textures.h"

namespace crex {
namespace {

// 13850 -> "13,850": counts people read at a glance.
std::string grouped(uint64_t n) {
    std::string digits = std::to_string(n), out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

// A frame's own seed (--seed-per-frame, --reuse-frames): the run's seed and the frame's number
// mixed, kept to the 53 bits a seed may have everywhere it is written (JSON, --seed), so a frame
// can be redone alone.
uint64_t frame_seed(uint64_t seed, int64_t frame) {
    return hash_combine(seed, static_cast<uint64_t>(frame)) & ((uint64_t{1} << 53) - 1);
}

// A frame's time on the path.
double frame_time(int64_t frame, double fps) { return double(frame) / fps; }

// A pixel centre sees a shape tagged as an on-screen distractor.
bool shows_a_distractor(const Scene& scene, const FrameGeometry& g) {
    for (const int32_t shape : g.shape)
        if (shape >= 0 && static_cast<size_t>(shape) < scene.shapes.size()) {
            const auto& tag = scene.shapes[static_cast<size_t>(shape)].tag;
            if (tag && tag->distractor) return true;
        }
    return false;
}

// The scene's camera as it was, whatever happens to the frames.
struct CameraRestore {
    Scene& scene;
    Camera saved;
    ~CameraRestore() { scene.camera = saved; }
};

// Scores `f` against its frame of `reference`, if that exists (checked before rendering:
// check_sequence_reference), through the reference's exposure as `crex compare` does.
void score_against_reference(FrameRun& f, const std::string& reference, const std::vector<float>& image, int width, int height) {
    const std::string path = frame_file_name(reference, f.frame);
    std::error_code ec;
    if (reference.empty() || !std::filesystem::exists(path, ec)) return;
    metrics::Image ref, test{width, height, image};
    if (std::string error = read_image(path, ref.width, ref.height, ref.rgb); !error.empty())
        throw FrameWriteError(fmt::format("frame {}: its reference: {}", f.frame, error));
    if (ref.width != width || ref.height != height)
        throw FrameWriteError(fmt::format("frame {}: its reference {} is {}x{}, the frame {}x{}", f.frame, path, ref.width, ref.height, width, height));
    metrics::MetricChoice choice;
    choice.flip = choice.relmse = true;
    const metrics::ImageComparison c = metrics::compare_images(test, ref, {true, display_exposure(ref.rgb)}, choice);
    f.flip = c.flip, f.relmse = c.relmse, f.reference = path;
}

// A restart's first frame inherits from the finished frame before it, read back from its
// file (EXR or HDR: a PNG holds display values, not light), every pixel counted at the cap,
// as nearly every pixel of a walk is after a frame or two: so a restarted walk goes on as it
// would have. Nothing when the file is not linear light of the frame's size.
std::optional<PixelHistory> history_from_file(const std::string& file, int width, int height, float frames) {
    const std::string ext = lower_extension(file);
    if (ext != ".exr" && ext != ".hdr") return std::nullopt;
    PixelHistory h;
    int w = 0, ht = 0;
    if (!read_image(file, w, ht, h.rgb).empty() || w != width || ht != height) return std::nullopt;
    h.weight.assign(static_cast<size_t>(w) * static_cast<size_t>(ht), frames);
    h.frames = frames;
    for (size_t p = 0; p < h.weight.size(); ++p)
        for (size_t c = 0; c < 3; ++c)
            if (!std::isfinite(h.rgb[3 * p + c])) h.weight[p] = 0;
    return h;
}

}  // namespace

std::string stopped_sequence_text(const std::vector<FrameRun>& frames, size_t total) {
    const auto rendered = std::count_if(frames.begin(), frames.end(), [](const FrameRun& f) { return !f.skipped; });
    return fmt::format("interrupted: {} of {} frames finished ({} rendered now); the frame under way was not written, and the same "
                       "command goes on from it",
                       frames.size(), total, rendered);
}

std::string check_sequence_reference(const std::string& reference, const FrameRange& range, int width, int height, bool& bad_pixels) {
    bad_pixels = false;
    size_t found = 0;
    for (int64_t frame : range.frames()) {
        const std::string path = frame_file_name(reference, frame);
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) continue;
        const std::string ext = lower_extension(path);
        if (ext != ".exr" && ext != ".hdr")
            return fmt::format("{} is not linear radiance: a reference sequence is EXR or HDR files (crex run --camera-path ... --spp 256 -o ref.exr makes one)", path);
        int w = 0, h = 0;
        ImageMetadata metadata;
        if (std::string error = read_image_metadata(path, w, h, metadata); !error.empty()) return error;
        if (w != width || h != height) return fmt::format("{} is {}x{}, the frames {}x{}", path, w, h, width, height);
        // Its pixels too, before any frame is rendered: a NaN would make the frame's FLIP and
        // relative MSE NaN, which the report and the JSON can only show as missing.
        std::vector<float> rgb;
        if (std::string error = read_image(path, w, h, rgb); !error.empty()) return error;
        if (const size_t bad = static_cast<size_t>(std::count_if(rgb.begin(), rgb.end(), [](float v) { return !std::isfinite(v); })); bad > 0)
            return bad_pixels = true, fmt::format("{} holds {} non-finite value{} (NaN or Inf): no error can be measured against it", path, bad,
                                                 bad == 1 ? "" : "s");
        ++found;
    }
    if (found == 0)
        return fmt::format("no frame of {} .. {} exists (looked for {} ...)", range.first, range.last, frame_file_name(reference, range.first));
    return "";
}

std::string parse_frame_range(const std::string& text, FrameRange& range) {
    const std::string expected = "expected FIRST..LAST or FIRST..LAST:STEP (whole frame numbers from 0, e.g. 0..59 or 0..59:2), or one frame";
    // Whole numbers only, of at most 7 digits: up to kMaxFrame, over three days in at 30 fps.
    auto whole = [](const std::string& s, int64_t& v, int64_t lo) {
        if (s.empty() || s.size() > 7 || s.find_first_not_of("0123456789") != std::string::npos) return false;
        v = std::stoll(s);
        return v >= lo;
    };
    std::string span = text;
    range.step = 1;
    if (size_t colon = text.find(':'); colon != std::string::npos) {
        span = text.substr(0, colon);
        if (!whole(text.substr(colon + 1), range.step, 1)) return expected + "; STEP from 1";
    }
    const size_t dots = span.find("..");
    if (dots == std::string::npos) {
        if (!whole(span, range.first, 0)) return expected;
        range.last = range.first;
        return "";
    }
    if (!whole(span.substr(0, dots), range.first, 0) || !whole(span.substr(dots + 2), range.last, 0)) return expected;
    if (range.last < range.first) return fmt::format("the last frame {} is before the first {}", range.last, range.first);
    return "";
}

std::string parse_frame_ranges(const std::string& text, std::vector<FrameRange>& ranges) {
    std::string item;
    for (std::istringstream list(text); std::getline(list, item, ',');) {
        FrameRange range;
        if (std::string error = parse_frame_range(item, range); !error.empty()) return fmt::format("'{}': {}", item, error);
        ranges.push_back(range);
    }
    return "";
}

std::vector<int64_t> FrameRange::frames() const {
    std::vector<int64_t> out;
    for (int64_t f = first; f <= last && step > 0; f += step) out.push_back(f);
    return out;
}

FrameRange path_frames(const CameraPath& path, double fps) {
    // Times of whole frames within the span, allowing for the division's rounding at its ends.
    // Clamped in double before the conversion: a path ending at 1e308 s has an infinite last
    // frame, which as an integer was undefined (INT64_MIN here: "0 frames", exit 0).
    const double slack = 1e-9, top = static_cast<double>(kMaxFrame + 1);
    auto frame = [top](double f) { return static_cast<int64_t>(std::isnan(f) ? top : std::clamp(f, -top, top)); };
    FrameRange r;
    r.first = frame(std::ceil(path.start_time() * fps - slack));
    r.last = frame(std::floor(path.end_time() * fps + slack));
    return r;
}

std::string check_path_frames(const CameraPath& path, double fps) {
    const FrameRange all = path_frames(path, fps);
    if (all.last < all.first)
        return fmt::format("the camera path runs from {:g} s to {:g} s, which holds no whole frame at {:g} fps (frame f is at f / fps s): "
                           "give a higher --fps or a longer path",
                           path.start_time(), path.end_time(), fps);
    if (all.last > kMaxFrame)
        return fmt::format("the camera path runs to {:g} s, past frame {} at {:g} fps: give --frames (at most {}) or a lower --fps",
                           path.end_time(), kMaxFrame, fps, kMaxFrame);
    return "";
}

std::string check_frame_range(const FrameRange& range, const CameraPath& path, double fps) {
    const FrameRange on = path_frames(path, fps);
    if (range.first >= on.first && range.last <= on.last) return "";
    return fmt::format("frames {}..{} are not all on the camera path: at {:g} fps it has frames {}..{} ({:g} s to {:g} s)", range.first,
                       range.last, fps, on.first, on.last, path.start_time(), path.end_time());
}

std::string check_path_cameras(const CameraPath& path, double fps, const FrameRange& range, const Scene& scene) {
    const SceneBox box = scene_box(scene);
    for (const int64_t frame : range.frames())
        if (std::string problem = camera_problem(path.camera_at(frame_time(frame, fps), scene.camera), box); !problem.empty())
            return fmt::format("frame {}: the camera is {}", frame, problem);
    return "";
}

std::string sequence_frames(const CameraPath& path, double fps, const std::optional<FrameRange>& given, FrameRange& out) {
    if (!given) {
        out = path_frames(path, fps);
        return check_path_frames(path, fps);
    }
    out = *given;
    const std::string off_path = check_frame_range(out, path, fps);
    return off_path.empty() ? "" : "--frames: " + off_path;
}

std::string frame_file_name(const std::string& path, int64_t frame) {
    const std::filesystem::path p(path);
    return (p.parent_path() / fmt::format("{}.{:04d}{}", p.stem().string(), frame, p.extension().string())).string();
}

double frame_budget(double total, double spent, double overhead, size_t frames_left, size_t frames) {
    const double least = total / static_cast<double>(std::max<size_t>(1, frames)) * 1e-3;
    if (frames_left == 0) return least;
    const double share = (total - spent) / static_cast<double>(frames_left) - std::max(0.0, overhead);
    return std::isfinite(share) ? std::max(share, least) : least;
}

std::pair<size_t, size_t> frame_share(size_t frames, int processes, int index) {
    const size_t p = static_cast<size_t>(std::max(1, processes)), i = static_cast<size_t>(std::clamp(index, 0, std::max(1, processes) - 1));
    return {frames * i / p, frames * (i + 1) / p};
}

std::vector<FrameRun> render_frames(RunInputs& in, const ResolvedRun& run, const RunFiles& files, const SequenceOptions& o,
                                    RunObserver& observer, const std::function<void(const FrameRun&, size_t, size_t)>& done,
                                    ProcessGroup* group) {
    LocalGroup alone;
    ProcessGroup& processes = group ? *group : alone;
    Scene& scene = *in.scene->scene;
    CameraRestore restore{scene, scene.camera};
    const Camera scene_camera = scene.camera;
    const std::vector<int64_t> frames = o.frames.frames();
    const auto [first_index, end_index] = frame_share(frames.size(), processes.processes(), processes.process_index());
    std::vector<FrameRun> out;
    // Each frame is said once, on the lead: its own as they end, the others' as they arrive.
    size_t heard = 0;
    auto hear = [&](const std::string& bytes) {
        const nlohmann::json j = nlohmann::json::parse(bytes);
        out.push_back(frame_from_json(j));
        ++heard;
        if (done) done(out.back(), j.at("index").get<size_t>(), frames.size());
    };
    auto frame_done = [&](size_t index) {
        if (!processes.leads()) {
            processes.tell_lead(frame_to_json(out.back(), index).dump(), fmt::format("what frame {} did", out.back().frame));
            return;
        }
        if (done) done(out.back(), index, frames.size());
        while (auto bytes = processes.heard_by_lead(false, "what a frame did")) hear(*bytes);
    };
    // What every frame starts from: the sequence's cache (a file's bytes, records given), then
    // each frame's records when carried. The file is read once: later frames only save to it,
    // and only the lead's frames (one process writes the file).
    ResolvedRun next = run;
    if (!processes.leads()) next.settings.ic_file.clear();
    next.settings.hand_on_ic_grids = o.carry_cache;  // a frame's lookup grids go on with its records
    // A sequence budget is wall clock: what this process has spent since its first frame.
    const auto sequence_start = std::chrono::steady_clock::now();
    double spent = 0, overhead = 0;
    std::optional<ProfileInput> carried_profile;  // a budget in % of the first frame (SequenceOptions::budget_of_first_frame)
    // Several processes carrying caches share them (the thesis's broadcast, 6.2): after each
    // step of their shares, every process's new records go to every other, so that a process
    // starting in the middle of the walk soon holds what the others made. One exchange per
    // step of the longest share, every process taking part in each.
    size_t most_frames = 0;
    for (int p = 0; p < processes.processes(); ++p) {
        const auto [first, end] = frame_share(frames.size(), processes.processes(), p);
        most_frames = std::max(most_frames, end - first);
    }
    const bool share_caches = processes.processes() > 1 && o.carry_cache && next.settings.irradiance_cache.has_value();
    auto share_records = [&](const std::vector<IrradianceRecord>& mine) {
        if (!share_caches) return;
        static_assert(std::is_trivially_copyable_v<IrradianceRecord>);
        const std::string bytes(reinterpret_cast<const char*>(mine.data()), mine.size() * sizeof(IrradianceRecord));
        const std::vector<std::string> all = processes.all_share(bytes, "the exchange of a frame's irradiance records");
        for (size_t p = 0; p < all.size(); ++p) {
            if (static_cast<int>(p) == processes.process_index()) continue;
            const size_t n = all[p].size() / sizeof(IrradianceRecord);
            const size_t at = next.settings.ic_records.size();
            next.settings.ic_records.resize(at + n);
            std::memcpy(static_cast<void*>(next.settings.ic_records.data() + at), all[p].data(), n * sizeof(IrradianceRecord));
        }
    };
    // The scene built once (nothing but the camera moves) for every frame: its BVH, lights and
    // texture bindings (a walk of the textured living room built them again at every frame:
    // 0.05 s of set-up a frame). Flicker and inheritance trace what each pixel centre sees in
    // it, and warp the frame before onto the next.
    // Building it may make tiled copies of large textures (a minute for a 30000x30000 PNG): said
    // as the first frame's "setup", as a single render says it.
    std::shared_ptr<RenderScene> probe_scene;
    RunProgress setup_line;
    auto built_scene = [&] {
        if (!probe_scene)
            probe_scene = std::make_shared<RenderScene>(scene, texture_cache_bytes(next.settings.max_memory), setup_progress(observer, setup_line));
        return probe_scene;
    };
    std::optional<FrameGeometry> previous_geometry;
    std::vector<float> previous_image;  // display values
    // --reuse-frames: the frame before's light and sample counts, and which shapes inherit.
    const bool reusing = o.reuse_frames > 0;
    std::optional<PixelHistory> previous_history;
    std::vector<char> inherits;
    double exposure = 0;                // the first frame rendered sets it for all
    FrameWriter writer(files.images);
    for (size_t index = first_index; index < end_index; ++index) {
        // Asked to stop (Ctrl-C; one process only: the others would wait for its records at the
        // next exchange): the next frame is not begun.
        if (processes.processes() == 1 && observer.stop_requested()) break;
        FrameRun f;
        f.frame = frames[index];
        f.time = frame_time(f.frame, o.fps);
        RunFiles frame_files;
        frame_files.components = files.components;
        for (const std::string& image : files.images) frame_files.images.push_back(frame_file_name(image, f.frame));
        f.files = frame_files.images;
        std::error_code ec;
        f.skipped = !o.force && !f.files.empty() &&
                    std::all_of(f.files.begin(), f.files.end(), [&](const std::string& p) { return std::filesystem::exists(p, ec); });
        std::vector<IrradianceRecord> made;  // this frame's records, for the other processes
        if (f.skipped) {
            previous_geometry.reset();
            previous_history.reset();
            out.push_back(f);
            frame_done(index);
            share_records({});
            continue;
        }
        spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - sequence_start).count();
        // The scene, built by the first frame rendered and on its clock (its set-up).
        const auto before_scene = std::chrono::steady_clock::now();
        next.settings.render_scene = built_scene();
        const double scene_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - before_scene).count();
        if (reusing && !previous_history && index > first_index && out.back().skipped && !out.back().files.empty()) {
            // Restarted: the finished frame before is read back, and what it saw traced again.
            if ((previous_history = history_from_file(out.back().files.front(), next.settings.width, next.settings.height, o.reuse_frames))) {
                scene.camera = o.path->camera_at(out.back().time, scene_camera);
                previous_geometry = frame_geometry(*built_scene(), next.settings.width, next.settings.height);
            }
        }
        scene.camera = o.path->camera_at(f.time, scene_camera);
        // What the frame's pixel centres see: for its flicker and its distractors (not counted
        // in the frame's time: one ray a pixel, in a scene built once), and for the light it
        // inherits (counted: the frame needs it).
        const auto before_geometry = std::chrono::steady_clock::now();
        std::optional<FrameGeometry> geometry;
        if (o.flicker || o.high_quality_without_distractors || reusing) {
            geometry = frame_geometry(*built_scene(), next.settings.width, next.settings.height);
        }
        next.settings.history.reset();
        // Each frame its own samples when it inherits: with the seed of the frame before, a
        // pixel's new samples would repeat the pattern its inherited ones were drawn from, and
        // the camera's motion would drag that fixed pattern across the surfaces as streaks. A
        // pixel that inherits nothing (an outline) keeps frame 0's places in the pixel instead:
        // drawn anew, its blend of two surfaces jumped from frame to frame.
        next.settings.seed = reusing || o.seed_per_frame ? frame_seed(run.settings.seed, f.frame) : run.settings.seed;
        if (reusing && !o.new_positions_every_frame) next.settings.position_seed = frame_seed(run.settings.seed, 0);
        if (reusing && previous_history && previous_geometry) {
            if (inherits.empty()) inherits = shapes_that_inherit(scene);
            const std::vector<PixelTaps> from = previous_taps(*previous_geometry, *geometry, probe_scene->embree->origin_offset());
            auto history = std::make_shared<PixelHistory>(inherited_history(*previous_history, from, geometry->shape, inherits, o.reuse_frames));
            std::tie(f.inherited_pixels, f.inherited_samples) = inherited_share(*history);
            next.settings.history = std::move(history);
        }
        const double reuse_seconds = reusing ? std::chrono::duration<double>(std::chrono::steady_clock::now() - before_geometry).count() : 0;
        f.high_quality = std::any_of(o.high_quality.begin(), o.high_quality.end(), [&](const FrameRange& r) { return r.contains(f.frame); });
        if (o.high_quality_without_distractors) {
            f.distractor_on_screen = shows_a_distractor(scene, *geometry);
            f.high_quality = f.high_quality || !*f.distractor_on_screen;
        }
        next.settings.uniform = f.high_quality ? UniformQuality::kMax : run.settings.uniform;
        if (o.budget_seconds > 0) {
            f.budget_seconds = frame_budget(o.budget_seconds, spent, overhead, end_index - index, end_index - first_index);
            next.settings.executor.budget_seconds = f.budget_seconds;
        } else if (carried_profile) {
            f.budget_seconds = next.budget_seconds;
        }
        const auto start = std::chrono::steady_clock::now();
        f.records_reused = next.settings.ic_records.size() + (next.settings.ic_grids ? next.settings.ic_grids->records.size() : 0);
        LocalGroup one;
        // The run takes its settings by value; the carried records are not in them but in
        // ic_grids (shared, moved into the frame's cache), so nothing large is copied.
        RunOutcome outcome = run_resolved(in.plan, scene, next, one, observer);
        const RunResult& result = *outcome.result;
        if (result.stopped && processes.processes() == 1) break;  // stopped during the frame: not finished, so not written
        f.records_reused += result.ic_loaded;
        f.records_made = result.ic_stats.records;
        f.rays = total_rays(result.stats);
        f.render_seconds = result.render_seconds;
        f.setup_seconds = result.setup_seconds + scene_seconds;
        f.preview_seconds = result.preview_seconds, f.guidance_seconds = result.guidance_seconds, f.selective_seconds = result.selective_seconds;
        f.warnings = result.warnings;
        f.notes = result.notes;
        RunRecord record;
        record.inputs = &in;
        record.outcome = &outcome;
        record.plan_file = o.plan_file;
        record.frame = f.frame;
        // Its files written while the next frame renders; the wait for the frame before's is
        // part of this frame's time.
        RunImages images = run_images(frame_files, record);
        // The final image, composited once for the files and for what follows (each composite
        // blends the history: 7-10 ms a frame at 320x240).
        const std::vector<float> linear = reusing || o.flicker || !o.reference.empty() ? images.layers.front().rgb : std::vector<float>{};
        writer.write(f.frame, std::move(images));
        if (reusing) {  // what the next frame inherits: this one's image and counts (timed: the frame's work)
            const auto t = std::chrono::steady_clock::now();
            previous_history = history_of(linear, result.film, result.history.get());
            f.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
        }
        f.seconds += scene_seconds + reuse_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // A frame's set-up and writing, the least seen since the first (whose own holds one-time
        // costs, 0.33 s against 0.05 s on the corridor); what is spent corrects the rest.
        const double frame_overhead = std::max(0.0, f.seconds - f.render_seconds);
        if (index > first_index) overhead = index == first_index + 1 ? frame_overhead : std::min(overhead, frame_overhead);
        // Scored after the frame's time is taken: not part of it.
        score_against_reference(f, o.reference, linear, next.settings.width, next.settings.height);
        if (o.flicker) {
            if (!(exposure > 0)) exposure = display_exposure(linear);
            std::vector<float> image = to_display(linear, exposure);
            if (previous_geometry)
                if (auto flicker = frame_flicker(*previous_geometry, previous_image, *geometry, image, probe_scene->embree->origin_offset())) {
                    f.flicker = flicker->difference;
                    f.flicker_matched = flicker->matched;
                }
            previous_image = std::move(image);
        }
        if (geometry) previous_geometry = std::move(*geometry);
        // The caustic map does not depend on the camera: every frame after takes this one's.
        next.settings.caustic_map = outcome.result->caustic_map;
        if (o.budget_of_first_frame) {  // the first frame's full time, every frame's measurements
            if (!carried_profile)
                carried_profile = ProfileInput{outcome.measured, result.render_seconds,
                                               measured_stage_costs(result, next.settings.width, next.settings.height), "the first frame"};
            else
                carried_profile->profile = outcome.measured;
            RunOptions options = *o.budget_of_first_frame;
            options.profile = carried_profile;
            options.budget_floor_ok = true;  // a sequence under way is not stopped: the frame is rendered and said to break it
            resolve_budget(next, in.plan, options);  // the budget, its profile and the preview's stride only
        }
        // The next frame starts from this one's cache, never from the file again (it holds
        // this frame's records now: --ic-file saves after every frame).
        next.settings.ic_file_read = false;
        if (o.carry_cache && next.settings.irradiance_cache) {
            // The records and their lookup grids, handed on together (moved: nothing copied).
            std::shared_ptr<IcGrids> handed = std::move(outcome.result->ic_grids);
            if (!handed) handed = std::make_shared<IcGrids>();
            handed->records = std::move(outcome.result->ic_records);
            handed->handed = handed->records.size();
            next.settings.ic_grids = handed;
            next.settings.ic_records.clear();
            next.settings.ic_file_bytes.reset();
            // The frame's own records are the cache's last (those it started with come first).
            const std::vector<IrradianceRecord>& records = handed->records;
            const size_t own = std::min<size_t>(result.ic_stats.records, records.size());
            made.assign(records.end() - static_cast<std::ptrdiff_t>(own), records.end());
        }
        out.push_back(std::move(f));
        frame_done(index);
        share_records(made);
    }
    writer.finish();  // the last frame's files: in the sequence's time, not in a frame's
    // A process with a shorter share takes part in the last exchange too.
    for (size_t step = end_index - first_index; step < most_frames; ++step) share_records({});
    if (!processes.leads()) processes.told_lead("what this process's frames did");
    if (processes.leads()) {  // the other processes' frames, each said as it arrives
        const size_t others = frames.size() - (end_index - first_index);
        while (heard < others)
            if (auto bytes = processes.heard_by_lead(true, "what a frame of its share did")) hear(*bytes);
        std::stable_sort(out.begin(), out.end(), [](const FrameRun& a, const FrameRun& b) { return a.frame < b.frame; });
    }
    return out;
}

nlohmann::json frame_json(const FrameRun& f) {
    nlohmann::json j = {{"frame", f.frame}, {"time", f.time}, {"skipped", f.skipped}, {"files", f.files}};
    if (f.skipped) return j;
    j["seconds"] = f.seconds;
    j["render_seconds"] = f.render_seconds;
    j["stages"] = {{"setup_seconds", f.setup_seconds}, {"preview_seconds", f.preview_seconds}, {"guidance_seconds", f.guidance_seconds},
                   {"selective_seconds", f.selective_seconds}};
    j["records_made"] = f.records_made;
    j["records_reused"] = f.records_reused;
    j["rays"] = f.rays;
    if (f.inherited_pixels > 0) j["inherited"] = {{"pixels", f.inherited_pixels}, {"samples", f.inherited_samples}};
    if (f.flicker) j["flicker"] = {{"display_difference", *f.flicker}, {"matched", f.flicker_matched}};
    j["quality"] = f.high_quality ? "high" : "selective";
    if (f.distractor_on_screen) j["distractor_on_screen"] = *f.distractor_on_screen;
    if (f.budget_seconds > 0) j["budget_seconds"] = f.budget_seconds;
    if (f.flip) j["error"] = {{"flip", *f.flip}, {"relmse", f.relmse ? nlohmann::json(*f.relmse) : nlohmann::json(nullptr)}, {"reference", f.reference}};
    return j;
}

nlohmann::json frame_to_json(const FrameRun& f, size_t index) {
    nlohmann::json j = frame_json(f);
    j["index"] = index;
    nlohmann::json warnings = nlohmann::json::array();
    for (const Diagnostic& w : f.warnings) warnings.push_back({{"code", w.code}, {"where", w.where}, {"message", w.message}, {"help", w.help}});
    j["warnings"] = std::move(warnings);
    j["notes"] = f.notes;
    return j;
}

FrameRun frame_from_json(const nlohmann::json& j) {
    FrameRun f;
    f.frame = j.at("frame").get<int64_t>();
    f.time = j.at("time").get<double>();
    f.skipped = j.at("skipped").get<bool>();
    f.files = j.at("files").get<std::vector<std::string>>();
    f.notes = j.value("notes", std::vector<std::string>{});
    for (const auto& w : j.value("warnings", nlohmann::json::array())) {
        f.warnings.push_back(run_diagnostic(w.at("code").get<std::string>(), w.at("where").get<std::string>(), w.at("message").get<std::string>()));
        f.warnings.back().help = w.value("help", "");
    }
    if (f.skipped) return f;
    f.seconds = j.at("seconds").get<double>();
    f.render_seconds = j.at("render_seconds").get<double>();
    if (j.contains("stages")) {
        const nlohmann::json& st = j["stages"];
        f.setup_seconds = st.value("setup_seconds", 0.0), f.preview_seconds = st.value("preview_seconds", 0.0);
        f.guidance_seconds = st.value("guidance_seconds", 0.0), f.selective_seconds = st.value("selective_seconds", 0.0);
    }
    f.records_made = j.at("records_made").get<size_t>();
    f.records_reused = j.at("records_reused").get<size_t>();
    f.rays = j.at("rays").get<uint64_t>();
    if (j.contains("inherited")) {
        f.inherited_pixels = j["inherited"].at("pixels").get<double>();
        f.inherited_samples = j["inherited"].at("samples").get<double>();
    }
    if (j.contains("flicker")) {
        f.flicker = j["flicker"].at("display_difference").get<double>();
        f.flicker_matched = j["flicker"].at("matched").get<double>();
    }
    f.high_quality = j.value("quality", "") == "high";
    if (j.contains("distractor_on_screen")) f.distractor_on_screen = j["distractor_on_screen"].get<bool>();
    f.budget_seconds = j.value("budget_seconds", 0.0);
    if (j.contains("error")) {
        f.flip = j["error"].at("flip").get<double>();
        if (!j["error"].at("relmse").is_null()) f.relmse = j["error"]["relmse"].get<double>();
        f.reference = j["error"].at("reference").get<std::string>();
    }
    return f;
}

nlohmann::json frames_json(const std::vector<FrameRun>& frames, double fps) {
    nlohmann::json list = nlohmann::json::array();
    size_t rendered = 0;
    double seconds = 0;
    uint64_t made = 0;
    for (const FrameRun& f : frames) {
        nlohmann::json j = frame_json(f);
        if (!f.skipped) {
            ++rendered;
            seconds += f.seconds;
            made += f.records_made;
        }
        list.push_back(std::move(j));
    }
    return {{"fps", fps}, {"frames", std::move(list)}, {"rendered", rendered}, {"skipped", frames.size() - rendered},
            {"seconds", seconds}, {"records_made", made}};
}

std::string frame_line(const FrameRun& f, size_t index, size_t count) {
    const std::string head = fmt::format("frame {}/{} ({:04d})", index + 1, count, f.frame);
    if (f.skipped) return head + ": skipped, its files exist (--force renders it again)";
    std::string line = fmt::format("{}: {:.2f} s", head, f.seconds);
    if (f.budget_seconds > 0) line += fmt::format(" (render budget {:.2f} s, rendered {:.2f} s)", f.budget_seconds, f.render_seconds);
    if (f.high_quality) line += f.distractor_on_screen ? ", high quality (no distractor on screen)" : ", high quality";
    if (f.records_made || f.records_reused)
        line += fmt::format(", {} new records, {} reused", grouped(f.records_made), grouped(f.records_reused));
    if (f.inherited_pixels > 0)
        line += fmt::format(", {:.0f} % of pixels inherited {:.1f} samples", 100 * f.inherited_pixels, f.inherited_samples);
    if (f.flicker) line += fmt::format(", flicker {:.4f} ({:.0f} % of pixels matched)", *f.flicker, 100 * f.flicker_matched);
    if (f.flip) line += fmt::format(", FLIP {:.4f} against its reference", *f.flip);
    return line;
}

static std::string frames_summary_body(const std::vector<FrameRun>& frames) {
    std::vector<const FrameRun*> rendered;
    for (const FrameRun& f : frames)
        if (!f.skipped) rendered.push_back(&f);
    const size_t skipped = frames.size() - rendered.size();
    std::string text = fmt::format("{} frame{}: {} rendered, {} skipped{}\n", frames.size(), frames.size() == 1 ? "" : "s",
                                   rendered.size(), skipped, skipped ? " (their files existed)" : "");
    if (rendered.empty()) return text;
    const FrameRun& first = *rendered.front();
    text += fmt::format("  first frame rendered ({:04d}): {:.2f} s, {} records made\n", first.frame, first.seconds, grouped(first.records_made));
    if (rendered.size() > 1) {
        double seconds = 0, made = 0;
        for (size_t i = 1; i < rendered.size(); ++i) seconds += rendered[i]->seconds, made += double(rendered[i]->records_made);
        const double n = double(rendered.size() - 1);
        text += fmt::format("  the other {}: {:.2f} s and {} records made per frame on average{}\n", rendered.size() - 1, seconds / n,
                            grouped(static_cast<uint64_t>(std::llround(made / n))),
                            seconds > 0 ? fmt::format(" ({:.1f}x faster than the first)", first.seconds / (seconds / n)) : "");
    }
    double flicker = 0;
    size_t measured = 0;
    for (const FrameRun* f : rendered)
        if (f->flicker) flicker += *f->flicker, ++measured;
    if (measured)
        text += fmt::format("  flicker (mean display difference from the frame before, warped onto it): {:.4f} on average over {} frame{}\n",
                            flicker / double(measured), measured, measured == 1 ? "" : "s");
    const FrameRun& last = *rendered.back();
    for (size_t k = 0; k < first.files.size() && k < last.files.size(); ++k)  // one line per -o, not per frame
        text += first.frame == last.frame ? fmt::format("  wrote {}\n", first.files[k])
                                          : fmt::format("  wrote {} .. {}\n", first.files[k], last.files[k]);
    return text;
}

std::string frames_summary_text(const std::vector<FrameRun>& frames, double budget_seconds, double took, int processes) {
    std::string text = frames_summary_body(frames);
    if (budget_seconds > 0)
        text += fmt::format("  sequence budget {:.2f} s: took {:.2f} s ({:+.1f} %)\n", budget_seconds, took, 100 * (took / budget_seconds - 1));
    if (processes > 1)
        text += fmt::format("  on {} processes, each a run of consecutive frames, their caches' new records shared after each frame\n", processes);
    return text;
}

}  // namespace crex
