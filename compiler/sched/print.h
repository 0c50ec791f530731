/// \file print.h
/// Printers for the schedule IR:
///  - to_crex():  canonical crex text; lowering it again gives the same Program
///                (the round-trip property tests/unit/compiler/crex_roundtrip_test.cpp checks);
///  - dump():     an indented tree, one node per line, for debugging and golden tests;
///  - explain():  numbered steps in plain words (`crex check --explain`).
#pragma once

#include <string>

#include "compiler/sched/program.h"

namespace crex::sched {

std::string to_crex(const Program& program);
std::string to_crex(const Node& node);
std::string dump(const Program& program);
std::string explain(const Program& program);

}  // namespace crex::sched
