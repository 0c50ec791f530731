/// \file run_outputs.h
/// What a run leaves behind, all or none (runtime/base/output_set.h): the images with what made
/// them in their headers, the measured profile, the maps and per-pixel pictures, and the report
/// with its error curve; with the run's summary (run_summary.h) that the report and
/// `--format json` show.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "runtime/api/equal_time.h"
#include "runtime/api/resume.h"
#include "runtime/api/run.h"
#include "runtime/api/run_inputs.h"
#include "runtime/api/run_summary.h"
#include "runtime/report/checkpoints.h"
#include "runtime/report/error_curve.h"
#include "runtime/report/run_pictures.h"

namespace crex {

/// Where a run's files go ("" or empty: not written).
struct RunFiles {
    std::vector<std::string> images;  ///< .exr (float), .hdr, .png, ... (tone-mapped)
    bool components = false;          ///< EXR: a layer per component AOV as well
    std::string profile;              ///< the measured profile (`--profile` reads it back)
    std::string maps_dir;             ///< every map, the preview, per-pixel pictures
    std::string report_dir;           ///< checkpoints, error plot, images, plan, index.html
};

/// "" when an image can be written to `path` (a known format, not a directory, in a folder
/// that exists and takes a new file), else why not: checked before rendering. The folder is
/// not made (runtime/base/output_folder.h: only default outputs' folders are).
std::string check_output_path(const std::string& path);

/// "" when every output of `files` (and the cache file `ic_file`) can be written, else why not,
/// checked before rendering: an image's format or folder (a bad second -o was once found
/// after the first was written), a missing folder, --maps naming a file, a report folder that
/// is not a report, or two outputs on one path (then `usage` is set: the command line's fault).
std::string outputs_refusal(const RunFiles& files, const std::string& ic_file, bool& usage);

/// What the files and the summary are made of.
struct RunRecord {
    const RunInputs* inputs = nullptr;
    const RunOutcome* outcome = nullptr;          ///< with its result
    std::string plan_file;                        ///< the pipeline or plan file run ("" for a crex)
    const CheckpointRecorder* checkpoints = nullptr;
    std::optional<metrics::Image> reference;      ///< the error curve's
    std::string reference_path;
    std::vector<PolicyRun> other_policies;        ///< the same render under other policies
    std::optional<EqualTimeRun> equal_time;       ///< uniform rendering in the same time (--equal-time)
    const ResumedRows* resumed = nullptr;         ///< rows taken from a partial image
    int64_t frame = -1;                           ///< a frame of a sequence (frame_sequence.h): its number; -1 none
};

/// The plan as a report draws it (Graphviz DOT): the pipeline's stages, or the crex's plan.
std::string plan_dot_of(const RunInputs& in);

/// How the error curve and the report show images to the perceptual metrics: as HDR, at the
/// reference's exposure (1 without one).
metrics::DisplayView report_view(const metrics::Image* reference);

/// The final image as written: the result's, with a resumed run's final rows taken in.
std::vector<float> final_image(const RunRecord& record);

/// What write_run_files() made beside the files.
struct WrittenRun {
    nlohmann::json summary;          ///< the run's JSON summary, with the error curve and the report's path
    std::vector<CurvePoint> curve;   ///< the error against time (with a reference)
    PictureSummary pictures;         ///< the pictures written to `maps_dir`, where they are now
};

/// A pipeline's preview and guidance as a full render of it measured them (what a profile keeps
/// for a later budget to size its preview from).
StageCosts measured_stage_costs(const RunResult& result, int width, int height);

/// Writes `files`, all or none. Returns "" or what failed (nothing written then).
std::string write_run_files(const RunFiles& files, const RunRecord& record, WrittenRun& written);

/// A run's images as they will be written: their pixels and header taken from the record, so
/// they can be written after the record is gone (a sequence writes a frame while the next
/// one renders: frame_writer.h).
struct RunImages {
    std::vector<std::string> paths;
    int width = 0, height = 0;
    std::vector<ImageLayer> layers;  ///< the final image, then a layer per component when asked
    ImageMetadata metadata;
};
RunImages run_images(const RunFiles& files, const RunRecord& record);
/// Writes every image of `images`, all or none. Returns "" or what failed.
std::string write_run_images(const RunImages& images);

/// The summaries' view of a run (run_summary.h).
RunFacts run_facts(const RunFiles& files, const RunRecord& record, const WrittenRun* written);

}  // namespace crex
