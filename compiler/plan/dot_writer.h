/// \file dot_writer.h
/// Pieces shared by the plan emitters: a schedule tree as JSON, and a DOT writer that draws
/// steps in execution order, groups as clusters and repeats as labelled back edges.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "compiler/sched/program.h"

namespace crex {

nlohmann::json schedule_to_json(const sched::Node& n);

/// Escapes a DOT label (quotes and backslashes), keeping the "\n" line breaks labels use.
std::string escape_dot(const std::string& s);

struct DotWriter {
    std::string out;
    int next_id = 0;
    std::string last;  ///< id of the last step emitted: steps chain in execution order

    /// A step node chained after `last`; `dead` draws it dashed. Returns its id.
    std::string step(const std::string& label, const std::string& tooltip, bool dead);
    /// A whole schedule tree.
    void node(const sched::Node& n);
};

}  // namespace crex
