/// \file run_resume.h
/// `crex run ... --resume NAME.partial.exr` (issue 19): finishing a distributed run that
/// failed. The partial image (distributed_partial.h) holds the rows rank 0 had finished; the
/// same command with --resume renders only the other rows and writes the whole image, equal
/// to the uninterrupted run's where that is exact:
///  - a plain crex: a pixel's value is the sum of its own samples (every random number keyed
///    by pixel and sample index), so the rows not final are rendered alone;
///  - a pipeline: guidance sees the whole image (saliency is normalised over it, maps are
///    blurred across rows), so the preview and every round but the last are rendered whole,
///    and only the last round's selective samples skip the final rows.
/// Equal up to the order of the film's sums: when the sample passes split differently (a
/// large image under --max-memory), a pixel's sum may differ in its last bits.
/// Refused (exit 2), because the rows rendered again would not be the ones the run would have
/// made: an irradiance cache (its records, made by every row's queries in order, decide each
/// pixel's light), a budget (what is rendered depends on the time), a `subsample` variable
/// (pixels interpolated across rows: its partial holds no row or every row), and outputs the
/// partial has no rows for (--components, --maps, --report, --reference). Under mpirun: not yet.
/// Warned: `--ambient auto` (a pipeline's default) when rays were left unexecuted, since their
/// stand-in is an average over every row's rays.
/// The partial must come from the same run: its header records the crex version, scene, crex,
/// pipeline, seed and the settings that decide pixels (size, spp, filter, shading limits,
/// ambient, rounds, --uniform); one that differs is named (exit 2).
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "apps/crex/run_input.h"
#include "apps/crex/run_options.h"
#include "apps/crex/run_setup.h"
#include "runtime/io/image_io.h"

namespace crex::app {

/// What a partial image's header says about the run that made it (checked by --resume).
ImageMetadata partial_identity(const RunInput& in, const RunSetup& setup);

/// --resume: reads and checks the partial image, marks its final rows in the settings and
/// keeps them in `setup.resume`. An exit code when it cannot resume (said on stderr).
std::optional<int> load_resume(const RunOptions& opt, const RunInput& in, RunSetup& setup);

/// A digest of the finished rows' pixels (FNV-1a over their float bits, as hex), written into a
/// partial's header (crex:finished_rows_digest) and checked by --resume: a header that names
/// rows its pixels do not hold (edited, or another image's) resumed into black rows.
std::string finished_rows_digest(const std::vector<float>& rgb, int width, const std::vector<char>& rows);

/// The final image of a resumed run: its final rows from the partial image.
void take_resumed_rows(const ResumedRows& resume, std::vector<float>& rgb, int width);

/// What a resumed run took from the partial, and a warning where its rows may differ from an
/// uninterrupted run's (--ambient auto with rays left unexecuted).
void say_resumed(const ResumedRows& resume, const RunSettings& settings, const RunResult& result, std::ostream& err);

}  // namespace crex::app
