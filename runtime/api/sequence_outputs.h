/// \file sequence_outputs.h
/// What a sequence leaves besides its frames' images (docs/animation.md), written by the lead
/// after the last frame: its preview video (video_file.h) and its report (sequence_report.h),
/// which embeds the video. The report folder is written aside and swapped in whole, so a
/// failed report leaves the one before it as it was.
#pragma once

#include <string>
#include <vector>

#include "runtime/api/frame_sequence.h"
#include "runtime/api/run_inputs.h"

namespace crex {

struct SequenceOutputs {
    std::string video;       ///< --video ("": none)
    std::string report_dir;  ///< --report ("": none)
};

/// What the report says of the sequence beside its frames.
struct SequenceDescription {
    std::string camera_path;
    std::string reference;  ///< SequenceOptions::reference
    double fps = 30;
    int width = 0, height = 0;
    int processes = 1;
    double sequence_budget = 0, took = 0;  ///< seconds; budget 0: none
};

/// Writes the video (from the first image of every frame, skipped ones too), then the report.
/// "" or what failed, with the output named; `wrote` gets a line per output written.
std::string write_sequence_outputs(const SequenceOutputs& out, const std::vector<FrameRun>& frames, const RunInputs& in,
                                   const SequenceDescription& d, std::vector<std::string>& wrote);

}  // namespace crex
