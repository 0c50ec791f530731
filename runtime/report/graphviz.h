/// \file graphviz.h
/// Drawing a DOT graph (a plan's) as SVG or PNG with Graphviz's `dot` program. It runs as a
/// child process with an argument vector, no shell, so no path or graph text is ever read as a
/// command; a program rather than libgvc keeps Graphviz's global state and its aborts on odd
/// input out of crex's process.
#pragma once

#include <string>

namespace crex {

/// Draws `dot_text` in `format` ("svg" or "png") into `output_path` (written atomically), or
/// onto this process's stdout when `output_path` is "". Returns "" or why not: `dot` is not
/// installed (said with the package to install), or what it said on failing.
std::string draw_graph(const std::string& dot_text, const std::string& format, const std::string& output_path);

/// A report's plan: `dot_text` written to DIR/plan.dot and drawn to DIR/plan.svg. Returns ""
/// or why plan.dot could not be written; `svg` gets the drawing, or "" when Graphviz could not
/// draw it (the page then shows the DOT text).
std::string write_plan_files(const std::string& dot_text, const std::string& dir, std::string& svg);

}  // namespace crex
