// libFuzzer target: a saved profile of the right shape whose numbers are the fuzzer's (issue 37:
// a string or null for full_render_seconds ended `crex run` as an internal error). Random bytes
// rarely make JSON with these keys, so the shape is built here and only the values vary: each
// value is a number (from 8 bytes as a double, NaN and infinities written as JSON cannot, so as
// 1e999 and the like), a string, null, a bool, an array or an object. Invariants: no crash or
// exception; an accepted profile holds only finite costs in [0, kMaxSecondsPerRay] and a full
// render time in [0, kMaxFullRenderSeconds].
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include <fmt/format.h>

#include "base/components.h"
#include "runtime/render/profile.h"

namespace {

struct Bytes {
    const uint8_t* data;
    size_t size, at = 0;
    uint8_t byte() { return at < size ? data[at++] : 0; }
    double number() {
        uint64_t bits = 0;
        for (int i = 0; i < 8; ++i) bits = bits << 8 | byte();
        double v = 0;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
};

// One JSON value of a kind the first byte picks.
std::string value(Bytes& b) {
    switch (b.byte() % 10) {
    case 0: return "null";
    case 1: return "\"x\"";
    case 2: return b.byte() & 1 ? "true" : "false";
    case 3: return "[1]";
    case 4: return "{}";
    case 5: {  // whole, maybe huge or negative (a double outside int64's range has no cast)
        const double v = b.number();
        return std::isfinite(v) && std::fabs(v) < 9.2e18 ? std::to_string(static_cast<int64_t>(v)) : "-9223372036854775808";
    }
    case 6: return "1e999";
    case 7: return "-0";
    default: {
        const double v = b.number();
        return std::isfinite(v) ? fmt::format("{:.17g}", v) : "-1e999";
    }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    Bytes b{data, size};
    std::string text = "{\"format\": \"crex-profile\", \"version\": 1";
    if (b.byte() & 1) text += ", \"full_render_seconds\": " + value(b);
    text += ", \"seconds_per_ray\": {";
    const char* keys[] = {"camera", "D", "G", "S", "T", "R", "M"};
    bool first = true;
    for (const char* key : keys)
        if (b.byte() & 1) text += fmt::format("{}\"{}\": {}", first ? "" : ", ", key, value(b)), first = false;
    text += "}}";
    Profile p;
    double full = -1;
    const std::string error = Profile::from_json_text(text, p, &full, "fuzz.json");
    if (!error.empty()) {
        if (error.rfind("fuzz.json:", 0) != 0) std::abort();  // located
        return 0;
    }
    if (!(full >= 0 && full <= Profile::kMaxFullRenderSeconds)) std::abort();
    for (const auto& row : kComponentTable)
        if (auto c = p.cost(row.component); c && !(std::isfinite(*c) && *c >= 0 && *c <= Profile::kMaxSecondsPerRay)) std::abort();
    if (auto c = p.camera_cost(); c && !(std::isfinite(*c) && *c >= 0 && *c <= Profile::kMaxSecondsPerRay)) std::abort();
    return 0;
}
