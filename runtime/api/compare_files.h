/// \file compare_files.h
/// `crex compare` as a library call: how far an image file is from a reference file, by the
/// metrics of spec §7, as the command's JSON gives it. The reference may be a whole frame or a
/// windowed reference (`crex reference --window`: the test is scored on its windows alone); two
/// sequences are compared frame by frame, with their flicker on request.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "runtime/api/frame_sequence.h"
#include "runtime/metrics/image_comparison.h"

namespace crex {

struct CompareRequest {
    std::string test, reference;  ///< files; with `frames`, sequences named as `crex run -o` names them
    metrics::MetricChoice choice;
    std::string attention;        ///< "saliency" or a map file: weights of the attention-weighted FLIP ("": none)
    std::string flip_map;         ///< write the per-pixel FLIP here as a heat picture ("": none)
    double exposure = 0;          ///< the tone map's exposure for both HDR images (0: the reference's)
    bool assume_display = false;  ///< a tone-mapped file against a linear one: tone-map the linear one as crex writes PNGs
    std::optional<FrameRange> frames;  ///< compare sequences over these frames
    bool flicker = false;              ///< with frames: each sequence's flicker too
    std::string flicker_scene;         ///< the scene the frames are traced in ("": their headers')
};

/// What a comparison found (`result`, the command's JSON), or why it could not be made:
/// `status` an exit code of base/exit_codes.h (1 images of different sizes or kinds, 3 a file
/// that cannot be read or written) and `error` the message.
struct CompareOutcome {
    int status = 0;
    std::string error;
    nlohmann::json result;
};

CompareOutcome compare_files(const CompareRequest& request);

}  // namespace crex
