#include "runtime/report/sequence_report.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/base64.h"
#include "runtime/base/atomic_file.h"
#include "runtime/base/file_extension.h"
#include "runtime/io/image_io.h"
#include "runtime/report/graphviz.h"
#include "runtime/report/html_report.h"
#include "runtime/report/svg_plot.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

// A video is embedded up to this size; a larger one is linked by its path instead.
constexpr uintmax_t kLargestEmbeddedVideo = 64u << 20;
// Frames in the strip are at most this wide (pixels), made smaller by whole factors.
constexpr int kStripWidth = 256;

double or_nan(const std::optional<double>& v) { return v ? *v : NAN; }

std::string figure_text(const std::optional<double>& v, const char* format) { return v ? fmt::format(fmt::runtime(format), *v) : "-"; }

// A frame as a viewer sees it, made at most kStripWidth wide by averaging whole blocks.
std::string write_strip_frame(const std::string& image, const std::string& out, double& exposure) {
    int w = 0, h = 0;
    std::vector<float> rgb;
    bool ldr = false;
    if (std::string error = read_image(image, w, h, rgb, &ldr); !error.empty()) return error;
    const std::vector<float> shown = as_displayed(rgb, ldr, exposure);
    const int k = std::max(1, (w + kStripWidth - 1) / kStripWidth), sw = std::max(1, w / k), sh = std::max(1, h / k);
    std::vector<float> small(static_cast<size_t>(sw) * static_cast<size_t>(sh) * 3, 0.0f);
    for (int y = 0; y < sh; ++y)
        for (int x = 0; x < sw; ++x)
            for (int c = 0; c < 3; ++c) {
                double sum = 0;
                int n = 0;
                for (int dy = 0; dy < k && y * k + dy < h; ++dy)
                    for (int dx = 0; dx < k && x * k + dx < w; ++dx, ++n)
                        sum += shown[(static_cast<size_t>(y * k + dy) * static_cast<size_t>(w) + static_cast<size_t>(x * k + dx)) * 3 + c];
                small[(static_cast<size_t>(y) * static_cast<size_t>(sw) + static_cast<size_t>(x)) * 3 + c] =
                    n ? static_cast<float>(sum / n) : 0.0f;
            }
    return write_image(out, sw, sh, {{"", std::move(small), true}});
}

std::string frames_csv(const std::vector<SequenceFrameRow>& frames) {
    std::string csv = "frame,time,skipped,high_quality,seconds,render_seconds,budget_seconds,records_made,records_reused,rays,inherited_pixels,flicker,flip,relmse,image\n";
    auto opt = [](const std::optional<double>& v) { return v ? fmt::format("{:.6g}", *v) : std::string(); };
    for (const auto& f : frames)
        csv += fmt::format("{},{:.6g},{},{},{:.6g},{:.6g},{:.6g},{},{},{},{:.6g},{},{},{},{}\n", f.frame, f.time, f.skipped ? 1 : 0, f.high_quality ? 1 : 0,
                           f.seconds, f.render_seconds, f.budget_seconds, f.records_made, f.records_reused, f.rays, f.inherited_pixels, opt(f.flicker),
                           opt(f.flip), opt(f.relmse), f.image);
    return csv;
}

nlohmann::json frames_data(const std::vector<SequenceFrameRow>& frames) {
    nlohmann::json list = nlohmann::json::array();
    auto opt = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
    for (const auto& f : frames)
        list.push_back({{"frame", f.frame}, {"time", f.time}, {"skipped", f.skipped}, {"high_quality", f.high_quality},
                        {"seconds", f.seconds}, {"render_seconds", f.render_seconds}, {"budget_seconds", f.budget_seconds},
                        {"records_made", f.records_made}, {"records_reused", f.records_reused}, {"rays", f.rays},
                        {"inherited_pixels", f.inherited_pixels}, {"flicker", opt(f.flicker)}, {"flip", opt(f.flip)}, {"relmse", opt(f.relmse)}, {"image", f.image}});
    return list;
}

