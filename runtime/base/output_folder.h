/// \file output_folder.h
/// The folder an output goes into. A path the user typed (-o, --maps, --report, --save-profile)
/// must name a folder that exists: a typo in it is said before anything renders, not turned
/// into a new directory tree. Only default outputs (out/render.exr, a pipeline's `output`
/// block) have their folder made.
#pragma once

#include <string>

namespace crex {

/// "" when the folder `path` goes into exists (a bare name goes into the working directory),
/// else "cannot write 'PATH': its folder 'DIR' does not exist" (or "is not a folder").
std::string missing_output_folder(const std::string& path);

/// Makes the folder `path` goes into, with its parents; "" or why it cannot be made.
std::string make_output_folder(const std::string& path);

}  // namespace crex
