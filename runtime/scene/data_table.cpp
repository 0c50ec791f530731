#include "runtime/scene/data_table.h"

#include <fmt/format.h>

#include <cmath>

namespace crex {
namespace {

// Where `x` falls on `axis`: the grid interval's lower index i (0 .. count-2) and the
// position in grid steps (i + fraction; outside [0, count-1] beyond the ends).
void locate(const DataTable::Axis& axis, double x, int& i, double& at) {
    const int n = axis.count;
    if (axis.points.empty()) {
        at = (x - axis.origin) / axis.size * (n - 1);
        i = !(at >= 0) ? 0 : at > n - 2 ? n - 2 : static_cast<int>(at);
        if (!std::isfinite(at)) at = 0;
        return;
    }
    // Points rise or fall: a bisection for the interval holding x.
    const std::vector<double>& p = axis.points;
    const bool rising = p.back() > p.front();
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if ((x >= p[static_cast<size_t>(mid)]) == rising) lo = mid;
        else hi = mid;
    }
    i = lo;
    at = i + (x - p[static_cast<size_t>(i)]) / (p[static_cast<size_t>(i) + 1] - p[static_cast<size_t>(i)]);
    if (!std::isfinite(at)) at = i;
}

double value_from(const DataTable& t, size_t dim, size_t offset, const double* point) {
    const DataTable::Axis& axis = t.axes[dim];
    int i = 0;
    double x = 0;
    locate(axis, point[dim], i, x);
    size_t stride = 1;
    for (size_t d = dim + 1; d < t.axes.size(); ++d) stride *= static_cast<size_t>(t.axes[d].count);
    const size_t k = offset + static_cast<size_t>(i) * stride;
    double y0, y1;
    if (dim + 1 < t.axes.size()) {
        y0 = value_from(t, dim + 1, k, point);
        y1 = value_from(t, dim + 1, k + stride, point);
    } else {
        y0 = t.values[k];
        y1 = t.values[k + 1];
    }
    // One step of extrapolation, then a harmonic fall towards zero.
    if (x > i + 2) return (2 * y1 - y0) / (x - (i - 1));
    if (x < i - 1) return (2 * y0 - y1) / (i - x);
    return y0 * ((i + 1) - x) + y1 * (x - i);
}

}  // namespace

double data_value(const DataTable& table, const double* point) { return value_from(table, 0, 0, point); }

std::string data_table_problem(const DataTable& t) {
    if (t.axes.empty()) return "it has no dimensions";
    size_t total = 1;
    for (size_t d = 0; d < t.axes.size(); ++d) {
        const DataTable::Axis& a = t.axes[d];
        if (a.count < 2) return fmt::format("dimension {} has {} point{} (at least 2 are needed)", d + 1, a.count, a.count == 1 ? "" : "s");
        if (!a.points.empty()) {
            if (a.points.size() != static_cast<size_t>(a.count)) return fmt::format("dimension {} lists {} points, not {}", d + 1, a.points.size(), a.count);
            for (size_t k = 1; k < a.points.size(); ++k) {
                const bool rising = a.points[1] > a.points[0];
                if (!(rising ? a.points[k] > a.points[k - 1] : a.points[k] < a.points[k - 1]))
                    return fmt::format("dimension {}'s points are not in increasing or decreasing order", d + 1);
            }
        } else if (!(a.size != 0 && std::isfinite(a.size) && std::isfinite(a.origin))) {
            return fmt::format("dimension {} begins and ends at the same value", d + 1);
        }
        if (total > (size_t{1} << 28) / static_cast<size_t>(a.count)) return "it has more than 2^28 values";
        total *= static_cast<size_t>(a.count);
    }
    if (t.values.size() != total) return fmt::format("it has {} values where its dimensions need {}", t.values.size(), total);
    return "";
}

}  // namespace crex
