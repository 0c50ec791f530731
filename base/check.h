/// \file check.h
/// Internal errors, kept apart from the user's: CREX_CHECK(cond) states an invariant the
/// compiler or the runtime relies on. When it fails it is a bug in crex, not bad input, so it
/// is reported as "internal error at file:line ... please report", never as a located
/// diagnostic or as "rendering failed". CREX_CHECK_EQ/_NE/_LT/_LE(a, b) also print both
/// values, so a report says what the numbers were, not only that they disagreed.
#pragma once

#include <sstream>
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

/// "expected a == b (3 vs 4)": the operands are evaluated once, here, only when the check fails
/// is the message built.
template <class A, class B>
[[noreturn]] void internal_compare_error(const char* file, int line, const char* expr, const A& a, const B& b) {
    std::ostringstream m;
    m << "expected " << expr << " (" << a << " vs " << b << ")";
    internal_error(file, line, m.str().c_str());
}

}  // namespace crex

#define CREX_CHECK_OP_(a, op, b)                                                                   \
    do {                                                                                           \
        const auto& crex_check_a_ = (a);                                                           \
        const auto& crex_check_b_ = (b);                                                           \
        if (!(crex_check_a_ op crex_check_b_))                                                     \
            ::crex::internal_compare_error(__FILE__, __LINE__, #a " " #op " " #b, crex_check_a_, crex_check_b_); \
    } while (false)
#define CREX_CHECK_EQ(a, b) CREX_CHECK_OP_(a, ==, b)
#define CREX_CHECK_NE(a, b) CREX_CHECK_OP_(a, !=, b)
#define CREX_CHECK_LT(a, b) CREX_CHECK_OP_(a, <, b)
#define CREX_CHECK_LE(a, b) CREX_CHECK_OP_(a, <=, b)

#define CREX_CHECK(cond) ((cond) ? static_cast<void>(0) : ::crex::internal_error(__FILE__, __LINE__, "expected " #cond))
