#include "runtime/cache/cbor_shape.h"

namespace crex {

std::string check_cbor_shape(const std::vector<std::uint8_t>& bytes, int max_depth) {
    const size_t n = bytes.size();
    size_t at = 0;
    // Items still expected in each open array or map (a map's entries count twice).
    std::vector<uint64_t> open = {1};
    auto where = [&](size_t byte, const std::string& what) { return "at byte " + std::to_string(byte) + ": " + what; };
    while (!open.empty()) {
        if (open.back() == 0) {
            open.pop_back();
            continue;
        }
        --open.back();
        if (at >= n) return where(n, "unexpected end of input");
        const size_t start = at;
        const std::uint8_t initial = bytes[at++];
        const int major = initial >> 5, info = initial & 31;
        uint64_t arg = static_cast<uint64_t>(info);
        if (info >= 24 && info <= 27) {
            const size_t len = size_t{1} << (info - 24);
            if (n - at < len) return where(n, "unexpected end of input");
            arg = 0;
            for (size_t i = 0; i < len; ++i) arg = arg << 8 | bytes[at++];
        } else if (info == 31) {
            return where(start, "an indefinite length, which crex files never use");
        } else if (info > 27) {
            return where(start, "a reserved CBOR code");
        }
        switch (major) {
            case 2:  // byte string
            case 3:  // text string
                if (arg > n - at) return where(n, "unexpected end of input (a string of " + std::to_string(arg) + " bytes)");
                at += static_cast<size_t>(arg);
                break;
            case 4:  // array
            case 5:  // map
                // Each item takes at least a byte: a larger count is damage, not a big array.
                if (arg > n - at || (major == 5 && arg > (n - at) / 2))
                    return where(start, "a count of " + std::to_string(arg) + " items with " + std::to_string(n - at) +
                                            " bytes left");
                if (static_cast<int>(open.size()) > max_depth) return where(start, "nested deeper than " + std::to_string(max_depth) + " levels");
                open.push_back(major == 5 ? 2 * arg : arg);
                break;
            case 6:  // tag: one more item follows
                ++open.back();
                break;
            default:  // integers, simple values and floats: their argument was all
                break;
        }
    }
    if (at != n) return where(at, "bytes after the end of the data");
    return "";
}

}  // namespace crex
