/// \file resume.h
/// `crex run ... --resume NAME.partial.exr` (issue 19): finishing a distributed run that
/// failed. The partial image (runtime/distributed/partial_rows.h) holds the rows rank 0 had finished; the
/// same command with --resume renders only the other rows and writes the whole image, equal
/// to the uninterrupted run's where that is exact:
///  - a plain crex: a pixel's value is the sum of its own samples (every random number keyed
///    by pixel and sample index), so the rows not final are rendered alone;
///  - a pipeline: guidance sees the whole image (saliency is normalised over it, maps are
///    blurred across rows), so the preview and every round but the last are rendered whole,
///    and only the last round's selective samples skip the final rows.
/// Equal up to the order of the film's sums: when the sample passes split differently (a
/// large image under --max-memory), a pixel's sum may differ in its last bits.
/// Refused, because the rows rendered again would not be the ones the run would have made: an
/// irradiance cache (its records, made by every row's queries in order, decide each pixel's
/// light), a budget (what is rendered depends on the time), a `subsample` variable (pixels
/// interpolated across rows: its partial holds no row or every row); `crex run` refuses outputs
/// the partial has no rows for too (--components, --maps, --report, --reference).
/// Warned: `--ambient auto` (a pipeline's default) when rays were left unexecuted, since their
/// stand-in is an average over every row's rays.
/// The partial must come from the same run: its header records the crex version, scene, crex,
/// pipeline, seed and the settings that decide pixels (size, spp, filter, shading limits,
/// ambient, rounds, --uniform); one that differs is named.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/driver/run_plan.h"
#include "runtime/io/image_io.h"

namespace crex {

/// The rows a failed distributed run finished, read back from its partial image.
struct ResumedRows {
    std::string path;
    std::vector<float> rgb;        ///< the partial image; rows not final are black
    std::vector<char> final_rows;  ///< per row
    std::string rows;              ///< "0..11" as the header says
};

/// What a partial image's header says about the run that made it (checked when resuming).
ImageMetadata partial_identity(const std::string& scene_spec, const PipelinePlan& plan, const RunSettings& settings);

/// Why a run with `settings` cannot finish a partial image exactly ("": it can).
std::string resume_refusal(const PipelinePlan& plan, const RunSettings& settings);

/// Reads and checks the partial image at `path` against this run. On failure `error` says
/// why, `io` whether reading it failed (rather than its being the wrong file).
struct ResumeLoad {
    std::optional<ResumedRows> rows;
    std::string error;
    bool io = false;        ///< the file could not be read (exit 3)
    bool bad_file = false;  ///< its header and pixels disagree (exit 1); else a usage error (exit 2)
};
ResumeLoad load_resume(const std::string& path, const std::string& scene_spec, const PipelinePlan& plan, const RunSettings& settings);

/// The final image of a resumed run: its final rows from the partial image.
void take_resumed_rows(const ResumedRows& resume, std::vector<float>& rgb, int width);

/// What a resumed run took from the partial, and a warning where its rows may differ from an
/// uninterrupted run's (automatic ambient stand-ins with rays left unexecuted).
void say_resumed(const ResumedRows& resume, const RunSettings& settings, const RunResult& result, std::ostream& err);

}  // namespace crex
