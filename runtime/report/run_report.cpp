#include "runtime/report/run_report.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "runtime/base/atomic_file.h"
#include "runtime/base/vec3.h"
#include "runtime/io/heat_map.h"
#include "runtime/io/image_io.h"
#include "runtime/metrics/metrics.h"
#include "runtime/report/graphviz.h"
#include "runtime/report/html_report.h"
#include "runtime/report/svg_plot.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

std::string safe_name(std::string s) {
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

}  // namespace

std::string report_folder_refusal(const std::string& dir) {
    std::error_code ec;
    if (!fs::exists(dir, ec)) return "";
    if (!fs::is_directory(dir, ec)) return fmt::format("--report {}: is a file; give a directory", dir);
    if (fs::directory_iterator(dir, ec) == fs::directory_iterator()) return "";  // empty (or unreadable: writing says so)
    std::ifstream in(fs::path(dir) / "index.html", std::ios::binary);
    std::string head(4096, '\0');  // the marker is in the page's head
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<size_t>(in.gcount()));
    if (head.find(kReportMarker) != std::string::npos) return "";
    return fmt::format("--report {}: the folder exists and is not a crex report (no index.html written by crex), so crex will not "
                       "replace it: give a new or empty folder",
                       dir);
}

namespace {

// The summed Rec. 709 luminance of a linear RGB image.
double light_of(const std::vector<float>& rgb) {
    double sum = 0;
    for (size_t i = 0; i + 2 < rgb.size(); i += 3) sum += luminance(Vec3{rgb[i], rgb[i + 1], rgb[i + 2]});
    return sum;
}

}  // namespace

std::string light_share_note(double part, double whole) {
    if (!(whole > 0) || !std::isfinite(part) || !std::isfinite(whole)) return "";
    const double percent = 100 * part / whole;
    if (percent > 0 && percent < 0.1) return "under 0.1 % of the image's light";
    return fmt::format("{:.1f} % of the image's light", percent);
}

