#include "runtime/api/sequence_outputs.h"

#include <fmt/format.h>

#include "compiler/sched/print.h"
#include "runtime/api/run_outputs.h"
#include "runtime/base/output_set.h"
#include "runtime/io/video_file.h"
#include "runtime/report/run_report.h"
#include "runtime/report/sequence_report.h"

namespace crex {
namespace {

SequenceFrameRow report_row(const FrameRun& f) {
    SequenceFrameRow row;
    row.frame = f.frame, row.time = f.time, row.skipped = f.skipped, row.high_quality = f.high_quality;
    row.seconds = f.seconds, row.render_seconds = f.render_seconds, row.budget_seconds = f.budget_seconds;
    row.records_made = f.records_made, row.records_reused = f.records_reused, row.rays = f.rays;
    row.inherited_pixels = f.inherited_pixels;
    row.flicker = f.flicker, row.flip = f.flip, row.relmse = f.relmse;
    if (!f.files.empty()) row.image = f.files.front();
    return row;
}

}  // namespace

std::string write_sequence_outputs(const SequenceOutputs& out, const std::vector<FrameRun>& frames, const RunInputs& in,
                                   const SequenceDescription& d, std::vector<std::string>& wrote) {
    if (!out.video.empty()) {
        std::vector<std::string> images;
        for (const FrameRun& f : frames)
            if (!f.files.empty()) images.push_back(f.files.front());
        if (std::string error = write_video(out.video, images, d.fps); !error.empty()) return "--video: " + error;
        wrote.push_back(fmt::format("{} ({} frames at {:g} fps)", out.video, images.size(), d.fps));
    }
    if (out.report_dir.empty()) return "";
    if (std::string refusal = report_folder_refusal(out.report_dir); !refusal.empty()) return refusal;
    OutputSet files;  // the folder is replaced whole, or not at all
    SequenceReport report;
    report.dir = files.stage_replacement_dir(out.report_dir);
    const std::string what = in.plan.staged ? "pipeline " + in.plan.name : sched::to_crex(in.plan.program);
    report.title = fmt::format("crex run: {} on {}, frames {}..{}", what, in.scene->scene->source, frames.empty() ? 0 : frames.front().frame,
                               frames.empty() ? 0 : frames.back().frame);
    report.summary = {{"scene", in.scene_spec}, {in.plan.staged ? "pipeline" : "crex", in.plan.staged ? in.plan.name : what}, {"camera path", d.camera_path},
                      {"size", fmt::format("{} x {}, {:g} frames a second", d.width, d.height, d.fps)}};
    if (d.processes > 1) report.summary.push_back({"processes", fmt::format("{}, each a run of consecutive frames", d.processes)});
    if (d.sequence_budget > 0)
        report.summary.push_back({"sequence budget", fmt::format("{:.2f} s: took {:.2f} s ({:+.1f} %)", d.sequence_budget, d.took,
                                                                 100 * (d.took / d.sequence_budget - 1))});
    for (const FrameRun& f : frames) report.frames.push_back(report_row(f));
    report.reference = d.reference;
    report.video = out.video;
    report.plan_dot = plan_dot_of(in);
    if (std::string error = write_sequence_report(report); !error.empty()) return "--report: " + files.in_user_terms(error);
    if (std::string error = files.commit(); !error.empty()) return "--report: " + error;
    wrote.push_back(out.report_dir + "/index.html");
    return "";
}

}  // namespace crex
