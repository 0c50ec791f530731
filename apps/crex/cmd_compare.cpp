// `crex compare`: how far an image is from a reference, by the metrics of spec §7.
#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <sstream>

#include "apps/crex/cli_values.h"
#include "apps/crex/commands.h"
#include "base/exit_codes.h"
#include "runtime/api/compare_files.h"

namespace crex::app {
namespace {

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

int print_result(const CompareOptions& opt, const nlohmann::json& j, bool perceptual) {
    std::cout << fmt::format("{} against {} ({}x{})\n", opt.test, opt.reference, j["size"][0].get<int>(), j["size"][1].get<int>());
    if (j.contains("windows"))
        std::cout << fmt::format("  on {} windows of the {}x{} frame ({} pixels), {} spp\n", j["windows"].size(), j["frame"][0].get<int>(),
                                 j["frame"][1].get<int>(), j["pixels"].get<size_t>(), j["reference_spp"].get<uint32_t>());
    if (j.contains("rmse")) std::cout << fmt::format("  rmse    {:.6g}   (linear radiance)\n", j["rmse"].get<double>());
    if (j.contains("reference_own_rmse"))
        std::cout << fmt::format("          the reference's own, estimated: {:.3g}\n", j["reference_own_rmse"].get<double>());
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

// Two sequences frame by frame: a row per frame, the means, each sequence's flicker.
int print_frames(const CompareOptions& opt, const nlohmann::json& j) {
    const auto& frames = j["frames"];
    const auto& mean = j["mean"];
    std::cout << fmt::format("{} against {}, frames {}..{}: {} with a reference\n", opt.test, opt.reference, frames.front()["frame"].get<int64_t>(),
                             frames.back()["frame"].get<int64_t>(), j["scored"].get<size_t>());
    std::vector<std::string> keys;
    for (const char* k : {"rmse", "relmse", "ssim", "flip", "perr"})
        if (mean.contains(k)) keys.push_back(k);
    std::string head = "  frame";
    for (const auto& k : keys) head += fmt::format(" {:>10}", k);
    if (opt.flicker) head += fmt::format(" {:>10}", "flicker");
    std::cout << head << "\n";
    for (const auto& one : frames) {
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
    CompareRequest request{opt.test, opt.reference, {}, opt.attention, opt.flip_out, opt.exposure, opt.assume_display, std::nullopt,
                           opt.flicker, opt.flicker_scene};
    if (!metric_choice(opt, request.choice)) return kExitUsage;
    if (opt.frames.empty() && (opt.flicker || !opt.flicker_scene.empty())) {
        std::cerr << "crex compare: error: --flicker is for sequences: give --frames A..B\n";
        return kExitUsage;
    }
    if (!opt.frames.empty()) {
        if (!opt.flip_out.empty() || !opt.attention.empty() || opt.assume_display) {
            std::cerr << "crex compare: error: --frames compares sequences: --flip-map, --attention and --assume-display are for one image\n";
            return kExitUsage;
        }
        request.frames.emplace();
        if (std::string error = parse_frame_range(opt.frames, *request.frames); !error.empty()) {
            std::cerr << fmt::format("crex compare: error: --frames {}: {}\n", opt.frames, error);
            return kExitUsage;
        }
    }
    const CompareOutcome out = compare_files(request);
    if (out.status != kExitOk) {
        std::cerr << "crex compare: error: " << out.error << (out.error.empty() || out.error.back() != '\n' ? "\n" : "");
        return out.status;
    }
    if (opt.format == "json") {
        std::cout << out.result.dump(2) << "\n";
        return kExitOk;
    }
    if (request.frames) return print_frames(opt, out.result);
    return print_result(opt, out.result, request.choice.ssim || request.choice.flip || request.choice.perr);
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
