/// \file video_file.h
/// A preview video of a frame sequence (`crex run --camera-path ... --video walk.mp4`, issue
/// 36), encoded by Debian's `ffmpeg` when it is installed (optional: crex links no codec). The
/// frames are read back from the images the sequence wrote, shown as a viewer would see them:
/// an 8-bit file as stored, linear radiance (EXR) through the PNG tone map with the first
/// frame's exposure for all (an exposure that changed would flicker), and piped to ffmpeg as
/// raw RGB (H.264 in yuv420p, dimensions padded to even). No shell is run; the video is written
/// beside its path and renamed into place, so a failed encode leaves no file.
#pragma once

#include <string>
#include <vector>

namespace crex {

/// ffmpeg's path on PATH, or "" when it is not installed.
std::string find_video_encoder();

/// "" when `path`'s extension names a container the video is written in (.mp4, .mov, .mkv),
/// else what is wrong.
std::string check_video_path(const std::string& path);

/// Encodes `frames` (image files of one size, in order) at `fps` into `path`. "" or why not.
std::string write_video(const std::string& path, const std::vector<std::string>& frames, double fps);

}  // namespace crex
