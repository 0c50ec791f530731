/// \file radiance_view.h
/// RADIANCE view options (-vp -vd -vu -vh -vv -vo and the view types -vtv -vtl -vta -vth
/// -vts -vtc), from a .vf file, a `#@crex view` line of a .rad scene, or `crex run --view
/// FILE.vf`. Errors are located in the text they came from (E301 missing numbers, E302 not a
/// number, E303 angle, E306 degenerate frame, E307 unknown view type); unknown options are
/// W301.
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "base/source.h"
#include "runtime/scene/scene.h"

namespace crex {

struct ViewWord {
    std::string text;
    uint32_t begin = 0, end = 0;  ///< byte offsets in the source
};

/// Words of a view file: comments (#) dropped, a leading program name ("rpict", "rview") skipped.
std::vector<ViewWord> view_file_words(const SourceFile& vf);

/// Applies the options to `camera`; `fresh`: from RADIANCE's defaults first (-vp 0 0 0 -vd 0 1 0
/// -vu 0 0 1 -vh 45 -vv 45), as a view file is read.
void apply_radiance_view(const SourceFile& file, const std::vector<ViewWord>& words, Camera& camera, bool fresh, DiagnosticSink& sink);

}  // namespace crex
