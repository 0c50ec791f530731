/// \file rif.h
/// RADIANCE's scene project files (`.rif`, what `rad` reads): which files make the scene and
/// from where it is seen. crex reads `materials`, `scene` and `illum` (in that order; a word
/// starting with '!' is a command, as in a scene file; `illum` files are read as scene files,
/// since crex does not run mkillum) and the first `view` (its options, `-vf FILE` read from
/// that file). Variable names may be shortened to their first three letters, as rad allows.
/// Of `render`'s options, crex takes `-bv` (back face visibility, which changes what the scene
/// shows); rad's other rendering settings (QUAL, render's other options, ...) are ignored.
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/scene/radiance/scene_text.h"
#include "runtime/scene/radiance_view.h"

namespace crex::radiance {

struct RifInput {
    bool is_command = false;
    Word file;        ///< a scene file named by the .rif
    Command command;  ///< or a '!' command written there
};

struct RifProject {
    std::vector<RifInput> inputs;  ///< in the order rad gives them to oconv
    std::string view_name;         ///< the first view's name ("" when it has none)
    std::vector<ViewWord> view;    ///< and its options (empty: the .rif has no view)
    bool back_faces_visible = true;  ///< `render = -bv-` makes it false
};

/// Reads `rif`; errors located in it.
RifProject read_rif(const SourceFile& rif, DiagnosticSink& sink);

}  // namespace crex::radiance
