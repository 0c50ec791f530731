// `crex compare`: how far an image is from a reference, by the metrics of spec §7.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <sstream>

#include "apps/crex/cli_values.h"
#include "apps/crex/commands.h"
#include "base/exit_codes.h"
#include "runtime/base/output_folder.h"
#include "runtime/api/equal_time.h"
#include "runtime/api/frame_sequence.h"
#include "runtime/api/sequence_flicker.h"
#include "runtime/io/heat_map.h"
#include "runtime/io/image_io.h"
#include "runtime/metrics/image_comparison.h"
#include "runtime/metrics/metrics.h"
#include "runtime/reference/windowed_image.h"

namespace crex::app {
namespace {

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

struct CompareOptions {
    std::string test, reference;
    std::string metrics = "rmse,relmse,ssim,flip,perr,fireflies";
    double perr_threshold = metrics::kDefaultPerrThreshold;
    double ppd = 67.0206;
    std::string flip_out;
    std::string attention;  ///< "saliency" or a map file: weights of the attention-weighted FLIP
    bool assume_display = false;  ///< compare a tone-mapped file with a linear one by tone-mapping the linear one
    double exposure = 0;          ///< --exposure: the tone map's exposure for both (0: the reference's)
    std::string format = "text";
    std::string frames;        ///< --frames A..B[:S]: TEST and REFERENCE name sequences
    bool flicker = false;      ///< --flicker: each sequence's flicker too
    std::string flicker_scene; ///< the scene to trace the frames in ("": their headers')
};

const std::vector<std::string> kMetricNames = {"rmse", "relmse", "ssim", "flip", "perr", "fireflies"};

// The metrics asked for; false (with the message said) for an unknown one.
bool metric_choice(const CompareOptions& opt, metrics::MetricChoice& choice) {
    std::stringstream list(opt.metrics);
    for (std::string m; std::getline(list, m, ',');) {
        if (std::find(kMetricNames.begin(), kMetricNames.end(), m) == kMetricNames.end()) {
            std::cerr << fmt::format("crex compare: error: unknown metric '{}': expected some of rmse,relmse,ssim,flip,perr,fireflies\n", m);
            return false;
        }
        (m == "rmse" ? choice.rmse : m == "relmse" ? choice.relmse : m == "ssim" ? choice.ssim : m == "flip" ? choice.flip
                                                                          : m == "perr" ? choice.perr : choice.fireflies) = true;
    }
    choice.perr_threshold = opt.perr_threshold;
    choice.pixels_per_degree = opt.ppd;
    choice.flip_map = !opt.flip_out.empty();
    return true;
}

// Reads an image for comparison; "" or why not (NaN or Inf make every metric 'nan' and the
// comparison say nothing, with exit 0: refused, exit 1).
int read_for_comparison(const std::string& path, metrics::Image& img, bool& ldr) {
    std::string error = read_image(path, img.width, img.height, img.rgb, &ldr);
    if (!error.empty()) {
        std::cerr << "crex compare: error: " << error << "\n";
        return kExitFailure;
    }
    size_t bad = 0;
    for (float v : img.rgb) bad += !std::isfinite(v);
    if (bad > 0) {
        std::cerr << fmt::format("crex compare: error: {} holds {} non-finite value{} (NaN or Inf): nothing to compare\n", path, bad,
                                 bad == 1 ? "" : "s");
        return kExitInputErrors;
    }
    return kExitOk;
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

int print_result(const CompareOptions& opt, const nlohmann::json& j, bool perceptual) {
    if (opt.format == "json") {
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    std::cout << fmt::format("{} against {} ({}x{})\n", opt.test, opt.reference, j["size"][0].get<int>(), j["size"][1].get<int>());
    if (j.contains("windows"))
        std::cout << fmt::format("  on {} windows of the {}x{} frame ({} pixels), {} spp\n", j["windows"].size(), j["frame"][0].get<int>(),
                                 j["frame"][1].get<int>(), j["pixels"].get<size_t>(), j["reference_spp"].get<uint32_t>());
    if (j.contains("rmse")) std::cout << fmt::format("  rmse    {:.6g}   (linear radiance)\n", j["rmse"].get<double>());
    if (j.contains("relmse")) std::cout << fmt::format("  relmse  {:.6g}   (mean of (t-r)^2/(r^2+0.01))\n", j["relmse"].get<double>());
    if (j.contains("ssim"))
        std::cout << (j["ssim"].is_null() ? std::string("  ssim    n/a (smaller than the 11x11 window)\n")
                                          : fmt::format("  ssim    {:.6f}   (1 = identical)\n", j["ssim"].get<double>()));
    if (j.contains("flip")) std::cout << fmt::format("  flip    {:.6f}   (mean LDR-FLIP, {:.1f} pixels per degree)\n", j["flip"].get<double>(), opt.ppd);
    if (j.contains("perr"))
        std::cout << fmt::format("  perr    {:.3f} %  (pixels with FLIP >= {:g}; not Daly's VDP)\n", j["perr"].get<double>(), opt.perr_threshold);
    if (j.contains("fireflies_per_mp"))
        std::cout << fmt::format("  fireflies {:.0f} / {:.0f} per megapixel (test / reference: over 10x their 3x3 median)\n",
                                 j["fireflies_per_mp"][0].get<double>(), j["fireflies_per_mp"][1].get<double>());
    if (j.contains("aflip"))
        std::cout << fmt::format("  aflip   {:.6f}   (FLIP weighted by {})\n", j["aflip"].get<double>(),
                                 opt.attention == "saliency" ? "the reference's saliency" : opt.attention);
    if (j.contains("windows"))
        for (const auto& w : j["windows"])
            std::cout << fmt::format("    window {:<20}{}{}\n", w["window"].dump(), w.contains("flip") ? fmt::format(" flip {:.6f}", w["flip"].get<double>()) : "",
                                     w.contains("aflip") ? fmt::format(" aflip {:.6f}", w["aflip"].get<double>()) : "");
    if (perceptual) std::cout << "  display: " << j["display"].get<std::string>() << "\n";
    if (!opt.flip_out.empty()) std::cout << "  wrote " << opt.flip_out << "\n";
    return kExitOk;
}

int write_flip_map(const std::string& path, int width, int height, const std::vector<float>& flip) {
    std::vector<double> values(flip.begin(), flip.end());
    ImageLayer layer{"", heat_colours(values, 1.0), true};
    std::string error = write_image(path, width, height, {layer});
    if (!error.empty()) {
        std::cerr << "crex compare: error: " << error << "\n";
        return kExitFailure;
    }
    return kExitOk;
}

// Against a windowed reference (issue 32): the test image's pixels at the windows (an image
// of the whole frame, or a windowed image with the same windows), each window compared as an
// image of its own, all seen through the whole frame's exposure the reference recorded.
int compare_on_windows(const CompareOptions& opt, const metrics::MetricChoice& choice, const ReferenceImage& ref) {
    const ReferenceHeader& h = ref.header;
    const WindowAtlas atlas(h.windows);
    metrics::Image test;
    bool test_ldr = false;
    if (int status = read_for_comparison(opt.test, test, test_ldr); status != kExitOk) return status;
    if (test_ldr) {
        std::cerr << fmt::format("crex compare: error: {} is display-referred (8-bit), but the windowed reference {} holds linear radiance: "
                                 "compare the render's linear image (.exr)\n", opt.test, opt.reference);
        return kExitInputErrors;
    }
    std::vector<float> test_atlas;
    std::optional<ReferenceImage> test_ref;
    if (test.width == h.frame_width && test.height == h.frame_height) {
        test_atlas = atlas.pack(test.rgb, test.width);
    } else if (read_reference_image(opt.test, test_ref).empty() && test_ref && test_ref->header.windows == h.windows &&
               test_ref->header.frame_width == h.frame_width && test_ref->header.frame_height == h.frame_height) {
        test_atlas = test.rgb;
    } else {
        std::cerr << fmt::format("crex compare: error: {} is {}x{}, but the reference {} holds windows of a {}x{} frame: compare an image of "
                                 "the whole frame (or a windowed reference with the same windows)\n",
                                 opt.test, test.width, test.height, opt.reference, h.frame_width, h.frame_height);
        return kExitInputErrors;
    }
    std::vector<float> weights;  // one a pixel of the atlas
    if (opt.attention == "saliency") {
        if (ref.attention.empty()) {
            std::cerr << fmt::format("crex compare: error: the windowed reference {} holds no saliency of its frame (layer '{}'): "
                                     "give the attention map as a file\n", opt.reference, kAttentionLayer);
            return kExitInputErrors;
        }
        weights = ref.attention;
    } else if (!opt.attention.empty()) {
        int w = 0, hgt = 0;
        std::vector<float> rgb;
        if (std::string error = read_image(opt.attention, w, hgt, rgb); !error.empty()) {
            std::cerr << "crex compare: error: " << error << "\n";
            return kExitFailure;
        }
        if (w != h.frame_width || hgt != h.frame_height) {
            std::cerr << fmt::format("crex compare: error: the attention map {} is {}x{} but the reference's frame is {}x{}\n", opt.attention, w,
                                     hgt, h.frame_width, h.frame_height);
            return kExitFailure;
        }
        std::vector<float> map(rgb.size() / 3);
        for (size_t i = 0; i < map.size(); ++i) map[i] = rgb[3 * i];
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
        std::cerr << fmt::format("crex compare: error: the attention map {} is zero at every window: nothing to weight by\n", opt.attention);
        return kExitInputErrors;
    }
    nlohmann::json j;
    j["test"] = opt.test;
    j["reference"] = opt.reference;
    j["size"] = {atlas.width, atlas.height};
    j["frame"] = {h.frame_width, h.frame_height};
    j["pixels"] = all.pixels;
    j["reference_spp"] = h.spp;
    j["display"] = fmt::format("HDR inputs tone-mapped with {} exposure {:.6g}, Reinhard, sRGB curve; each window compared as an image of its own",
                               opt.exposure > 0 ? "the given" : "the whole frame's", view.exposure);
    put_metrics(all, choice, j);
    if (!opt.attention.empty()) j["attention"] = opt.attention;
    j["windows"] = windows;
    if (!opt.flip_out.empty()) {
        if (int status = write_flip_map(opt.flip_out, atlas.width, atlas.height, flip_atlas); status != kExitOk) return status;
        j["flip_map"] = opt.flip_out;
    }
    return print_result(opt, j, choice.ssim || choice.flip || choice.perr);
}

// Two sequences frame by frame (issue 36): TEST and REFERENCE as `crex run -o` names them
// (walk.exr: walk.0000.exr, ...). Every frame of the range must be in the test sequence; a
// reference may hold some (a frame every tenth): the others have no error. With --flicker,
// each sequence's flicker from frame to frame, traced from the frames' own headers.
int compare_frames(const CompareOptions& opt, const metrics::MetricChoice& choice) {
    FrameRange range;
    if (std::string error = parse_frame_range(opt.frames, range); !error.empty()) {
        std::cerr << fmt::format("crex compare: error: --frames {}: {}\n", opt.frames, error);
        return kExitUsage;
    }
    std::vector<int64_t> frames = range.frames(), with_reference;
    std::vector<std::string> tests, references;
    for (int64_t f : frames) {
        tests.push_back(frame_file_name(opt.test, f));
        if (!std::filesystem::exists(tests.back())) {
            std::cerr << fmt::format("crex compare: error: frame {} of the test sequence, {}, does not exist\n", f, tests.back());
            return kExitFailure;
        }
        if (std::filesystem::exists(frame_file_name(opt.reference, f))) {
            with_reference.push_back(f);
            references.push_back(frame_file_name(opt.reference, f));
        }
    }
    if (references.empty() && !opt.flicker) {
        std::cerr << fmt::format("crex compare: error: no frame of {} .. {} has a reference ({} ...): nothing to compare\n", tests.front(),
                                 tests.back(), frame_file_name(opt.reference, frames.front()));
        return kExitFailure;
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
            if (int status = read_for_comparison(tests[i], test, test_ldr); status != kExitOk) return status;
            if (int status = read_for_comparison(ref_path, ref, ref_ldr); status != kExitOk) return status;
            if (test.width != ref.width || test.height != ref.height || test_ldr != ref_ldr) {
                std::cerr << fmt::format("crex compare: error: frame {}: {} is {}x{}{} but {} is {}x{}{}\n", frames[i], tests[i], test.width,
                                         test.height, test_ldr ? " (8-bit)" : "", ref_path, ref.width, ref.height, ref_ldr ? " (8-bit)" : "");
                return kExitInputErrors;
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
                std::cerr << fmt::format("crex compare: error: --flicker: {}\n", error);
                return kExitInputErrors;
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
    if (opt.format == "json") {
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    std::cout << fmt::format("{} against {}, frames {}..{}: {} with a reference\n", opt.test, opt.reference, frames.front(), frames.back(), scored);
    std::vector<std::string> keys;
    for (const char* k : {"rmse", "relmse", "ssim", "flip", "perr"})
        if (mean.contains(k)) keys.push_back(k);
    std::string head = "  frame";
    for (const auto& k : keys) head += fmt::format(" {:>10}", k);
    if (opt.flicker) head += fmt::format(" {:>10}", "flicker");
    std::cout << head << "\n";
    for (const auto& one : j["frames"]) {
        std::string line = fmt::format("  {:5d}", one["frame"].get<int64_t>());
        for (const auto& k : keys) line += one.contains(k) ? fmt::format(" {:>10.6f}", one[k].get<double>()) : fmt::format(" {:>10}", "-");
        if (opt.flicker)
            line += one.contains("flicker") ? fmt::format(" {:>10.6f}", one["flicker"]["display_difference"].get<double>()) : fmt::format(" {:>10}", "-");
        std::cout << line << "\n";
    }
    std::string line = "  mean ";
    for (const auto& k : keys) line += fmt::format(" {:>10.6f}", mean[k].get<double>());
    if (opt.flicker && j["flicker"].contains("test")) line += fmt::format(" {:>10.6f}", j["flicker"]["test"]["mean"].get<double>());
    std::cout << line << "\n";
    if (opt.flicker && j["flicker"].contains("reference"))
        std::cout << fmt::format("  the reference's own flicker: {:.6f} over {} frames\n", j["flicker"]["reference"]["mean"].get<double>(),
                                 j["flicker"]["reference"]["frames"].get<size_t>());
    if (opt.flicker)
        std::cout << "  flicker: mean display difference from the frame before, warped onto it through the scene "
                  << j["flicker"]["scene"].get<std::string>() << "\n";
    return kExitOk;
}

int compare(const CompareOptions& opt) {
    metrics::MetricChoice choice;
    if (!metric_choice(opt, choice)) return kExitUsage;
    if (opt.frames.empty() && (opt.flicker || !opt.flicker_scene.empty())) {
        std::cerr << "crex compare: error: --flicker is for sequences: give --frames A..B\n";
        return kExitUsage;
    }
    if (!opt.frames.empty()) {
        if (!opt.flip_out.empty() || !opt.attention.empty() || opt.assume_display) {
            std::cerr << "crex compare: error: --frames compares sequences: --flip-map, --attention and --assume-display are for one image\n";
            return kExitUsage;
        }
        return compare_frames(opt, choice);
    }
    if (std::string missing = opt.flip_out.empty() ? "" : missing_output_folder(opt.flip_out); !missing.empty()) {
        std::cerr << "crex compare: error: " << missing << "\n";  // before the work, as crex run says it
        return kExitFailure;
    }
    {
        std::optional<ReferenceImage> windowed;
        if (std::string error = read_reference_image(opt.reference, windowed); !error.empty() && error.find("header") != std::string::npos) {
            std::cerr << "crex compare: error: " << error << "\n";
            return kExitInputErrors;
        }
        if (windowed && !windowed->header.whole_frame()) return compare_on_windows(opt, choice, *windowed);
    }
    metrics::Image test, ref;
    bool test_ldr = false, ref_ldr = false;
    if (int status = read_for_comparison(opt.test, test, test_ldr); status != kExitOk) return status;
    if (int status = read_for_comparison(opt.reference, ref, ref_ldr); status != kExitOk) return status;
    if (test.width != ref.width || test.height != ref.height) {
        std::cerr << fmt::format("crex compare: error: {} is {}x{} but the reference {} is {}x{}\n", opt.test, test.width, test.height,
                                 opt.reference, ref.width, ref.height);
        return kExitInputErrors;
    }
    // A tone-mapped picture (PNG) and linear radiance (EXR) hold different things: comparing
    // them as they are tone-mapped the PNG a second time (perr 99.9 % for the same render).
    std::string display_note;
    if (test_ldr != ref_ldr) {
        const std::string& ldr = test_ldr ? opt.test : opt.reference;
        const std::string& hdr = test_ldr ? opt.reference : opt.test;
        if (!opt.assume_display) {
            std::cerr << fmt::format("crex compare: error: {} is display-referred (8-bit, already tone-mapped) but {} holds linear "
                                     "radiance: their values mean different things\n  = help: compare two linear files (.exr), or "
                                     "pass --assume-display to tone-map {} as crex writes PNGs and compare what a viewer sees\n",
                                     ldr, hdr, hdr);
            return kExitInputErrors;
        }
        // The linear one as crex would have written it as a PNG (its own exposure), kept as
        // linearised sRGB like an 8-bit file read back; then both are compared as stored.
        metrics::Image& lin = test_ldr ? ref : test;
        for (float& v : lin.rgb = to_display(lin.rgb, display_exposure(lin.rgb))) {
            double d = std::clamp(static_cast<double>(v), 0.0, 1.0);
            v = static_cast<float>(d <= 0.04045 ? d / 12.92 : std::pow((d + 0.055) / 1.055, 2.4));
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
            std::cerr << "crex compare: error: " << error << "\n";
            return kExitFailure;
        }
    }
    const metrics::ImageComparison c = metrics::compare_images(test, ref, view, choice, opt.attention.empty() ? nullptr : &weights);
    if (!opt.attention.empty() && !c.aflip) {
        std::cerr << fmt::format("crex compare: error: the attention map {} is zero everywhere: nothing to weight by\n", opt.attention);
        return kExitInputErrors;
    }
    nlohmann::json j;
    j["test"] = opt.test;
    j["reference"] = opt.reference;
    j["size"] = {ref.width, ref.height};
    j["display"] = display_note.empty() ? view.describe() : display_note;
    put_metrics(c, choice, j);
    if (!opt.attention.empty()) j["attention"] = opt.attention;
    if (!opt.flip_out.empty()) {
        if (int status = write_flip_map(opt.flip_out, ref.width, ref.height, c.flip_map); status != kExitOk) return status;
        j["flip_map"] = opt.flip_out;
    }
    return print_result(opt, j, choice.ssim || choice.flip || choice.perr);
}

}  // namespace

Runner add_compare_command(CLI::App& app) {
    auto opt = std::make_shared<CompareOptions>();
    CLI::App* cmd = app.add_subcommand("compare", "Measure how far an image is from a reference (RMSE, relMSE, SSIM, FLIP, perr)");
    cmd->add_option("test", opt->test, "The image to judge (any format OpenImageIO reads)")->required();
    cmd->add_option("reference", opt->reference, "The reference image, same size")->required();
    cmd->add_option("--metric", opt->metrics, "Comma-separated metrics: rmse,relmse,ssim,flip,perr,fireflies")->capture_default_str();
    cmd->add_option("--perr-threshold", opt->perr_threshold, "FLIP value from which a pixel counts as visibly different")
        ->capture_default_str()
        ->check(number_in(0.0, 1.0));
    cmd->add_option("--ppd", opt->ppd, "Pixels per degree of visual angle for FLIP")->capture_default_str()->check(number_in(1.0, 1000.0));
    cmd->add_option("--flip-map", opt->flip_out, "Write the per-pixel FLIP error as a picture (viridis, 0..1)");
    cmd->add_option("--attention", opt->attention,
                    "Also the attention-weighted FLIP (aflip): FLIP averaged with weights 'saliency' (of the reference) or from a map file (e.g. a task map)");
    cmd->add_option("--exposure", opt->exposure,
                    "Tone-map both HDR images with this exposure instead of the reference's (the key 0.18 over its log-average luminance)")
        ->check(number_in(1e-12, 1e12));
    cmd->add_flag("--assume-display", opt->assume_display,
                  "Compare a tone-mapped file (PNG) with a linear one (EXR) by tone-mapping the linear one as crex writes PNGs");
    cmd->add_option("--format", opt->format, "Output as text or json")->check(CLI::IsMember({"text", "json"}));
    cmd->add_option("--frames", opt->frames,
                    "Compare two sequences, FIRST..LAST[:STEP]: TEST and REFERENCE are names as crex run -o gives them (walk.exr: "
                    "walk.0000.exr, ...); frames without a reference file are listed without an error")
        ->allow_extra_args(false);
    cmd->add_flag("--flicker", opt->flicker,
                  "With --frames: each sequence's flicker, the mean display difference from the frame before warped onto it, "
                  "traced in the scene and views the frames' headers name");
    cmd->add_option("--flicker-scene", opt->flicker_scene, "With --flicker: trace the frames in this scene instead of their headers'");
    cmd->footer(R"(
RMSE and relMSE compare linear radiance. SSIM, FLIP and perr compare what a viewer sees:
LDR files (PNG, JPEG) as stored; HDR files (EXR, HDR) both through the tone map of spec
section 7 with the reference's exposure, and the output says so. One of each is refused
(exit 1): the PNG is already tone-mapped. --assume-display tone-maps the linear one as crex
writes PNGs (its own exposure) and compares the two as displayed.

A windowed reference ('crex reference --window'): the test is an image of the whole frame,
scored on the reference's windows alone, each window compared as an image of its own (the
same figures as 'crex compare' of the crops with --exposure E) and the figures combined over
all their pixels; both are tone-mapped with the whole frame's exposure E the reference
recorded, and --attention saliency weights by the whole frame's saliency it recorded. The
JSON lists each window's figures too.

Examples:
  crex compare out/sel_rp.exr out/gold.exr
  crex compare a.png b.png --metric flip,perr --flip-map flip.png
  crex compare a.exr ref.exr --format json
  crex compare a.exr ref.exr --attention saliency        FLIP where a viewer looks
  crex compare out/walk.exr refs/walk.exr --frames 0..59 --metric flip --flicker

Exit status: 0 compared, 1 images of different sizes or kinds, 2 usage, 3 an image cannot be read or written.)");
    return [opt] { return compare(*opt); };
}

}  // namespace crex::app
