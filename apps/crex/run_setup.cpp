#include "apps/crex/run_setup.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include "apps/crex/cli_values.h"
#include "apps/crex/exit_codes.h"
#include "compiler/pipeline/settings_table.h"
#include "runtime/io/image_io.h"
#include "runtime/report/reference_cache.h"

namespace crex::app {
namespace {

// "10s", "500ms" or "25%" (of the full render time in the profile).
bool parse_budget(const std::string& text, double& value, bool& percent) {
    std::string t = text;
    percent = false;
    double scale = 1;
    if (t.size() > 2 && t.substr(t.size() - 2) == "ms") t.resize(t.size() - 2), scale = 1e-3;
    else if (!t.empty() && t.back() == 's') t.pop_back();
    else if (!t.empty() && t.back() == '%') t.pop_back(), percent = true;
    else return false;  // a unit is required, as in the pipeline language
    try {
        size_t used = 0;
        value = std::stod(t, &used) * scale;
        return used == t.size() && value > 0 && std::isfinite(value) && value <= 1e7 && (!percent || value <= 1000);
    } catch (...) {
        return false;
    }
}

}  // namespace

std::optional<int> parse_ambient(RunOptions& opt, bool say) {
    if (opt.ambient_text.empty()) return std::nullopt;
    if (opt.ambient_text == "auto") {
        opt.ambient_auto = true;
        return std::nullopt;
    }
    try {
        size_t used = 0;
        opt.ambient = std::stod(opt.ambient_text, &used);
        if (used == opt.ambient_text.size() && std::isfinite(opt.ambient) && opt.ambient >= 0 && opt.ambient <= 1e30)
            return std::nullopt;
    } catch (const std::exception&) {
    }
    if (say) std::cerr << fmt::format("crex run: error: --ambient '{}': expected 'auto' or a radiance from 0 to 1e30\n", opt.ambient_text);
    return kExitUsage;
}

std::optional<OutputPathFailure> check_output_path(const std::string& path) {
    namespace fs = std::filesystem;
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    static const std::set<std::string> kFormats = {".exr", ".hdr", ".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".tga", ".ppm", ".pfm"};
    std::error_code ec;
    if (fs::is_directory(path, ec))
        return OutputPathFailure{fmt::format("-o {}: is a directory; give a file name such as {}/render.exr", path, path), kExitFailure};
    if (!kFormats.count(ext))
        return OutputPathFailure{fmt::format("-o {}: unknown image format '{}'; crex writes .exr (float), .hdr, .png, .jpg, .tif, .bmp, "
                                             ".tga, .ppm or .pfm",
                                             path, ext.empty() ? "(no extension)" : ext),
                                 kExitFailure};
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    fs::create_directories(dir, ec);
    // Writable: a file can be made (and is removed) where the image will go.
    std::string probe = (dir / ".crex-write-check-XXXXXX").string();
    int fd = ::mkstemp(probe.data());
    if (fd < 0) return OutputPathFailure{fmt::format("-o {}: cannot write in {}: {}", path, dir.string(), std::strerror(errno)), kExitFailure};
    ::close(fd);
    ::unlink(probe.c_str());
    return std::nullopt;
}

std::optional<int> make_run_setup(const RunOptions& opt, const RunInput& in, RunSetup& setup) {
    const Scene& scene = *in.scene->scene;
    RunSettings& rs = setup.settings;
    if (!parse_image_size(opt.size, rs.width, rs.height)) {
        std::cerr << fmt::format("crex run: error: image size '{}': expected WIDTHxHEIGHT, each 1 to 16384, e.g. 512x512\n", opt.size);
        return kExitUsage;
    }
    rs.spp = opt.spp;
    rs.seed = opt.seed;
    rs.filter = opt.filter == "gaussian" ? PixelFilter::kGaussian : PixelFilter::kBox;
    rs.ambient = {opt.ambient, opt.ambient, opt.ambient};
    // A pipeline never shows black for skipped work unless it asked for an av (spec §6).
    rs.ambient_auto = opt.ambient_auto || (in.pipeline && !opt.ambient_given);
    rs.executor.shade.shadow_rays = opt.shadow_rays;
    rs.executor.shade.media_samples = opt.media_samples;
    rs.executor.shade.weight_limit = opt.lw;
    rs.executor.shade.max_depth = opt.max_depth;
    rs.executor.shade.roulette = !opt.no_roulette;
    rs.executor.clamp_indirect = opt.clamp;
    rs.executor.constant_importance = opt.importance;
    rs.executor.profile = &setup.profile;
    rs.max_memory = static_cast<size_t>(opt.max_memory_mib * double(1 << 20));
    rs.pass_samples = opt.pass_samples;
    rs.rounds = opt.rounds;
    rs.uniform = opt.uniform == "max" ? UniformQuality::kMax : opt.uniform == "min" ? UniformQuality::kMin : UniformQuality::kOff;

    // The budget and the profile it is predicted from.
    if (!opt.profile_in.empty()) {
        std::stringstream text;
        if (opt.profile_text) {
            text << *opt.profile_text;
        } else {
            std::ifstream file(opt.profile_in);
            text << file.rdbuf();
            if (!file) {
                std::cerr << fmt::format("crex run: error: cannot read profile '{}'\n", opt.profile_in);
                return kExitFailure;
            }
        }
        std::string error = Profile::from_json_text(text.str(), setup.profile);
        if (!error.empty()) {
            std::cerr << fmt::format("crex run: error: profile '{}': {}\n", opt.profile_in, error);
            return kExitInputErrors;
        }
        setup.predicted = setup.profile;
        auto j = nlohmann::json::parse(text.str(), nullptr, false);
        if (j.is_object()) setup.full_render_seconds = j.value("full_render_seconds", 0.0);
    }
    if (!opt.budget.empty() && !opt.no_budget) {
        bool percent = false;
        if (!parse_budget(opt.budget, setup.budget, percent)) {
            std::cerr << fmt::format("crex run: error: --budget '{}': expected a time with its unit, e.g. 10s, 500ms or 25%\n",
                                     opt.budget);
            return kExitUsage;
        }
        if (percent) {
            if (!(setup.full_render_seconds > 0)) {
                // Said where the budget comes from: the pipeline's line, or the flag.
                std::cerr << fmt::format("{}: error: {}a budget in % needs the time of a full render: render once without a "
                                         "budget with --save-profile FILE, then pass --profile FILE (or --no-budget)\n",
                                         opt.budget_origin.empty() ? "crex run" : opt.budget_origin,
                                         opt.budget_origin.empty() ? "--budget " + opt.budget + ": " : "budget " + opt.budget + ": ");
                return opt.budget_origin.empty() ? kExitUsage : kExitInputErrors;  // the flag's, or the file's
            }
            setup.budget = setup.budget / 100 * setup.full_render_seconds;
        }
    }
    rs.executor.budget_seconds = setup.budget;
    if (!opt.policy.empty()) rs.policy = pipeline::scheduling_policy_from_name(opt.policy);

    // The irradiance cache: --ic, --ic-file, or a pipeline that has one.
    bool wants_cache = opt.ic || !opt.ic_file.empty();
    for (const auto& n : in.plan.nodes) wants_cache |= n.id == "irradiance_cache";
    if (wants_cache) {
        IcSettings ics;
        ics.accuracy = opt.aa, ics.divisions = opt.ad, ics.bounces = opt.ab, ics.resolution = opt.ar;
        ics.ambient = rs.ambient;
        ics.seed = opt.seed;
        ics.caustic_photons = opt.caustic_photons;
        rs.irradiance_cache = ics;
        rs.ic_file = opt.ic_file;
    }

    setup.outputs = opt.outputs;
    if (setup.outputs.empty()) setup.outputs = {"out/render.exr", "out/render.png"};
    // Every output is checked before anything renders: a bad second -o used to be found after
    // the render, with the first image already written.
    for (const auto& path : setup.outputs)
        if (auto failure = opt.writes_outputs ? check_output_path(path) : std::nullopt) {
            std::cerr << "crex run: error: " << failure->message << "\n";
            return failure->exit_code;
        }
    setup.maps_dir = opt.maps_dir;
    if (setup.maps_dir.empty() && opt.maps_beside_output)
        setup.maps_dir = (std::filesystem::path(setup.outputs.front()).parent_path() / "maps").string();
    for (const auto& [flag, dir] : {std::pair{"--maps", setup.maps_dir}, std::pair{"--report", opt.report_dir}}) {
        std::error_code ec;
        if (opt.writes_outputs && !dir.empty() && std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
            std::cerr << fmt::format("crex run: error: {} {}: is a file; give a directory\n", flag, dir);
            return kExitFailure;
        }
    }

    // The reference of the error curve: with --reference, or for a report.
    setup.reference_file = opt.reference;
    if (opt.writes_outputs && (!opt.reference.empty() || !opt.report_dir.empty())) {
        bool automatic = opt.reference.empty() || opt.reference == "auto";
        if (automatic) {
            ReferenceSettings ref;
            ref.width = rs.width, ref.height = rs.height;
            setup.reference_file = find_cached_reference(scene, ref);
        }
        if (!automatic || !setup.reference_file.empty()) {
            metrics::Image img;
            std::string error = read_image(setup.reference_file, img.width, img.height, img.rgb);
            if (!error.empty()) {
                std::cerr << "crex run: error: reference: " << error << "\n";
                return kExitFailure;
            }
            if (img.width != rs.width || img.height != rs.height) {
                std::cerr << fmt::format("crex run: error: the reference {} is {}x{} but the render is {}x{}\n", setup.reference_file,
                                         img.width, img.height, rs.width, rs.height);
                return kExitInputErrors;
            }
            setup.reference = std::move(img);
        } else if (opt.reference == "auto") {
            std::cerr << fmt::format("crex run: error: no cached reference of {} at {}x{}: make one with 'crex reference {} --size "
                                     "{}x{}'\n",
                                     in.scene_spec, rs.width, rs.height, in.scene_spec, rs.width, rs.height);
            return kExitFailure;
        }
    }
    return std::nullopt;
}

}  // namespace crex::app
