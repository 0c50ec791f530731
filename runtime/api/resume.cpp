#include "runtime/api/resume.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <regex>
#include <sstream>

#include "compiler/sched/print.h"
#include "runtime/api/run_description.h"
#include "runtime/base/finished_rows_digest.h"
#include "runtime/base/file_extension.h"

namespace crex {
namespace {

// The items of pixel_settings_text(): a partial and the run resuming it must agree on each.
std::vector<std::string> items(const std::string& text) {
    std::vector<std::string> out;
    for (size_t at = 0; at <= text.size();) {
        size_t end = text.find(", ", at);
        if (end == std::string::npos) end = text.size();
        out.push_back(text.substr(at, end - at));
        at = end + 2;
    }
    return out;
}

// "0..11, 20..24" into `rows` (height of them); false when malformed or out of range.
bool parse_rows(const std::string& text, int height, std::vector<char>& rows) {
    rows.assign(static_cast<size_t>(height), 0);
    static const std::regex range(R"(^([0-9]+)\.\.([0-9]+)$)");
    for (const std::string& item : items(text)) {
        std::smatch m;
        if (!std::regex_match(item, m, range)) return false;
        const long first = std::stol(m[1]), last = std::stol(m[2]);
        if (first > last || last >= height) return false;
        std::fill(rows.begin() + first, rows.begin() + last + 1, char{1});
    }
    return true;
}

}  // namespace

ImageMetadata partial_identity(const std::string& scene_spec, const PipelinePlan& plan, const RunSettings& settings) {
    return {{"Software", std::string("crex ") + CREX_VERSION},
            {"crex:version", CREX_VERSION},
            {"crex:scene", scene_spec},
            {"crex:crex", sched::to_crex(plan.program)},
            {"crex:pipeline", plan.staged ? plan.name : "none"},
            {"crex:seed", std::to_string(settings.seed)},
            {"crex:settings", pixel_settings_text(settings)}};
}

std::string resume_refusal(const PipelinePlan& plan, const RunSettings& settings) {
    if (settings.irradiance_cache)
        return "an irradiance cache: its records, made by every row's queries in order, decide each pixel's light, so rows "
               "rendered again would not be the run's";
    if (settings.executor.budget_seconds > 0)
        return "a budget: what a run renders depends on the time it had (--no-budget renders everything)";
    for (const PlanVariable& v : plan.variables)
        if (v.variable == pipeline::SelectiveVariable::kSubsample)
            return "a pipeline that varies subsample: its pixels are interpolated across rows at the end, so rows cannot be "
                   "rendered apart (its partial image holds no row or every row: then it is the whole image already)";
    return {};
}

ResumeLoad load_resume(const std::string& path, const std::string& scene_spec, const PipelinePlan& plan, const RunSettings& s) {
    ResumeLoad out;
    auto fail = [&](const std::string& why, bool io) {
        out.error = why, out.io = io;
        return out;
    };
    auto fail_input = [&](const std::string& why) {
        out.error = why, out.bad_file = true;
        return out;
    };
    if (std::string why = resume_refusal(plan, s); !why.empty()) return fail("cannot resume a run with " + why, false);
    const std::string ext = lower_extension(path);
    if (ext != ".exr") return fail("give the .exr partial image (the rows as rendered; other formats are tone-mapped or rounded)", false);
    int width = 0, height = 0;
    ImageMetadata header;
    if (std::string error = read_image_metadata(path, width, height, header); !error.empty()) return fail(error, true);
    const std::string rows = attribute_text(header, "crex:finished_rows");
    if (rows.empty()) return fail("not a partial image of crex run (its header has no crex:finished_rows)", false);
    // The same run: every attribute the partial recorded about it, and the size.
    for (const ImageAttribute& identity : partial_identity(scene_spec, plan, s)) {
        const std::string& key = identity.name;
        const std::string expected = identity.text();
        if (key == "Software") continue;
        const std::string found = attribute_text(header, key);
        if (found == expected) continue;
        const std::string name = key == "crex:version" ? "crex version" : key.substr(key.find(':') + 1);
        std::string what = fmt::format("{} '{}', this run's '{}'", name, found, expected);
        if (key == "crex:settings") {  // name the setting that differs
            const std::vector<std::string> a = items(found), b = items(expected);
            for (size_t k = 0; k < std::max(a.size(), b.size()); ++k)
                if (k >= a.size() || k >= b.size() || a[k] != b[k]) {
                    what = fmt::format("{}, this run has {}", k < a.size() ? a[k] : "(none)", k < b.size() ? b[k] : "(none)");
                    break;
                }
        }
        return fail(fmt::format("it is not a partial of this run: it was rendered with {} (resume with the failed run's inputs "
                                "and options)",
                                what),
                    false);
    }
    if (width != s.width || height != s.height) return fail(fmt::format("it is {}x{}, this run {}x{}", width, height, s.width, s.height), false);
    ResumedRows r;
    r.path = path;
    r.rows = rows;
    if (!parse_rows(rows, height, r.final_rows)) return fail(fmt::format("its crex:finished_rows '{}' is not rows of {}", rows, height), false);
    int w = 0, h = 0;
    if (std::string error = read_image(path, w, h, r.rgb); !error.empty()) return fail(error, true);
    if (w != width || h != height || r.rgb.size() != 3 * static_cast<size_t>(w) * static_cast<size_t>(h))
        return fail("its pixels do not match its header", true);
    // Its header against its pixels: the digest crex wrote of the finished rows, and every
    // finished pixel finite (a header saying more than the file holds resumed into black rows).
    const std::string digest = attribute_text(header, "crex:finished_rows_digest");
    if (digest != finished_rows_digest(r.rgb, width, r.final_rows))
        return fail_input(digest.empty() ? "its header has no crex:finished_rows_digest: it was not written by this crex's partial writer"
                                         : fmt::format("its crex:finished_rows '{}' names rows its pixels do not hold (their digest differs "
                                                       "from the header's): the file was changed after crex wrote it; render again without "
                                                       "--resume",
                                                       rows));
    for (size_t row = 0; row < r.final_rows.size(); ++row)
        for (size_t i = 3 * row * static_cast<size_t>(width); r.final_rows[row] && i < 3 * (row + 1) * static_cast<size_t>(width); ++i)
            if (!std::isfinite(r.rgb[i]) || r.rgb[i] < 0)
                return fail_input(fmt::format("row {} is named finished but holds a non-finite or negative value", row));
    out.rows = std::move(r);
    return out;
}

void take_resumed_rows(const ResumedRows& resume, std::vector<float>& rgb, int width) {
    const size_t row = 3 * static_cast<size_t>(width);
    for (size_t r = 0; r < resume.final_rows.size(); ++r)
        if (resume.final_rows[r] && (r + 1) * row <= rgb.size() && (r + 1) * row <= resume.rgb.size())
            std::copy_n(resume.rgb.begin() + static_cast<std::ptrdiff_t>(r * row), row, rgb.begin() + static_cast<std::ptrdiff_t>(r * row));
}

void say_resumed(const ResumedRows& resume, const RunSettings& settings, const RunResult& result, std::ostream& err) {
    err << fmt::format("crex run: note: rows {} of {} taken from {}; this run rendered the others (the rays and times below are "
                       "its own)\n",
                       resume.rows, resume.final_rows.size(), resume.path);
    size_t left = 0;
    for (size_t c : result.rays_left) left += c;
    if (settings.ambient_auto && left > 0)
        err << fmt::format("crex run: warning: --resume: {} rays were left unexecuted and --ambient auto stood them in with what "
                           "this run's rays of their component brought back on average, not the uninterrupted run's (it also "
                           "traced the final rows): the rows rendered here may differ slightly from that run's\n",
                           left);
}

}  // namespace crex
