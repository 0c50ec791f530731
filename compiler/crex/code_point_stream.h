/// \file code_point_stream.h
/// An ANTLRInputStream over code points decoded by decode_utf8() (ANTLR-side files only).
#pragma once

#include "antlr4-runtime.h"
#include "compiler/crex/parse_internal.h"

namespace crex::detail {

class CodePointStream : public antlr4::ANTLRInputStream {
public:
    explicit CodePointStream(const std::u32string& cps) {
        _data = cps;
        p = 0;
    }
};

}  // namespace crex::detail
