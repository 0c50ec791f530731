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
#include <iostream>
#include <map>
#include <set>

#include "apps/crex/cli_values.h"
#include "apps/crex/exit_codes.h"
#include "base/input_file.h"
#include "base/number_range.h"
#include "compiler/pipeline/settings_table.h"
#include "runtime/io/image_io.h"
#include "runtime/report/reference_cache.h"

namespace crex::app {
namespace {

// "10s", "500ms" or "25%" (of the full render time in the profile): "" or what is wrong,
// in the pipeline language's ranges (settings_table.h).
std::string parse_budget(const std::string& text, double& value, bool& percent) {
    std::string t = text;
    percent = false;
    double scale = 1;
    if (t.size() > 2 && t.substr(t.size() - 2) == "ms") t.resize(t.size() - 2), scale = 1e-3;
    else if (!t.empty() && t.back() == 's') t.pop_back();
    else if (!t.empty() && t.back() == '%') t.pop_back(), percent = true;
    else return "expected a time with its unit, e.g. 10s, 500ms or 25%";  // as in the pipeline language
    auto v = parse_number_text(t);
    if (!v) return "expected a time with its unit, e.g. 10s, 500ms or 25%";
    value = *v * scale;
    if (std::string range = pipeline::budget_range_error(value, percent); !range.empty())
        return fmt::format("{}: expected {}", std::isnan(value) ? "nan is not a number" : std::isinf(value) ? "it is infinite" : "out of range", range);
    return "";
}

// --profile FILE (or, under mpirun off rank 0, its text as rank 0 read it): the costs and the
// full render's time, every number checked (a string there was an internal error).
std::optional<int> read_profile(const RunOptions& opt, RunSetup& setup) {
    std::string text;
    if (opt.profile_text) {
        text = *opt.profile_text;
    } else {
        std::string error;
        auto bytes = read_input_file(opt.profile_in, error, kMaxTextInputBytes);
        if (!bytes) {
            std::cerr << fmt::format("crex run: error: --profile: {}\n", error);
            return kExitFailure;
        }
        text = std::move(*bytes);
    }
    std::string error = Profile::from_json_text(text, setup.profile, &setup.full_render_seconds, opt.profile_in);
    if (!error.empty()) {
        std::cerr << fmt::format("crex run: error: profile {}\n", error);
        return kExitInputErrors;
    }
    setup.predicted = setup.profile;
    return std::nullopt;
}

// Two outputs named by one path (`-o X -o X`, `-o X --save-profile X`): the second replaced the
// first and the commit then said "cannot move 'X' into place: No such file or directory" after
// the old X was gone. Compared as absolute, normalised paths, before anything renders.
std::string same_output_twice(const RunOptions& opt, const RunSetup& setup) {
    std::vector<std::pair<std::string, std::string>> named;  // (flag, path)
    for (const auto& o : setup.outputs) named.push_back({"-o", o});
    if (!opt.profile_out.empty()) named.push_back({"--save-profile", opt.profile_out});
    if (!opt.ic_file.empty()) named.push_back({"--ic-file", opt.ic_file});
    if (!setup.maps_dir.empty()) named.push_back({"--maps", setup.maps_dir});
    if (!opt.report_dir.empty()) named.push_back({"--report", opt.report_dir});
    std::map<std::string, size_t> seen;
    for (size_t i = 0; i < named.size(); ++i) {
        std::error_code ec;
        std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(named[i].second, ec), ec);
        std::string key = (p.filename().empty() ? p.parent_path() : p).lexically_normal().string();
        auto [it, fresh] = seen.try_emplace(key, i);
        if (fresh) continue;
        const auto& first = named[it->second];
        return fmt::format("{} {} and {} {} name the same path: each output needs its own", first.first, first.second, named[i].first,
                           named[i].second);
    }
    return "";
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
    if (!opt.profile_in.empty())
        if (auto exit = read_profile(opt, setup)) return *exit;
    if (!opt.budget.empty() && !opt.no_budget) {
        bool percent = false;
        // Said where the budget comes from: the pipeline's line, or the flag.
        const std::string where = opt.budget_origin.empty() ? "crex run" : opt.budget_origin;
        const std::string what = opt.budget_origin.empty() ? "--budget " + opt.budget : "budget " + opt.budget;
        const int exit_code = opt.budget_origin.empty() ? kExitUsage : kExitInputErrors;  // the flag's, or the file's
        if (std::string error = parse_budget(opt.budget, setup.budget, percent); !error.empty()) {
            std::cerr << fmt::format("{}: error: {}: {}\n", where, what, error);
            return exit_code;
        }
        if (percent) {
            if (!(setup.full_render_seconds > 0)) {
                if (opt.profile_in.empty())
                    std::cerr << fmt::format("{}: error: {}: a budget in % needs the time of a full render: render once without a "
                                             "budget with --save-profile FILE, then pass --profile FILE (or --no-budget)\n",
                                             where, what);
                else
                    std::cerr << fmt::format("{}: error: {}: the profile '{}' holds no full render time (\"full_render_seconds\" "
                                             "above 0): save it again with --save-profile from a render without a budget, or give "
                                             "the budget in seconds\n",
                                             where, what, opt.profile_in);
                return opt.profile_in.empty() ? exit_code : kExitInputErrors;
            }
            setup.budget = setup.budget / 100 * setup.full_render_seconds;
        }
    }
    rs.executor.budget_seconds = setup.budget;
    if (!opt.policy.empty()) rs.policy = pipeline::scheduling_policy_from_name(opt.policy);

    // --ic-file names a file, read if it exists: a directory or a device there is said now, not
    // as "basic_filebuf::underflow error reading the file" after the render.
    if (!opt.ic_file.empty() && opt.writes_outputs) {
        std::error_code ec;
        if (std::filesystem::exists(opt.ic_file, ec))
            if (std::string error = check_input_file(opt.ic_file, kMaxDataInputBytes); !error.empty()) {
                std::cerr << fmt::format("crex run: error: --ic-file: {}{}\n", error,
                                         std::filesystem::is_directory(opt.ic_file, ec)
                                             ? fmt::format("; it names the cache's file (made if missing), e.g. {}/scene.ic", opt.ic_file)
                                             : "");
                return kExitFailure;
            }
    }
    // The irradiance cache: --ic, --ic-file, or a pipeline that has one.
    const bool wants_cache = opt.ic || !opt.ic_file.empty() || in.plan.irradiance_cache;
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
    if (opt.writes_outputs)
        if (std::string clash = same_output_twice(opt, setup); !clash.empty()) {
            std::cerr << "crex run: error: " << clash << "\n";
            return kExitUsage;
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
            // NaN or Inf would make the error curve 'nan' and perr 100 % with exit 0, where
            // `crex compare` refuses the same image.
            size_t bad = 0;
            for (float v : img.rgb) bad += !std::isfinite(v);
            if (bad > 0) {
                std::cerr << fmt::format("crex run: error: the reference {} holds {} non-finite value{} (NaN or Inf): no error can be "
                                         "measured against it{}\n",
                                         setup.reference_file, bad, bad == 1 ? "" : "s",
                                         automatic ? fmt::format("; render it again with 'crex reference {} --size {}x{} --force'",
                                                                 in.scene_spec, rs.width, rs.height)
                                                   : "");
                return kExitInputErrors;
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
