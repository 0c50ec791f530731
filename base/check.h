/// \file check.h
/// Internal errors, kept apart from the user's: CREX_CHECK(cond) states an invariant the
/// compiler or the runtime relies on. When it fails it is a bug in crex, not bad input, so it
/// is reported as "internal error at file:line ... please report", never as a located
/// diagnostic or as "rendering failed".
#pragma once

#include <stdexcept>
#include <string>

namespace crex {

struct InternalError : std::logic_error {
    using std::logic_error::logic_error;
};

[[noreturn]] inline void internal_error(const char* file, int line, const char* what) {
    std::string f = file;
    if (auto at = f.rfind("/crex/"); at != std::string::npos) f = f.substr(at + 6);  // repo-relative where possible
    throw InternalError("internal error at " + f + ":" + std::to_string(line) + ": " + what +
                        " (a bug in crex: please report it with the command that caused it)");
}

}  // namespace crex

#define CREX_CHECK(cond) ((cond) ? static_cast<void>(0) : ::crex::internal_error(__FILE__, __LINE__, "expected " #cond))
