/// \file html_report.h
/// The report of a run as one self-contained HTML page: images embedded as data: URIs, the
/// plot and plan graph as inline SVG, a summary table. A script on the page records in
/// <body data-*> how many images decoded and how many curves the plot drew, which is what the
/// headless-Chromium test reads back.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace crex {

/// What a picture's colours mean: a bar under it from `lo` (left) to `hi` (right).
struct ColourScale {
    double lo = 0, hi = 1;
    std::string gradient;  ///< CSS background of the bar (heat_css_gradient(), or black to white)
    std::string unit;      ///< said after hi, e.g. "rays"
};

struct ReportImage {
    std::string title;
    std::string png_path;  ///< read and embedded
    std::optional<ColourScale> scale;
    std::string note = "";  ///< said after the title in the caption (not in the alt text)
};

struct ReportPage {
    std::string title;
    std::vector<std::pair<std::string, std::string>> summary;  ///< rows of the summary table
    std::string plot_svg;
    std::string policy_plot_svg;  ///< every budget policy's error against time, or ""
    std::string plan_svg;  ///< Graphviz's SVG of the plan, or "" to show plan_dot as text
    std::string plan_dot;
    std::vector<ReportImage> images;
    /// `crex run --equal-time`: the pipeline and uniform rendering in the same time, and their
    /// FLIP maps, two a row (pipeline left); `equal_time_note` says what was compared.
    std::vector<ReportImage> equal_time;
    std::string equal_time_note;
};

/// In the head of every report page: a folder whose index.html carries it is a crex report,
/// which a later run may replace whole (run_report.h).
inline constexpr const char* kReportMarker = "<meta name=\"generator\" content=\"crex report\">";

/// Returns the page; `error` names an image that could not be read.
std::string render_report_html(const ReportPage& page, std::string& error);

/// The parts every report page is made of, for pages of other shapes (a sequence's,
/// sequence_report.h): text made safe for HTML; the page's head (marker, style, the checking
/// script) and the start of its body with the title; an SVG made fit to sit inside HTML; one
/// picture as a <figure> with its PNG embedded (false, and `error`, when it cannot be read).
std::string html_escape(const std::string& s);
std::string report_page_start(const std::string& title);
std::string inline_svg(const std::string& svg);
bool append_report_figure(const ReportImage& img, std::string& html, std::string& error);

}  // namespace crex