// Means of what the frames measured, for the summary: first frame against the rest, flicker, error.
std::vector<std::pair<std::string, std::string>> measured_rows(const SequenceReport& r) {
    std::vector<std::pair<std::string, std::string>> rows;
    std::vector<const SequenceFrameRow*> rendered;
    for (const auto& f : r.frames)
        if (!f.skipped) rendered.push_back(&f);
    rows.push_back({"frames", fmt::format("{} ({} rendered, {} skipped: their files existed)", r.frames.size(), rendered.size(),
                                          r.frames.size() - rendered.size())});
    if (!rendered.empty()) {
        double rest = 0, total = 0;
        size_t made = 0;
        for (size_t i = 0; i < rendered.size(); ++i) total += rendered[i]->seconds, made += rendered[i]->records_made, rest += i ? rendered[i]->seconds : 0;
        std::string line = fmt::format("first {:.3f} s", rendered.front()->seconds);
        if (rendered.size() > 1) {
            rest /= static_cast<double>(rendered.size() - 1);
            line += fmt::format(", the rest {:.3f} s on average ({:.1f}x cheaper)", rest, rest > 0 ? rendered.front()->seconds / rest : 0.0);
        }
        rows.push_back({"time per frame", line});
        rows.push_back({"frames' time in all", fmt::format("{:.2f} s", total)});
        rows.push_back({"cache records made", fmt::format("{}", made)});
        double inherited = 0;
        for (const auto* f : rendered) inherited += f->inherited_pixels;
        if (inherited > 0 && rendered.size() > 1)
            rows.push_back({"pixels that inherited", fmt::format("{:.0f} % of each frame after the first, on average (--reuse-frames)",
                                                                 100 * inherited / static_cast<double>(rendered.size() - 1))});
    }
    auto mean_of = [&](auto get, const char* what, const char* name) {
        double sum = 0;
        size_t n = 0;
        for (const auto& f : r.frames)
            if (auto v = get(f)) sum += *v, ++n;
        if (n) rows.push_back({name, fmt::format("{:.4f} over {} frames{}", sum / static_cast<double>(n), n, what)});
    };
    mean_of([](const SequenceFrameRow& f) { return f.flicker; }, ": the mean display difference from the frame before, reprojected",
            "flicker");
    mean_of([](const SequenceFrameRow& f) { return f.flip; }, "", "FLIP against the reference");
    mean_of([](const SequenceFrameRow& f) { return f.relmse; }, "", "relMSE against the reference");
    if (!r.reference.empty()) rows.push_back({"reference", r.reference + " (frame N as its name with .NNNN)"});
    return rows;
}

std::string video_html(const std::string& video) {
    std::error_code ec;
    const uintmax_t size = fs::file_size(video, ec);
    if (ec) return "";
    const std::string ext = lower_extension(video);
    const std::string type = ext == ".mov" ? "video/quicktime" : ext == ".mkv" ? "video/x-matroska" : "video/mp4";
    if (size > kLargestEmbeddedVideo)
        return fmt::format("<p>The video, {:.0f} MB, is not embedded: <a href=\"file://{}\">{}</a></p>\n", static_cast<double>(size) / (1 << 20),
                           html_escape(fs::absolute(video).string()), html_escape(video));
    std::ifstream in(video, std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    return fmt::format("<video controls loop muted preload=\"metadata\" src=\"data:{};base64,{}\"></video>\n<p>{}</p>\n", type,
                       base64(bytes.str()), html_escape(video));
}

}  // namespace

std::vector<size_t> strip_frames(size_t count, size_t most) {
    std::vector<size_t> out;
    if (count == 0 || most == 0) return out;
    if (most == 1 || count == 1) return {0};
    const size_t n = std::min(count, most);
    for (size_t i = 0; i < n; ++i) {
        const size_t k = static_cast<size_t>(std::llround(static_cast<double>(i) * static_cast<double>(count - 1) / static_cast<double>(n - 1)));
        if (out.empty() || out.back() != k) out.push_back(k);
    }
    return out;
}

