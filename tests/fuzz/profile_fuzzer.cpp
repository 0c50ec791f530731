// libFuzzer target: any bytes as a profile file (crex run --profile). Invariants: no crash,
// and a profile that loads holds only finite, non-negative costs.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "base/components.h"
#include "runtime/render/profile.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace crex;
    Profile p;
    std::string error = Profile::from_json_text(std::string(reinterpret_cast<const char*>(data), size), p);
    if (error.empty()) {
        for (const auto& row : kComponentTable)
            if (auto c = p.cost(row.component); c && !(std::isfinite(*c) && *c >= 0)) std::abort();
        if (auto c = p.camera_cost(); c && !(std::isfinite(*c) && *c >= 0)) std::abort();
    }
    return 0;
}
