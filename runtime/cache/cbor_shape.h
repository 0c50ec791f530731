/// \file cbor_shape.h
/// A non-recursive check that bytes are one well-formed CBOR item of bounded nesting with
/// definite lengths only, run before nlohmann's reader: that reader recurses per nesting level
/// and per chunk of an indefinite-length string, so a damaged file could overflow the stack
/// (found by tests/fuzz/ic_file_fuzzer.cpp). crex's files never use indefinite lengths.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace crex {

/// "" if `bytes` hold exactly one such item, else what is wrong and at which byte.
std::string check_cbor_shape(const std::vector<std::uint8_t>& bytes, int max_depth);

}  // namespace crex