std::string write_sequence_report(const SequenceReport& r) {
    std::error_code ec;
    fs::create_directories(fs::path(r.dir) / "frames", ec);
    if (ec) return "cannot create '" + r.dir + "': " + ec.message();
    const fs::path dir(r.dir);
    nlohmann::json data = {{"title", r.title}, {"reference", r.reference}, {"video", r.video}, {"frames", frames_data(r.frames)}};
    for (const auto& [k, v] : r.summary) data["summary"][k] = v;
    std::string error = write_file_atomically((dir / "frames.json").string(), data.dump(2) + "\n");
    if (error.empty()) error = write_file_atomically((dir / "frames.csv").string(), frames_csv(r.frames));
    if (!error.empty()) return error;

    // The plots, against frame number.
    auto series = [&](const std::string& name, const std::string& colour, auto get) {
        PlotSeries s{name, colour, {}, r.frames.size() <= 40};
        for (const auto& f : r.frames) s.points.push_back({static_cast<double>(f.frame), f.skipped ? NAN : get(f)});
        return s;
    };
    std::vector<PlotSeries> time = {series("whole frame", "#1a73e8", [](const SequenceFrameRow& f) { return f.seconds; }),
                                    series("render", "#e37400", [](const SequenceFrameRow& f) { return f.render_seconds; })};
    if (std::any_of(r.frames.begin(), r.frames.end(), [](const SequenceFrameRow& f) { return f.budget_seconds > 0; }))
        time.push_back(series("budget", "#d93025", [](const SequenceFrameRow& f) { return f.budget_seconds > 0 ? f.budget_seconds : NAN; }));
    std::vector<PlotSeries> quality = {series("flicker", "#9334e6", [](const SequenceFrameRow& f) { return or_nan(f.flicker); })};
    if (std::any_of(r.frames.begin(), r.frames.end(), [](const SequenceFrameRow& f) { return f.flip.has_value(); })) {
        quality.push_back(series("FLIP vs reference", "#188038", [](const SequenceFrameRow& f) { return or_nan(f.flip); }));
        quality.back().dots = quality.back().dashed = true;  // often a reference every tenth frame: samples
    }
    const std::vector<PlotSeries> records = {
        series("records made", "#5f6368", [](const SequenceFrameRow& f) { return static_cast<double>(f.records_made); })};
    struct Plot {
        const char *title, *file;
        std::string svg;
    };
    const Plot plots[] = {
        {"Time per frame", "time_plot.svg", series_plot_svg("time-plot", "frame", "seconds", time)},
        {"Flicker and error per frame", "quality_plot.svg", series_plot_svg("quality-plot", "frame", "display difference / FLIP", quality)},
        {"Irradiance-cache records made per frame", "records_plot.svg", series_plot_svg("records-plot", "frame", "records", records)},
    };
    for (const Plot& p : plots)
        if (std::string e = write_file_atomically((dir / p.file).string(), p.svg); !e.empty()) return e;

    // The strip: frames whose image exists, all through the first one's exposure.
    std::vector<const SequenceFrameRow*> shown;
    for (const auto& f : r.frames)
        if (!f.image.empty() && fs::exists(f.image)) shown.push_back(&f);
    std::vector<ReportImage> strip;
    double exposure = 0;
    for (size_t k : strip_frames(shown.size(), r.strip)) {
        const SequenceFrameRow& f = *shown[k];
        const std::string png = (dir / "frames" / fmt::format("frame_{:04d}.png", f.frame)).string();
        if (std::string e = write_strip_frame(f.image, png, exposure); !e.empty()) return e;
        std::string caption = fmt::format("frame {}{}: {:.2f} s", f.frame, f.skipped ? " (skipped)" : "", f.seconds);
        if (f.flicker) caption += fmt::format(", flicker {:.4f}", *f.flicker);
        if (f.flip) caption += fmt::format(", FLIP {:.4f}", *f.flip);
        strip.push_back({caption, png, std::nullopt});
    }

    std::string html = report_page_start(r.title) + "<h2>Summary</h2>\n<table>\n";
    auto rows = r.summary;
    for (auto& row : measured_rows(r)) rows.push_back(std::move(row));
    for (const auto& [k, v] : rows) html += "<tr><th>" + html_escape(k) + "</th><td>" + html_escape(v) + "</td></tr>\n";
    html += "</table>\n";
    for (const Plot& p : plots) html += fmt::format("<h2>{}</h2>\n<div class=\"plot\">\n{}</div>\n", p.title, inline_svg(p.svg));
    html += "<h2>Frames</h2>\n<div class=\"images\">\n";
    for (const auto& img : strip)
        if (!append_report_figure(img, html, error)) return error;
    html += "</div>\n";
    if (!r.video.empty()) html += "<h2>Video</h2>\n" + video_html(r.video);
    html += "<h2>Every frame</h2>\n<table>\n<tr><th>frame</th><th>time on the path</th><th>seconds</th><th>render</th><th>budget</th>"
            "<th>records made</th><th>reused</th><th>rays</th><th>inherited</th><th>flicker</th><th>FLIP</th><th>relMSE</th><th>quality</th></tr>\n";
    for (const auto& f : r.frames) {
        auto num = [](const std::string& v) { return "<td class=\"num\">" + v + "</td>"; };
        html += "<tr>" + num(fmt::format("{}", f.frame)) + num(fmt::format("{:.3f} s", f.time)) +
                (f.skipped ? std::string("<td colspan=\"7\">skipped: its files existed</td>")
                           : num(fmt::format("{:.3f}", f.seconds)) + num(fmt::format("{:.3f}", f.render_seconds)) +
                                 num(f.budget_seconds > 0 ? fmt::format("{:.3f}", f.budget_seconds) : "-") +
                                 num(fmt::format("{}", f.records_made)) + num(fmt::format("{}", f.records_reused)) + num(fmt::format("{}", f.rays)) +
                                 num(f.inherited_pixels > 0 ? fmt::format("{:.0f} %", 100 * f.inherited_pixels) : "-")) +
                num(figure_text(f.flicker, "{:.4f}")) + num(figure_text(f.flip, "{:.4f}")) + num(figure_text(f.relmse, "{:.4g}")) + "<td>" +
                (f.skipped ? "" : f.high_quality ? "high" : "selective") + "</td></tr>\n";
    }
    html += "</table>\n";
    if (!r.plan_dot.empty()) {
        std::string svg;
        if (std::string e = write_plan_files(r.plan_dot, r.dir, svg); !e.empty()) return e;
        html += "<h2>Plan</h2>\n<div class=\"plan\">\n" + (svg.empty() ? "<pre>" + html_escape(r.plan_dot) + "</pre>\n" : inline_svg(svg));
        html += "</div>\n";
    }
    html += "</body>\n</html>\n";
    return write_file_atomically((dir / "index.html").string(), html);
}

}  // namespace crex
