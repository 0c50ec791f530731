#include "runtime/report/html_report.h"

#include "base/base64.h"
#include "runtime/report/svg_plot.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

namespace crex {
namespace {

constexpr const char* kStyle = R"(<style>
body { font-family: Helvetica, Arial, sans-serif; margin: 24px; color: #202124; }
h1 { font-size: 20px; } h2 { font-size: 16px; margin-top: 28px; }
table { border-collapse: collapse; } td, th { border: 1px solid #ddd; padding: 4px 10px; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.images { display: flex; flex-wrap: wrap; gap: 16px; }
.pair { display: grid; grid-template-columns: repeat(2, max-content); gap: 16px; }
figure { margin: 0; } figcaption { font-size: 12px; color: #555; }
.scale { display: flex; align-items: center; gap: 6px; font-size: 11px; color: #555; margin: 2px 0; }
.ramp { flex: 1; height: 10px; border: 1px solid #ccc; }
img { image-rendering: pixelated; min-width: 192px; border: 1px solid #ccc; }
.plan svg { max-width: 100%; height: auto; }
</style>
)";

}  // namespace

std::string html_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
        }
    }
    return out;
}

// Graphviz's SVG starts with an XML prolog and a DOCTYPE, which may not appear inside HTML.
std::string inline_svg(const std::string& svg) {
    size_t at = svg.find("<svg");
    return at == std::string::npos ? svg : svg.substr(at);
}

namespace {

constexpr const char* kScript = R"(<script>
window.addEventListener('load', () => {
  const imgs = Array.from(document.images);
  const b = document.body.dataset;
  b.imagesTotal = imgs.length;
  b.imagesLoaded = imgs.filter(i => i.complete && i.naturalWidth > 0).length;
  const plot = document.getElementById('error-plot');
  b.plotCurves = plot ? plot.querySelectorAll('polyline.curve').length : 0;
  b.plotWidth = plot ? Math.round(plot.getBoundingClientRect().width) : 0;
  b.plots = document.querySelectorAll('.plot svg').length;
  b.plotsCurves = document.querySelectorAll('.plot svg polyline.curve').length;
  // A picture of one colour (a black component, an empty map) says nothing: count them.
  let blank = 0;
  for (const i of imgs) {
    if (!i.complete || !i.naturalWidth) continue;
    const c = document.createElement('canvas');
    c.width = i.naturalWidth, c.height = i.naturalHeight;
    const g = c.getContext('2d');
    g.drawImage(i, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let same = true;
    for (let k = 4; k < d.length && same; k += 4) same = d[k] === d[0] && d[k + 1] === d[1] && d[k + 2] === d[2];
    if (same) blank++;
  }
  b.imagesBlank = blank;
  // Text that overlaps other text in the plot (tick and stage labels, the legend).
  let overlaps = 0;
  for (const one of document.querySelectorAll('.plot svg')) {
    const boxes = Array.from(one.querySelectorAll('text')).map(t => t.getBoundingClientRect());
    for (let m = 0; m < boxes.length; m++)
      for (let n = m + 1; n < boxes.length; n++) {
        const a = boxes[m], q = boxes[n];
        if (a.left < q.right - 1 && q.left < a.right - 1 && a.top < q.bottom - 1 && q.top < a.bottom - 1) overlaps++;
      }
  }
  b.plotOverlaps = overlaps;
  // Colour bars drawn wide enough to read (a heat map without one cannot be read).
  b.colourBars = Array.from(document.querySelectorAll('.scale .ramp')).filter(r => r.getBoundingClientRect().width > 50).length;
  b.ready = 'yes';
});
</script>
)";

}  // namespace

std::string render_report_html(const ReportPage& page, std::string& error) {
    std::string html = report_page_start(page.title) + "<h2>Summary</h2>\n<table>\n";
    for (const auto& [k, v] : page.summary) html += "<tr><th>" + html_escape(k) + "</th><td>" + html_escape(v) + "</td></tr>\n";
    html += "</table>\n";
    if (!page.plot_svg.empty()) html += "<h2>Error against time</h2>\n<div class=\"plot\">\n" + inline_svg(page.plot_svg) + "</div>\n";
    if (!page.policy_plot_svg.empty())
        html += "<h2>Every budget policy, same budget</h2>\n<div class=\"plot\">\n" + inline_svg(page.policy_plot_svg) + "</div>\n";
    auto figure = [&](const ReportImage& img) { return append_report_figure(img, html, error); };
    if (!page.equal_time.empty()) {
        html += "<h2>Equal time: the pipeline beside uniform rendering</h2>\n<p>" + html_escape(page.equal_time_note) + "</p>\n<div class=\"pair\">\n";
        for (const auto& img : page.equal_time)
            if (!figure(img)) return "";
        html += "</div>\n";
    }
    html += "<h2>Images</h2>\n<div class=\"images\">\n";
    for (const auto& img : page.images)
        if (!figure(img)) return "";
    html += "</div>\n<h2>Plan</h2>\n<div class=\"plan\">\n";
    html += page.plan_svg.empty() ? "<pre>" + html_escape(page.plan_dot) + "</pre>\n" : inline_svg(page.plan_svg);
    html += "</div>\n</body>\n</html>\n";
    return html;
}

std::string report_page_start(const std::string& title) {
    return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n" + std::string(kReportMarker) + "\n<title>" +
           html_escape(title) + "</title>\n" + kStyle + kScript + "</head>\n<body>\n<h1>" + html_escape(title) + "</h1>\n";
}

bool append_report_figure(const ReportImage& img, std::string& html, std::string& error) {
    std::ifstream in(img.png_path, std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    if (!in) {
        error = "cannot read " + img.png_path + " for the report";
        return false;
    }
    std::string bar;
    if (img.scale)
        bar = fmt::format("<div class=\"scale\"><span>{}</span><div class=\"ramp\" style=\"background: {}\"></div><span>{}{}</span></div>",
                          tick_label(img.scale->lo), img.scale->gradient, tick_label(img.scale->hi),
                          img.scale->unit.empty() ? "" : " " + html_escape(img.scale->unit));
    html += fmt::format("<figure><img alt=\"{0}\" src=\"data:image/png;base64,{1}\">{2}<figcaption>{0}{3}</figcaption></figure>\n",
                        html_escape(img.title), base64(bytes.str()), bar, img.note.empty() ? "" : ": " + html_escape(img.note));
    return true;
}

}  // namespace crex
