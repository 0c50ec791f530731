/// \file distributed_partial.h
/// Under mpirun, the rows rank 0 finished, written when the run fails before its outputs
/// (issue 19). A fault (a rank that hangs and is named by the watchdog, or one that reports a
/// failure) aborts the job; rank 0, if alive, first writes every -o image as NAME.partial.EXT
/// beside it (never the requested name, which is left as it was), atomically, holding the rows
/// that were final: its own band once it had rendered it, every band once the last exchange of
/// rows was done; the other rows are black, and the image's header says which rows are final.
/// A finished row is exactly that row of the image the run would have written, except under
/// a pipeline's component subsampling (capict), whose stand-ins are made only at the end.
#pragma once

#include <string>
#include <vector>

#include "runtime/io/image_io.h"
#include "runtime/render/film.h"

namespace crex::app {

/// NAME.partial.EXT for the output NAME.EXT.
std::string partial_path(const std::string& output);

/// Rank 0, before the render: where the finished rows would go (each of `outputs` as its
/// partial_path) and what the images say about themselves; from here a fault writes them.
void arm_partial_outputs(const std::vector<std::string>& outputs, int width, int height, ImageMetadata metadata);

/// Rank 0: rows [row_begin, row_end) of `film` (with its ambient stand-ins) are final; they
/// are kept as the image will show them.
void keep_finished_rows(const Film& film, const std::vector<double>& ambient, int row_begin, int row_end);

/// Rank 0, once every rank is past its last exchange: the outputs themselves follow, and a
/// failure from here on is an ordinary one (nothing partial is written).
void disarm_partial_outputs();

}  // namespace crex::app
