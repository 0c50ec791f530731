#include "base/nearest_name.h"

#include <fmt/format.h>

#include <algorithm>

namespace crex {

size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= b.size(); ++j)
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

std::string did_you_mean(std::string_view name, const std::vector<std::string>& known) {
    std::string best;
    size_t best_d = std::max<size_t>(2, name.size() / 3) + 1;
    for (const auto& k : known) {
        size_t d = edit_distance(name, k);
        if (d < best_d) best_d = d, best = k;
    }
    return best.empty() ? "" : fmt::format("did you mean '{}'?", best);
}

}  // namespace crex
