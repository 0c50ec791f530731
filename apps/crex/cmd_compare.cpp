// `crex compare`: how far an image is from a reference, by the metrics of spec §7.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <sstream>

#include "apps/crex/cli_values.h"
#include "apps/crex/commands.h"
#include "apps/crex/exit_codes.h"
#include "runtime/io/heat_map.h"
#include "runtime/io/image_io.h"
#include "runtime/metrics/metrics.h"
#include "stdlib/guidance/operators.h"

namespace crex::app {
namespace {

// Where a viewer looks, as weights per pixel: the Itti-Koch saliency of the reference as
// displayed, or a map from a file (a task map written by `crex run --maps`; its first channel).
std::string attention_weights(const std::string& source, const metrics::Image& reference_display, std::vector<float>& weights) {
    if (source == "saliency") {
        guidance::Raster rgb(reference_display.width, reference_display.height, 3);
        rgb.v = reference_display.rgb;
        weights = guidance::saliency(rgb).v;
        // A featureless reference draws the eye nowhere in particular: every pixel counts alike.
        if (std::none_of(weights.begin(), weights.end(), [](float w) { return w > 0; })) std::fill(weights.begin(), weights.end(), 1.0f);
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
    std::string metrics = "rmse,relmse,ssim,flip,perr";
    double perr_threshold = metrics::kDefaultPerrThreshold;
    double ppd = 67.0206;
    std::string flip_out;
    std::string attention;  ///< "saliency" or a map file: weights of the attention-weighted FLIP
    bool assume_display = false;  ///< compare a tone-mapped file with a linear one by tone-mapping the linear one
    std::string format = "text";
};

const std::vector<std::string> kMetricNames = {"rmse", "relmse", "ssim", "flip", "perr"};

int compare(const CompareOptions& opt) {
    std::vector<std::string> wanted;
    std::stringstream list(opt.metrics);
    for (std::string m; std::getline(list, m, ',');) {
        if (std::find(kMetricNames.begin(), kMetricNames.end(), m) == kMetricNames.end()) {
            std::cerr << fmt::format("crex compare: error: unknown metric '{}': expected some of rmse,relmse,ssim,flip,perr\n", m);
            return kExitUsage;
        }
        wanted.push_back(m);
    }
    metrics::Image test, ref;
    bool test_ldr = false, ref_ldr = false;
    for (auto [path, img, ldr] : {std::tuple{&opt.test, &test, &test_ldr}, std::tuple{&opt.reference, &ref, &ref_ldr}}) {
        std::string error = read_image(*path, img->width, img->height, img->rgb, ldr);
        if (!error.empty()) {
            std::cerr << "crex compare: error: " << error << "\n";
            return kExitFailure;
        }
        // NaN or Inf would make every metric 'nan' and the comparison say nothing, with exit 0.
        size_t bad = 0;
        for (float v : img->rgb) bad += !std::isfinite(v);
        if (bad > 0) {
            std::cerr << fmt::format("crex compare: error: {} holds {} non-finite value{} (NaN or Inf): nothing to compare\n", *path,
                                     bad, bad == 1 ? "" : "s");
            return kExitInputErrors;
        }
    }
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
    // HDR if both images are: both are then seen through the reference's exposure.
    metrics::DisplayView view{!(test_ldr && ref_ldr), display_exposure(ref.rgb)};
    bool perceptual = false;
    for (const auto& m : wanted) perceptual |= m == "ssim" || m == "flip" || m == "perr";
    metrics::Image td, rd;
    std::vector<float> flip;
    if (perceptual || !opt.flip_out.empty() || !opt.attention.empty()) {
        td = metrics::display_view(test, view), rd = metrics::display_view(ref, view);
        flip = metrics::flip_map(td, rd, opt.ppd);
    }
    nlohmann::json j;
    j["test"] = opt.test;
    j["reference"] = opt.reference;
    j["size"] = {ref.width, ref.height};
    j["display"] = display_note.empty() ? view.describe() : display_note;
    for (const auto& m : wanted) {
        if (m == "rmse") j["rmse"] = metrics::rmse(test, ref);
        if (m == "relmse") j["relmse"] = metrics::relmse(test, ref);
        if (m == "ssim") {
            auto s = metrics::ssim(td, rd);
            j["ssim"] = s ? nlohmann::json(*s) : nlohmann::json(nullptr);
        }
        if (m == "flip") j["flip"] = metrics::mean(flip);
        if (m == "perr") {
            j["perr"] = metrics::perr(flip, opt.perr_threshold);
            j["perr_threshold"] = opt.perr_threshold;
        }
    }
    if (!opt.attention.empty()) {
        std::vector<float> weights;
        std::string error = attention_weights(opt.attention, rd, weights);
        if (!error.empty()) {
            std::cerr << "crex compare: error: " << error << "\n";
            return kExitFailure;
        }
        auto aflip = metrics::weighted_mean(flip, weights);
        if (!aflip) {
            std::cerr << fmt::format("crex compare: error: the attention map {} is zero everywhere: nothing to weight by\n", opt.attention);
            return kExitInputErrors;
        }
        j["aflip"] = *aflip;
        j["attention"] = opt.attention;
    }
    if (!opt.flip_out.empty()) {
        std::vector<double> values(flip.begin(), flip.end());
        ImageLayer layer{"", heat_colours(values, 1.0), true};
        std::string error = write_image(opt.flip_out, ref.width, ref.height, {layer});
        if (!error.empty()) {
            std::cerr << "crex compare: error: " << error << "\n";
            return kExitFailure;
        }
        j["flip_map"] = opt.flip_out;
    }
    if (opt.format == "json") {
        std::cout << j.dump(2) << "\n";
        return kExitOk;
    }
    std::cout << fmt::format("{} against {} ({}x{})\n", opt.test, opt.reference, ref.width, ref.height);
    if (j.contains("rmse")) std::cout << fmt::format("  rmse    {:.6g}   (linear radiance)\n", j["rmse"].get<double>());
    if (j.contains("relmse")) std::cout << fmt::format("  relmse  {:.6g}   (mean of (t-r)^2/(r^2+0.01))\n", j["relmse"].get<double>());
    if (j.contains("ssim"))
        std::cout << (j["ssim"].is_null() ? std::string("  ssim    n/a (smaller than the 11x11 window)\n")
                                          : fmt::format("  ssim    {:.6f}   (1 = identical)\n", j["ssim"].get<double>()));
    if (j.contains("flip")) std::cout << fmt::format("  flip    {:.6f}   (mean LDR-FLIP, {:.1f} pixels per degree)\n", j["flip"].get<double>(), opt.ppd);
    if (j.contains("perr"))
        std::cout << fmt::format("  perr    {:.3f} %  (pixels with FLIP >= {:g}; not Daly's VDP)\n", j["perr"].get<double>(), opt.perr_threshold);
    if (j.contains("aflip"))
        std::cout << fmt::format("  aflip   {:.6f}   (FLIP weighted by {})\n", j["aflip"].get<double>(),
                                 opt.attention == "saliency" ? "the reference's saliency" : opt.attention);
    if (perceptual) std::cout << "  display: " << j["display"].get<std::string>() << "\n";
    if (!opt.flip_out.empty()) std::cout << "  wrote " << opt.flip_out << "\n";
    return kExitOk;
}

}  // namespace

Runner add_compare_command(CLI::App& app) {
    auto opt = std::make_shared<CompareOptions>();
    CLI::App* cmd = app.add_subcommand("compare", "Measure how far an image is from a reference (RMSE, relMSE, SSIM, FLIP, perr)");
    cmd->add_option("test", opt->test, "The image to judge (any format OpenImageIO reads)")->required();
    cmd->add_option("reference", opt->reference, "The reference image, same size")->required();
    cmd->add_option("--metric", opt->metrics, "Comma-separated metrics: rmse,relmse,ssim,flip,perr")->capture_default_str();
    cmd->add_option("--perr-threshold", opt->perr_threshold, "FLIP value from which a pixel counts as visibly different")
        ->capture_default_str()
        ->check(number_in(0.0, 1.0));
    cmd->add_option("--ppd", opt->ppd, "Pixels per degree of visual angle for FLIP")->capture_default_str()->check(number_in(1.0, 1000.0));
    cmd->add_option("--flip-map", opt->flip_out, "Write the per-pixel FLIP error as a picture (viridis, 0..1)");
    cmd->add_option("--attention", opt->attention,
                    "Also the attention-weighted FLIP (aflip): FLIP averaged with weights 'saliency' (of the reference) or from a map file (e.g. a task map)");
    cmd->add_flag("--assume-display", opt->assume_display,
                  "Compare a tone-mapped file (PNG) with a linear one (EXR) by tone-mapping the linear one as crex writes PNGs");
    cmd->add_option("--format", opt->format, "Output as text or json")->check(CLI::IsMember({"text", "json"}));
    cmd->footer(R"(
RMSE and relMSE compare linear radiance. SSIM, FLIP and perr compare what a viewer sees:
LDR files (PNG, JPEG) as stored; HDR files (EXR, HDR) both through the tone map of spec
section 7 with the reference's exposure, and the output says so. One of each is refused
(exit 1): the PNG is already tone-mapped. --assume-display tone-maps the linear one as crex
writes PNGs (its own exposure) and compares the two as displayed.

Examples:
  crex compare out/sel_rp.exr out/gold.exr
  crex compare a.png b.png --metric flip,perr --flip-map flip.png
  crex compare a.exr ref.exr --format json
  crex compare a.exr ref.exr --attention saliency        FLIP where a viewer looks

Exit status: 0 compared, 1 images of different sizes or kinds, 2 usage, 3 an image cannot be read or written.)");
    return [opt] { return compare(*opt); };
}

}  // namespace crex::app
