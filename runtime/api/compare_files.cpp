#include "runtime/api/compare_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "base/exit_codes.h"
#include "runtime/api/equal_time.h"
#include "runtime/api/sequence_flicker.h"
#include "runtime/base/output_folder.h"
#include "runtime/io/heat_map.h"
#include "runtime/io/image_io.h"
#include "runtime/metrics/metrics.h"
#include "runtime/reference/windowed_image.h"

namespace crex {
namespace {

CompareOutcome fail(int status, std::string error) { return {status, std::move(error), {}}; }
CompareOutcome done(nlohmann::json result) { return {kExitOk, "", std::move(result)}; }

// Where a viewer looks, as weights per pixel: the Itti-Koch saliency of the reference as
// displayed, or a map from a file (a task map written by `crex run --maps`; its first channel).
std::string attention_weights(const std::string& source, const metrics::Image& reference_display, std::vector<float>& weights) {
    if (source == "saliency") {
        weights = saliency_weights(reference_display);
        return "";
    }
    int w = 0, h = 0;
    bool ldr = false;
    std::vector<float> rgb;
    std::string error = read_image(source, w, h, rgb, &ldr);
    if (!error.empty()) return error;
    if (w != reference_display.width || h != reference_display.height)
        return fmt::format("the attention map {} is {}x{} but the reference is {}x{}", source, w, h, reference_display.width,
                           reference_display.height);
    weights.resize(static_cast<size_t>(w) * static_cast<size_t>(h));
    for (size_t i = 0; i < weights.size(); ++i) weights[i] = rgb[3 * i];
    return "";
}

// "" when every weight of a map `width` pixels wide is finite and not negative, else what is
// wrong and where first: such a weight was silently dropped from the weighted mean.
std::string weight_map_problem(const std::string& source, const std::vector<float>& map, int width) {
    size_t bad = 0, first = 0;
    for (size_t i = 0; i < map.size(); ++i)
        if (!(std::isfinite(map[i]) && map[i] >= 0) && bad++ == 0) first = i;
    if (bad == 0) return "";
    const size_t w = static_cast<size_t>(std::max(width, 1));
    return fmt::format("the attention map {} holds {} weight{} that {} negative or not finite (NaN or Inf), the first at pixel ({}, {}) "
                       "with {}: a weight must be 0 or more",
                       source, bad, bad == 1 ? "" : "s", bad == 1 ? "is" : "are", first % w, first / w, map[first]);
}

// Reads an image for comparison; "" or why not (NaN or Inf make every metric 'nan' and the
// comparison say nothing, with exit 0: refused, exit 1).
CompareOutcome read_for_comparison(const std::string& path, metrics::Image& img, bool& ldr) {
    std::string error = read_image(path, img.width, img.height, img.rgb, &ldr);
    if (!error.empty()) {
        return fail(kExitFailure, error);
    }
    size_t bad = 0;
    for (float v : img.rgb) bad += !std::isfinite(v);
    if (bad > 0) {
        return fail(kExitInputErrors, fmt::format("{} holds {} non-finite value{} (NaN or Inf): nothing to compare", path, bad,
                                 bad == 1 ? "" : "s"));
    }
    return {};
}

// The metrics of `c` into `j` (as JSON keys), those asked for.
void put_metrics(const metrics::ImageComparison& c, const metrics::MetricChoice& choice, nlohmann::json& j) {
    if (choice.rmse && c.rmse) j["rmse"] = *c.rmse;
    if (choice.relmse && c.relmse) j["relmse"] = *c.relmse;
    if (choice.ssim) j["ssim"] = c.ssim ? nlohmann::json(*c.ssim) : nlohmann::json(nullptr);
    if (choice.flip && c.flip) j["flip"] = *c.flip;
    if (choice.perr && c.perr) {
        j["perr"] = *c.perr;
        j["perr_threshold"] = choice.perr_threshold;
    }
    if (c.aflip) j["aflip"] = *c.aflip;
    const double mp = static_cast<double>(c.pixels) / 1e6;  // fireflies per megapixel: test, reference
    if (c.test_fireflies && mp > 0) j["fireflies_per_mp"] = {static_cast<double>(*c.test_fireflies) / mp, static_cast<double>(*c.reference_fireflies) / mp};
}

CompareOutcome write_flip_map(const std::string& path, int width, int height, const std::vector<float>& flip) {
    std::vector<double> values(flip.begin(), flip.end());
    ImageLayer layer{"", heat_colours(values, 1.0), true};
    std::string error = write_image(path, width, height, {layer});
    if (!error.empty()) {
        return fail(kExitFailure, error);
    }
    return {};
}

// Against a windowed reference (issue 32): the test image's pixels at the windows (an image
// of the whole frame, or a windowed image with the same windows), each window compared as an
// image of its own, all seen through the whole frame's exposure the reference recorded.
CompareOutcome compare_on_windows(const CompareRequest& opt, const ReferenceImage& ref) {
    const metrics::MetricChoice& choice = opt.choice;
    const ReferenceHeader& h = ref.header;
    const WindowAtlas atlas(h.windows);
    metrics::Image test;
    bool test_ldr = false;
    if (CompareOutcome bad = read_for_comparison(opt.test, test, test_ldr); bad.status != kExitOk) return bad;
    if (test_ldr) {
        return fail(kExitInputErrors, fmt::format("{} is display-referred (8-bit), but the windowed reference {} holds linear radiance: "
                                 "compare the render's linear image (.exr)", opt.test, opt.reference));
    }
    std::vector<float> test_atlas;
    std::optional<ReferenceImage> test_ref;
    if (test.width == h.frame_width && test.height == h.frame_height) {
        test_atlas = atlas.pack(test.rgb, test.width);
    } else if (read_reference_image(opt.test, test_ref).empty() && test_ref && test_ref->header.windows == h.windows &&
               test_ref->header.frame_width == h.frame_width && test_ref->header.frame_height == h.frame_height) {
        test_atlas = test.rgb;
    } else {
        return fail(kExitInputErrors, fmt::format("{} is {}x{}, but the reference {} holds windows of a {}x{} frame: compare an image of "
                                 "the whole frame (or a windowed reference with the same windows)", opt.test, test.width, test.height, opt.reference, h.frame_width, h.frame_height));
    }
    std::vector<float> weights;  // one a pixel of the atlas
    if (opt.attention == "saliency") {
        if (ref.attention.empty()) {
            return fail(kExitInputErrors, fmt::format("the windowed reference {} holds no saliency of its frame (layer '{}'): "
                                     "give the attention map as a file", opt.reference, kAttentionLayer));
        }
        weights = ref.attention;
    } else if (!opt.attention.empty()) {
        int w = 0, hgt = 0;
        std::vector<float> rgb;
        if (std::string error = read_image(opt.attention, w, hgt, rgb); !error.empty()) {
            return fail(kExitFailure, error);
        }
        if (w != h.frame_width || hgt != h.frame_height) {
            return fail(kExitFailure, fmt::format("the attention map {} is {}x{} but the reference's frame is {}x{}", opt.attention, w,
                                     hgt, h.frame_width, h.frame_height));
        }
        std::vector<float> map(rgb.size() / 3);
        for (size_t i = 0; i < map.size(); ++i) map[i] = rgb[3 * i];
        if (std::string problem = weight_map_problem(opt.attention, map, w); !problem.empty()) return fail(kExitInputErrors, problem);
        weights = atlas.pack(map, w, 1);
    }
    const metrics::DisplayView view{true, opt.exposure > 0 ? opt.exposure : h.exposure > 0 ? h.exposure : display_exposure(ref.rgb)};
    std::vector<metrics::ImageComparison> parts;
    nlohmann::json windows = nlohmann::json::array();
    std::vector<float> flip_atlas(static_cast<size_t>(atlas.width) * static_cast<size_t>(atlas.height), 0.0f);
    for (size_t i = 0; i < h.windows.size(); ++i) {
        const PixelWindow& w = h.windows[i];
        const metrics::Image t{w.width, w.height, atlas.window(test_atlas, i)}, r{w.width, w.height, atlas.window(ref.rgb, i)};
        const std::vector<float> wi = weights.empty() ? std::vector<float>{} : atlas.window(weights, i, 1);
        parts.push_back(metrics::compare_images(t, r, view, choice, weights.empty() ? nullptr : &wi));
        nlohmann::json one;
        one["window"] = {w.x, w.y, w.width, w.height};
        put_metrics(parts.back(), choice, one);
        windows.push_back(one);
        for (int y = 0; y < w.height && !parts.back().flip_map.empty(); ++y)
            std::copy_n(parts.back().flip_map.begin() + static_cast<std::ptrdiff_t>(y) * w.width, w.width,
                        flip_atlas.begin() + static_cast<std::ptrdiff_t>(y) * atlas.width + atlas.column[i]);
    }
    const metrics::ImageComparison all = metrics::combine(parts);
    if (!weights.empty() && !all.aflip) {
        return fail(kExitInputErrors, fmt::format("the attention map {} is zero at every window: nothing to weight by", opt.attention));
    }
    nlohmann::json j;
    j["test"] = opt.test;
    j["reference"] = opt.reference;
    j["size"] = {atlas.width, atlas.height};
    j["frame"] = {h.frame_width, h.frame_height};
    j["pixels"] = all.pixels;
    j["reference_spp"] = h.spp;
    if (h.own_rmse > 0) j["reference_own_rmse"] = h.own_rmse;  // its own error, beside the test's rmse
    j["display"] = fmt::format("HDR inputs tone-mapped with {} exposure {:.6g}, Reinhard, sRGB curve; each window compared as an image of its own",
                               opt.exposure > 0 ? "the given" : "the whole frame's", view.exposure);
    put_metrics(all, choice, j);
    if (!opt.attention.empty()) j["attention"] = opt.attention;
    j["windows"] = windows;
    if (!opt.flip_map.empty()) {
        if (CompareOutcome bad = write_flip_map(opt.flip_map, atlas.width, atlas.height, flip_atlas); bad.status != kExitOk) return bad;
        j["flip_map"] = opt.flip_map;
    }
    return done(std::move(j));
}

// Two sequences frame by frame (issue 36): TEST and REFERENCE as `crex run -o` names them
// (walk.exr: walk.0000.exr, ...). Every frame of the range must be in the test sequence; a
// reference may hold some (a frame every tenth): the others have no error. With --flicker,
// each sequence's flicker from frame to frame, traced from the frames' own headers.
CompareOutcome compare_frames(const CompareRequest& opt) {
    const metrics::MetricChoice& choice = opt.choice;
    std::vector<int64_t> frames = opt.frames->frames(), with_reference;
    std::vector<std::string> tests, references;
    for (int64_t f : frames) {
        tests.push_back(frame_file_name(opt.test, f));
        if (!std::filesystem::exists(tests.back())) {
            return fail(kExitFailure, fmt::format("frame {} of the test sequence, {}, does not exist", f, tests.back()));
        }
        if (std::filesystem::exists(frame_file_name(opt.reference, f))) {
            with_reference.push_back(f);
            references.push_back(frame_file_name(opt.reference, f));
        }
    }
    if (references.empty() && !opt.flicker) {
        return fail(kExitFailure, fmt::format("no frame of {} .. {} has a reference ({} ...): nothing to compare", tests.front(),
                                 tests.back(), frame_file_name(opt.reference, frames.front())));
    }
    nlohmann::json list = nlohmann::json::array(), sums = nlohmann::json::object();
    size_t scored = 0;
    for (size_t i = 0; i < frames.size(); ++i) {
        nlohmann::json one = {{"frame", frames[i]}, {"test", tests[i]}};
        const auto r = std::find(with_reference.begin(), with_reference.end(), frames[i]);
        if (r != with_reference.end()) {
            const std::string& ref_path = references[static_cast<size_t>(r - with_reference.begin())];
            metrics::Image test, ref;
            bool test_ldr = false, ref_ldr = false;
            if (CompareOutcome bad = read_for_comparison(tests[i], test, test_ldr); bad.status != kExitOk) return bad;
            if (CompareOutcome bad = read_for_comparison(ref_path, ref, ref_ldr); bad.status != kExitOk) return bad;
            if (test.width != ref.width || test.height != ref.height || test_ldr != ref_ldr) {
                return fail(kExitInputErrors, fmt::format("frame {}: {} is {}x{}{} but {} is {}x{}{}", frames[i], tests[i], test.width,
                                         test.height, test_ldr ? " (8-bit)" : "", ref_path, ref.width, ref.height, ref_ldr ? " (8-bit)" : ""));
            }
            const metrics::DisplayView view{!(test_ldr && ref_ldr), opt.exposure > 0 ? opt.exposure : display_exposure(ref.rgb)};
            one["reference"] = ref_path;
            put_metrics(metrics::compare_images(test, ref, view, choice, nullptr), choice, one);
            for (auto& [key, value] : one.items())
                if (value.is_number() && key != "frame" && key != "perr_threshold") sums[key] = sums.value(key, 0.0) + value.get<double>();
            ++scored;
        }
        list.push_back(std::move(one));
    }
    nlohmann::json j = {{"test", opt.test}, {"reference", opt.reference}, {"frames", list}, {"scored", scored}};
    nlohmann::json mean = nlohmann::json::object();
    for (auto& [key, value] : sums.items()) mean[key] = value.get<double>() / static_cast<double>(scored);
    j["mean"] = mean;
    if (opt.flicker) {
        nlohmann::json flicker;
        for (const bool of_reference : {false, true}) {
            SequenceFlicker seq;
            const std::vector<int64_t>& numbers = of_reference ? with_reference : frames;
            if (std::string error = sequence_flicker(of_reference ? references : tests, numbers, opt.flicker_scene, seq); !error.empty()) {
                return fail(kExitInputErrors, fmt::format("--flicker: {}", error));
            }
            double sum = 0;
            size_t measured = 0;
            for (size_t i = 0; i < seq.frames.size(); ++i) {
                if (!seq.frames[i]) continue;
                sum += seq.frames[i]->difference, ++measured;
                if (!of_reference) j["frames"][i]["flicker"] = {{"display_difference", seq.frames[i]->difference}, {"matched", seq.frames[i]->matched}};
            }
            if (measured) flicker[of_reference ? "reference" : "test"] = {{"mean", sum / static_cast<double>(measured)}, {"frames", measured}};
            flicker["scene"] = seq.scene;
        }
        j["flicker"] = flicker;
    }
    return done(std::move(j));
}

}  // namespace

CompareOutcome compare_files(const CompareRequest& opt) {
    if (opt.frames) return compare_frames(opt);
    const metrics::MetricChoice& choice = opt.choice;
    if (std::string missing = opt.flip_map.empty() ? "" : missing_output_folder(opt.flip_map); !missing.empty()) {
        return fail(kExitFailure, missing);
    }
    {
        std::optional<ReferenceImage> windowed;
        if (std::string error = read_reference_image(opt.reference, windowed); !error.empty() && error.find("header") != std::string::npos) {
            return fail(kExitInputErrors, error);
        }
        if (windowed && !windowed->header.whole_frame()) return compare_on_windows(opt, *windowed);
    }
    metrics::Image test, ref;
    bool test_ldr = false, ref_ldr = false;
    if (CompareOutcome bad = read_for_comparison(opt.test, test, test_ldr); bad.status != kExitOk) return bad;
    if (CompareOutcome bad = read_for_comparison(opt.reference, ref, ref_ldr); bad.status != kExitOk) return bad;
    if (test.width != ref.width || test.height != ref.height) {
        return fail(kExitInputErrors, fmt::format("{} is {}x{} but the reference {} is {}x{}", opt.test, test.width, test.height,
                                 opt.reference, ref.width, ref.height));
    }
    // A tone-mapped picture (PNG) and linear radiance (EXR) hold different things: comparing
    // them as they are tone-mapped the PNG a second time (perr 99.9 % for the same render).
    std::string display_note;
    if (test_ldr != ref_ldr) {
        const std::string& ldr = test_ldr ? opt.test : opt.reference;
        const std::string& hdr = test_ldr ? opt.reference : opt.test;
        if (!opt.assume_display) {
            return fail(kExitInputErrors, fmt::format("{} is display-referred (8-bit, already tone-mapped) but {} holds linear "
                                     "radiance: their values mean different things\n  = help: compare two linear files (.exr), or "
                                     "pass --assume-display to tone-map {} as crex writes PNGs and compare what a viewer sees", ldr, hdr, hdr));
        }
        // The linear one as crex would have written it as a PNG (its own exposure), kept as
        // linearised sRGB like an 8-bit file read back; then both are compared as stored.
        metrics::Image& lin = test_ldr ? ref : test;
        for (float& v : lin.rgb = to_display(lin.rgb, display_exposure(lin.rgb))) {
            v = static_cast<float>(srgb_decode(std::clamp(static_cast<double>(v), 0.0, 1.0)));
        }
        test_ldr = ref_ldr = true;
        display_note = fmt::format("{} tone-mapped as crex writes PNGs (--assume-display), then both as stored (sRGB)", hdr);
    }
    // HDR if both images are: both are then seen through the reference's exposure (or --exposure).
    metrics::DisplayView view{!(test_ldr && ref_ldr), opt.exposure > 0 ? opt.exposure : display_exposure(ref.rgb)};
    std::vector<float> weights;
    if (!opt.attention.empty()) {
        std::string error = attention_weights(opt.attention, metrics::display_view(ref, view), weights);
        if (!error.empty()) {
            return fail(kExitFailure, error);
        }
        if (std::string problem = weight_map_problem(opt.attention, weights, ref.width); !problem.empty())
            return fail(kExitInputErrors, problem);
    }
    const metrics::ImageComparison c = metrics::compare_images(test, ref, view, choice, opt.attention.empty() ? nullptr : &weights);
    if (!opt.attention.empty() && !c.aflip) {
        return fail(kExitInputErrors, fmt::format("the attention map {} is zero everywhere: nothing to weight by", opt.attention));
    }
    nlohmann::json j;
    j["test"] = opt.test;
    j["reference"] = opt.reference;
    j["size"] = {ref.width, ref.height};
    j["display"] = display_note.empty() ? view.describe() : display_note;
    put_metrics(c, choice, j);
    if (!opt.attention.empty()) j["attention"] = opt.attention;
    if (!opt.flip_map.empty()) {
        if (CompareOutcome bad = write_flip_map(opt.flip_map, ref.width, ref.height, c.flip_map); bad.status != kExitOk) return bad;
        j["flip_map"] = opt.flip_map;
    }
    return done(std::move(j));
}

}  // namespace crex
