/// \file sequence_flicker.h
/// The flicker (frame_flicker.h) of a sequence already on disk, for `crex compare --frames
/// --flicker`: each file a frame `crex run --camera-path` wrote, whose header names its scene
/// (`crex:scene`) and its view (`crex:view`, RADIANCE options). The scene is loaded once and
/// each frame's geometry traced from its view, so any two renderings of one walk are measured
/// alike, a reference sequence's included.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/api/frame_flicker.h"

namespace crex {

struct SequenceFlicker {
    /// Per file: its flicker against the file before it (none for the first, and where the
    /// one before is not the frame just before it, or where no pixel matched).
    std::vector<std::optional<FrameFlicker>> frames;
    std::string scene;  ///< the scene the geometry was traced in
};

/// `files` in frame order; `frame_numbers` their frames (a gap means no flicker across it);
/// `scene_spec` another scene than the first header's ("": the header's). "" or why not (a
/// file without the headers, a scene that does not load: said in full).
std::string sequence_flicker(const std::vector<std::string>& files, const std::vector<int64_t>& frame_numbers, const std::string& scene_spec,
                             SequenceFlicker& out);

}  // namespace crex
