/// \file partial_rows.h
/// Under mpirun, the rows rank 0 finished, written when the run fails before its outputs
/// (issue 19). A fault (a rank that hangs and is named by the watchdog, or one that reports a
/// failure) aborts the job; rank 0, if alive, first writes every -o image as NAME.partial.EXT
/// beside it (never the requested name, which is left as it was), atomically, holding the rows
/// that were final: its own band once it had rendered it, every band once the last exchange of
/// rows was done; the other rows are black, and the image's header says which rows are final.
/// mpirun ending the job from outside (SIGTERM to every rank when another rank died, e.g.
/// was SIGKILLed, or when mpirun was interrupted) writes them too: write_finished_rows_on_stop.
/// Rank 0 killed outright (SIGKILL, a crash) writes nothing: it holds the image.
/// A finished row is exactly that row of the image the run would have written. A pipeline
/// that varies subsample (apict, capict) interpolates across rows at the end: its rows are
/// final only once every band is in (a fault before then writes none).
#pragma once

#include <string>
#include <vector>

#include "runtime/io/image_io.h"
#include "runtime/render/film.h"

namespace crex::distributed {

/// NAME.partial.EXT for the output NAME.EXT.
std::string partial_path(const std::string& output);

/// Rank 0, before the render: where the finished rows would go (each of `outputs` as its
/// partial_path) and what the images say about themselves; from here a fault writes them.
void arm_partial_outputs(const std::vector<std::string>& outputs, int width, int height, ImageMetadata metadata);

/// Rank 0: rows [row_begin, row_end) of `film` (with its ambient stand-ins) are final; they
/// are kept as the image will show them (a plan without subsample variables).
void keep_finished_rows(const Film& film, const std::vector<double>& ambient, int row_begin, int row_end);
/// Rank 0: rows [row_begin, row_end) of the final image `rgb` (`width` pixels a row) are final.
void keep_finished_rows(const std::vector<float>& rgb, int width, int row_begin, int row_end);

/// Rank 0, once every rank is past its last exchange: the outputs themselves follow, and a
/// failure from here on is an ordinary one (nothing partial is written).
void disarm_partial_outputs();

/// The thread that takes SIGTERM, SIGINT and SIGHUP (stop_signals.h): while outputs are armed,
/// says on stderr that the run was ended from outside, writes the finished rows as a fault
/// does (never while keep_finished_rows is copying them) and ends the process with exit 3
/// (mpirun sends SIGKILL a second after SIGTERM; an image of finished rows takes
/// milliseconds). Otherwise returns: the signal then ends the process as it would have.
void write_finished_rows_on_stop(int signal);

}  // namespace crex::distributed
