#include "runtime/scene/radiance/data_file.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>

#include "runtime/scene/data_table.h"

namespace crex::radiance {
namespace {

// RADIANCE's data arrays have at most this many dimensions (MAXDDIM).
constexpr int kMaxDimensions = 5;

class Words {
public:
    explicit Words(const std::string& t) : t_(t) {}
    // The next word; false at the end of the text.
    bool next(std::string_view& word) {
        while (i_ < t_.size()) {
            const char c = t_[i_];
            if (c == '#') {
                while (i_ < t_.size() && t_[i_] != '\n') ++i_;
            } else if (std::isspace(static_cast<unsigned char>(c))) {
                if (c == '\n') ++line_, line_start_ = i_ + 1;
                ++i_;
            } else {
                break;
            }
        }
        if (i_ >= t_.size()) return false;
        start_ = i_;
        while (i_ < t_.size() && !std::isspace(static_cast<unsigned char>(t_[i_])) && t_[i_] != '#') ++i_;
        word = std::string_view(t_).substr(start_, i_ - start_);
        return true;
    }
    DataFileError error(std::string message) const {
        return {std::move(message), line_, static_cast<int>(start_ - line_start_) + 1};
    }

private:
    const std::string& t_;
    size_t i_ = 0, start_ = 0, line_start_ = 0;
    int line_ = 1;
};

bool number(std::string_view w, double& out) {
    const char* b = w.data();
    if (!w.empty() && *b == '+') ++b;
    auto [end, ec] = std::from_chars(b, w.data() + w.size(), out);
    return ec == std::errc() && end == w.data() + w.size() && std::isfinite(out);
}

}  // namespace

bool parse_data_file(const std::string& text, DataTable& out, DataFileError& error) {
    Words words(text);
    std::string_view w;
    auto read = [&](double& v, const char* what) {
        if (!words.next(w)) {
            error = words.error(fmt::format("the file ends where {} was expected", what));
            return false;
        }
        if (!number(w, v)) {
            error = words.error(fmt::format("'{}' is not a number ({} was expected)", w, what));
            return false;
        }
        return true;
    };
    auto read_count = [&](int& n, const char* what, int lo, int hi) {
        double v;
        if (!read(v, what)) return false;
        if (!(v == std::floor(v) && v >= lo && v <= hi)) {
            error = words.error(fmt::format("{} must be a whole number from {} to {}, got '{}'", what, lo, hi, w));
            return false;
        }
        n = static_cast<int>(v);
        return true;
    };
    DataTable t;
    int dims = 0;
    if (!read_count(dims, "the number of dimensions", 1, kMaxDimensions)) return false;
    size_t total = 1;
    for (int d = 0; d < dims; ++d) {
        DataTable::Axis a;
        double end = 0;
        if (!read(a.origin, "a dimension's beginning") || !read(end, "a dimension's end") ||
            !read_count(a.count, "a dimension's number of points", 2, 1 << 24))
            return false;
        a.size = end - a.origin;
        if (a.size == 0) {  // the points are listed
            a.points.resize(static_cast<size_t>(a.count));
            for (double& p : a.points)
                if (!read(p, "a grid point")) return false;
            a.origin = a.points.front();
            a.size = a.points.back() - a.points.front();
        }
        total *= static_cast<size_t>(a.count);
        if (total > (size_t{1} << 28)) {
            error = words.error("the table has more than 2^28 values");
            return false;
        }
        t.axes.push_back(std::move(a));
    }
    t.values.resize(total);
    for (double& v : t.values)
        if (!read(v, "a value")) return false;
    if (std::string problem = data_table_problem(t); !problem.empty()) {
        error = words.error(problem);
        return false;
    }
    out = std::move(t);
    return true;
}

}  // namespace crex::radiance
