/// \file command_line.h
/// A `!` command split into words as a POSIX shell would split the simple pipelines scene
/// files hold: blanks separate words, '...' is literal, "..." and a backslash escape, `|`
/// separates the stages of a pipeline. Anything that needs a shell to mean something
/// (redirection, `;`, `&`, `$`, backquotes, globbing) is refused where it stands: crex never
/// runs a shell.
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/scene/radiance/scene_text.h"

namespace crex::radiance {

using CommandWords = std::vector<Word>;

/// The stages of `c` (at least one, each with at least one word). False with a located error
/// when it is not such a pipeline.
bool split_command_line(const Command& c, std::vector<CommandWords>& stages, DiagnosticSink& sink);

/// Only the texts.
std::vector<std::string> texts(const CommandWords& words, size_t first = 0);

}  // namespace crex::radiance
