#include "runtime/base/output_set.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace crex {
namespace fs = std::filesystem;

namespace {

std::string staged_name(const fs::path& destination, bool directory) {
    // Hidden, beside the destination, named by the process: two runs never share one.
    std::string name = "." + destination.filename().string() + ".crex-staged-" + std::to_string(::getpid());
    if (!directory) name += destination.extension().string();
    return (destination.parent_path() / name).string();
}

// Every (staged file, destination file) pair of an entry.
template <typename F>
void for_each_file(const std::string& staged, const std::string& destination, bool directory, F&& f) {
    if (!directory) {
        f(fs::path(staged), fs::path(destination));
        return;
    }
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(staged, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->is_regular_file(ec)) f(it->path(), fs::path(destination) / fs::relative(it->path(), staged, ec));
}

}  // namespace

OutputSet::~OutputSet() {
    std::error_code ec;
    for (const Entry& e : entries_) fs::remove_all(e.staged, ec);
}

std::string OutputSet::stage_file(const std::string& destination) {
    std::error_code ec;
    fs::path parent = fs::path(destination).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    entries_.push_back({staged_name(destination, false), destination, false});
    return entries_.back().staged;
}

std::string OutputSet::stage_dir(const std::string& destination) {
    fs::path d(destination);
    if (d.filename().empty()) d = d.parent_path();  // "maps/" is "maps"
    std::error_code ec;
    if (!d.parent_path().empty()) fs::create_directories(d.parent_path(), ec);
    Entry e{staged_name(d, true), d.string(), true};
    fs::remove_all(e.staged, ec);  // a leftover of a killed run of this pid
    fs::create_directories(e.staged, ec);
    entries_.push_back(e);
    return e.staged;
}

std::string OutputSet::destination_of(const std::string& staged) const {
    for (const Entry& e : entries_) {
        if (staged == e.staged) return e.destination;
        if (e.directory && staged.rfind(e.staged + "/", 0) == 0) return e.destination + staged.substr(e.staged.size());
    }
    return staged;
}

std::string OutputSet::in_user_terms(std::string message) const {
    for (const Entry& e : entries_)
        for (size_t at = message.find(e.staged); at != std::string::npos; at = message.find(e.staged, at + e.destination.size()))
            message.replace(at, e.staged.size(), e.destination);
    return message;
}

std::string OutputSet::commit() {
    // First every destination, so that one that cannot take its file moves nothing.
    std::string problem;
    for (const Entry& e : entries_)
        for_each_file(e.staged, e.destination, e.directory, [&](const fs::path&, const fs::path& to) {
            if (!problem.empty()) return;
            std::error_code ec;
            fs::path dir = to.parent_path();
            if (!dir.empty()) {
                for (fs::path up = dir; !up.empty() && up != up.parent_path(); up = up.parent_path())
                    if (fs::exists(up, ec) && !fs::is_directory(up, ec)) {
                        problem = "'" + up.string() + "' is in the way of '" + to.string() + "': it is not a directory";
                        return;
                    }
            }
            if (fs::is_directory(to, ec)) problem = "'" + to.string() + "' is a directory";
        });
    if (!problem.empty()) return problem + "; no output was written";
    for (const Entry& e : entries_) {
        for_each_file(e.staged, e.destination, e.directory, [&](const fs::path& from, const fs::path& to) {
            if (!problem.empty()) return;
            std::error_code ec;
            if (!to.parent_path().empty()) fs::create_directories(to.parent_path(), ec);
            if (std::rename(from.c_str(), to.c_str()) != 0)
                problem = "cannot move '" + to.string() + "' into place: " + std::strerror(errno);
        });
        if (!problem.empty()) return problem;
    }
    return "";
}

}  // namespace crex
