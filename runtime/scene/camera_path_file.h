/// \file camera_path_file.h
/// Camera path files (`crex run --camera-path FILE`, docs/animation.md): a JSON path of keys,
/// or a RADIANCE file with one view per line (a `ranimate` / walkthrough view file: each line
/// `-vp x y z -vd x y z ...`, as `rpict -vf` reads one), line k the view of frame k. Which one
/// a file is goes by its text: JSON starts with `{` (after comments). Errors are located in
/// the file and reported with the scene codes: E301 malformed, E302 wrong type, E303 out of
/// range or out of order, E304 missing, E306 degenerate (an aim parallel to up, a camera at
/// its own look-at point, at constant speed a key repeated); unknown fields W301.
#pragma once

#include <optional>

#include "base/diagnostic.h"
#include "base/source.h"
#include "runtime/scene/camera_path.h"

namespace crex {

/// The path in `file`; nullopt when it has errors (said to `sink`). A view file's line k is at
/// time k / fps, so frame k at `fps` is its view.
std::optional<CameraPath> read_camera_path(const SourceFile& file, double fps, DiagnosticSink& sink);

}  // namespace crex