std::string write_run_report(const RunReport& r, std::vector<CurvePoint>& curve) {
    std::error_code ec;
    fs::create_directories(fs::path(r.dir) / "images", ec);
    if (ec) return "cannot create '" + r.dir + "': " + ec.message();
    curve.clear();
    if (r.reference && r.checkpoints) curve = error_curve(*r.checkpoints, *r.reference, r.view);

    // Data: JSON and CSV of the checkpoints.
    nlohmann::json j;
    j["summary"] = r.summary;
    j["reference"] = r.reference ? nlohmann::json(r.reference_path) : nlohmann::json(nullptr);
    j["display"] = r.view.describe();
    if (r.budget_seconds) j["budget_seconds"] = *r.budget_seconds;
    j["checkpoints"] = nlohmann::json::array();
    for (size_t i = 0; r.checkpoints && i < r.checkpoints->size(); ++i) {
        const Checkpoint& c = (*r.checkpoints)[i];
        nlohmann::json cj = {{"seconds", c.seconds}, {"stage", c.stage}, {"event", c.event}, {"rays", c.rays}};
        if (i < curve.size()) {
            cj["rmse"] = curve[i].rmse, cj["relmse"] = curve[i].relmse, cj["flip"] = curve[i].flip, cj["perr"] = curve[i].perr;
            cj["ssim"] = curve[i].ssim ? nlohmann::json(*curve[i].ssim) : nlohmann::json(nullptr);
        }
        j["checkpoints"].push_back(cj);
    }
    // Every policy's FLIP against time on one plot, this run's first (--compare-policies).
    std::string policies_plot;
    if (!curve.empty() && !r.other_policies.empty() && r.reference) {
        std::vector<std::pair<std::string, std::vector<CurvePoint>>> runs = {{r.policy, curve}};
        for (const auto& [name, checkpoints] : r.other_policies) runs.push_back({name, error_curve(*checkpoints, *r.reference, r.view)});
        nlohmann::json pj = nlohmann::json::object();
        for (const auto& [name, c] : runs) {
            pj[name] = nlohmann::json::array();
            for (const auto& p : c) pj[name].push_back({{"seconds", p.seconds}, {"flip", p.flip}, {"perr", p.perr}});
        }
        j["policies"] = pj;
        policies_plot = policy_plot_svg(runs, r.budget_seconds);
    }
    std::string error = write_file_atomically((fs::path(r.dir) / "checkpoints.json").string(), j.dump(2) + "\n");
    if (error.empty() && !curve.empty()) error = write_file_atomically((fs::path(r.dir) / "checkpoints.csv").string(), curve_csv(curve));
    std::string plot;
    if (!curve.empty()) {
        plot = error_plot_svg(curve, r.budget_seconds);
        if (error.empty()) error = write_file_atomically((fs::path(r.dir) / "error_plot.svg").string(), plot);
    }
    if (error.empty() && !policies_plot.empty())
        error = write_file_atomically((fs::path(r.dir) / "policies_plot.svg").string(), policies_plot);
    if (!error.empty()) return error;

    // Images, all through one exposure (the reference's, else the final image's, the first
    // image given): a component shows at its true share of the light, not auto-exposed to look
    // as bright as the whole image.
    ReportPage page;
    page.title = r.title;
    page.policy_plot_svg = policies_plot;
    std::optional<double> exposure;
    for (const auto& [title, rgb] : r.images)
        if (title == "reference") exposure = display_exposure(rgb);
    if (!exposure) exposure = r.images.empty() ? 1.0 : display_exposure(r.images.front().second);
    // A component's caption says its share of the final image's light, so that a dark tile
    // reads as a small share rather than as a failure.
    const double final_light = r.images.empty() ? 0.0 : light_of(r.images.front().second);
    for (const auto& [title, rgb] : r.images) {
        std::string path = (fs::path(r.dir) / "images" / (safe_name(title) + ".png")).string();
        if (std::string e = write_image(path, r.width, r.height, {{"", to_display(rgb, *exposure), true}}); !e.empty()) return e;
        page.images.push_back({title, path, std::nullopt, title.rfind("component ", 0) == 0 ? light_share_note(light_of(rgb), final_light) : ""});
    }
    // --equal-time: the two images in one exposure, and where each differs from the reference.
    if (const auto& e = r.equal_time) {
        page.equal_time_note = e->note;
        auto add = [&](const std::string& title, const std::string& file, const std::vector<float>& rgb) {
            std::string path = (fs::path(r.dir) / "images" / file).string();
            std::string err = write_image(path, r.width, r.height, {{"", rgb, true}});
            page.equal_time.push_back({title, path, std::nullopt});
            return err;
        };
        auto heat = [](const std::vector<float>& flip) { return heat_colours(std::vector<double>(flip.begin(), flip.end()), 1.0); };
        for (std::string e2 : {add(e->pipeline_title, "equal_time_pipeline.png", to_display(e->pipeline, *exposure)),
                               add(e->uniform_title, "equal_time_uniform.png", to_display(e->uniform, *exposure)),
                               add("FLIP of the pipeline against the reference", "equal_time_pipeline_flip.png", heat(e->pipeline_flip)),
                               add("FLIP of uniform rendering against the reference", "equal_time_uniform_flip.png", heat(e->uniform_flip))})
            if (!e2.empty()) return e2;
        for (size_t i = 2; i < 4; ++i) page.equal_time[i].scale = ColourScale{0, 1, heat_css_gradient(), ""};
    }
    // Where the final image differs from the reference, as a viewer sees it.
    if (r.reference && !r.images.empty() && r.images.front().first == "final image") {
        metrics::Image final_image{r.width, r.height, r.images.front().second};
        std::vector<float> flip = metrics::flip_map(metrics::display_view(final_image, r.view), metrics::display_view(*r.reference, r.view));
        std::vector<double> values(flip.begin(), flip.end());
        std::string path = (fs::path(r.dir) / "images" / "flip_against_reference.png").string();
        if (std::string e = write_image(path, r.width, r.height, {{"", heat_colours(values, 1.0), true}}); !e.empty()) return e;
        page.images.push_back({"FLIP against the reference (0 same .. 1 most different)", path, ColourScale{0, 1, heat_css_gradient(), ""}});
    }
    for (const auto& [name, map] : r.maps) {
        std::vector<float> rgb(3 * map.pixels());
        for (size_t p = 0; p < map.pixels(); ++p) rgb[3 * p] = rgb[3 * p + 1] = rgb[3 * p + 2] = map.v[p];
        std::string path = (fs::path(r.dir) / "images" / ("map_" + safe_name(name) + ".png")).string();
        if (std::string e = write_image(path, r.width, r.height, {{"", rgb, true}}); !e.empty()) return e;
        page.images.push_back({"map " + name, path, ColourScale{0, 1, "linear-gradient(to right, black, white)", ""}});
    }
    for (const auto& p : r.pictures)
        if (p.size() > 4 && p.substr(p.size() - 4) == ".png" && p.find("map_") == std::string::npos &&
            p.find("preview") == std::string::npos)
            page.images.push_back({fs::path(p).stem().string(), p,
                                   r.picture_scales.count(p) ? std::optional(ColourScale{0, r.picture_scales.at(p).first, heat_css_gradient(),
                                                                                         r.picture_scales.at(p).second})
                                                             : std::nullopt});

    // The plan, drawn by Graphviz when it is installed.
    page.plan_dot = r.plan_dot;
    if (std::string e = write_plan_files(r.plan_dot, r.dir, page.plan_svg); !e.empty()) return e;  // no drawing: the page shows the DOT

    // Summary rows.
    auto row = [&](const std::string& k, const std::string& v) { page.summary.push_back({k, v}); };
    const auto& s = r.summary;
    row("scene", s.value("scene", ""));
    if (s.contains("pipeline")) row("pipeline", s["pipeline"].get<std::string>());
    row("crex", s.value("crex", ""));
    if (s.contains("size")) row("size", fmt::format("{} x {}", s["size"][0].get<int>(), s["size"][1].get<int>()));
    row("render time", fmt::format("{:.3f} s", s.value("render_seconds", 0.0)));
    if (s.contains("stages"))
        row("stages", fmt::format("preview {:.3f} s ({:.0f} %), guidance {:.3f} s, selective {:.3f} s",
                                  s["stages"].value("preview_seconds", 0.0), s.value("preview_percent_of_time", 0.0),
                                  s["stages"].value("guidance_seconds", 0.0), s["stages"].value("selective_seconds", 0.0)));
    row("rays", fmt::format("{}", s.value("rays", uint64_t{0})));
    if (r.budget_seconds)
        row("budget", fmt::format("{:.3f} s, overshoot {:+.1f} %", *r.budget_seconds, s.value("overshoot_percent", 0.0)));
    if (!curve.empty()) {
        const CurvePoint& last = curve.back();
        row("reference", r.reference_path);
        row("final error", fmt::format("RMSE {:.4g}, relMSE {:.4g}, FLIP {:.4f}, perr {:.1f} %{}", last.rmse, last.relmse, last.flip,
                                       last.perr, last.ssim ? fmt::format(", SSIM {:.4f}", *last.ssim) : ""));
        row("checkpoints", fmt::format("{} (copying and scoring them paused the clock for {:.1f} ms in all)", curve.size(),
                                       1e3 * s.value("checkpoint_seconds", 0.0)));
        row("display", r.view.describe());
    } else {
        row("reference", "none: no error curve (give --reference FILE, or make one with 'crex reference' and use --reference auto)");
    }
    if (s.contains("equal_time")) {
        const auto& e = s["equal_time"];
        auto figures = [](const nlohmann::json& x) {
            return fmt::format("FLIP {:.4f}{}", x["flip"].get<double>(),
                               x["aflip"].is_null() ? "" : fmt::format(", aFLIP {:.4f}", x["aflip"].get<double>()));
        };
        row("equal time", fmt::format("{:.3f} s each; aFLIP weighted by {}", e["seconds"].get<double>(), e["attention"].get<std::string>()));
        row("equal time: pipeline", figures(e["pipeline"]));
        row("equal time: uniform", fmt::format("{} (crex {}, {:.1f} spp on average)", figures(e["uniform"]), e["uniform"]["crex"].get<std::string>(),
                                   e["uniform"]["spp"]["mean"].get<double>()));
    }
    page.plot_svg = plot;
    std::string html = render_report_html(page, error);
    if (!error.empty()) return error;
    return write_file_atomically((fs::path(r.dir) / "index.html").string(), html);
}

}  // namespace crex
