#include "compiler/pipeline/stdlib_pipelines.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "base/nearest_name.h"
#include "compiler/pipeline/resolve.h"

namespace crex::pipeline {
namespace {

bool is_bare_name(const std::string& s) {
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
    return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

std::filesystem::path pipelines_folder() { return std::filesystem::path(stdlib_dir()) / "pipelines"; }

}  // namespace

std::vector<std::string> stdlib_pipeline_names() {
    std::vector<std::string> names;
    std::error_code ec;
    const std::filesystem::path folder = pipelines_folder();
    for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::filesystem::path& p = it->path();
        std::error_code file_ec;
        if (p.extension() == ".pipe" && is_bare_name(p.stem().string()) && std::filesystem::is_regular_file(p, file_ec))
            names.push_back(p.stem().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

std::string stdlib_pipelines_said() {
    const std::vector<std::string> names = stdlib_pipeline_names();
    if (names.empty()) return "";
    std::string out = fmt::format("A stdlib pipeline runs by its name alone ('crex run sel_quiet'; a file of that name in the\n"
                                  "working folder comes first). The stdlib's, in {}:\n ",
                                  pipelines_folder().string());
    size_t column = 1;
    for (const std::string& name : names) {
        if (column + name.size() + 1 > 94) out += "\n ", column = 1;
        out += " " + name;
        column += name.size() + 1;
    }
    return out + "\n";
}

PipelineArgument pipeline_argument(const std::string& arg) {
    PipelineArgument a{arg, false, ""};
    std::error_code ec;
    if (!is_bare_name(arg) || std::filesystem::exists(arg, ec)) return a;
    const std::vector<std::string> names = stdlib_pipeline_names();
    if (std::binary_search(names.begin(), names.end(), arg)) {
        a.path = (pipelines_folder() / (arg + ".pipe")).string();
        a.stdlib = true;
        return a;
    }
    if (names.empty()) return a;
    const std::string guess = did_you_mean(arg, names);
    a.hint = fmt::format("nor is it a stdlib pipeline{}; the stdlib's, in {}: {}", guess.empty() ? "" : " (" + guess + ")",
                         pipelines_folder().string(), fmt::join(names, ", "));
    return a;
}

}  // namespace crex::pipeline
