#include "runtime/base/output_set.h"

#include <fcntl.h>
#include <stdio.h>
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

// `staged` (a folder) becomes `destination`; the old destination, if any, is removed. One
// rename where the kernel can exchange two names atomically (renameat2, Linux 3.15), so a
// reader never sees the folder missing; else two renames, the old folder put back if the
// second fails.
std::string swap_into_place(const std::string& staged, const std::string& destination) {
    std::error_code ec;
    if (!fs::exists(destination, ec)) {
        if (std::rename(staged.c_str(), destination.c_str()) != 0)
            return "cannot move '" + destination + "' into place: " + std::strerror(errno);
        return "";
    }
    if (::renameat2(AT_FDCWD, staged.c_str(), AT_FDCWD, destination.c_str(), RENAME_EXCHANGE) == 0) {
        fs::remove_all(staged, ec);  // the old folder, now under the staged name
        return "";
    }
    const std::string old = staged + ".old";
    fs::remove_all(old, ec);
    if (std::rename(destination.c_str(), old.c_str()) != 0)
        return "cannot move the old '" + destination + "' aside: " + std::strerror(errno);
    if (std::rename(staged.c_str(), destination.c_str()) != 0) {
        std::string why = std::strerror(errno);
        std::rename(old.c_str(), destination.c_str());
        return "cannot move '" + destination + "' into place: " + why;
    }
    fs::remove_all(old, ec);
    return "";
}

}  // namespace

OutputSet::~OutputSet() {
    std::error_code ec;
    for (const Entry& e : entries_) fs::remove_all(e.staged, ec);
}

std::string OutputSet::stage_file(const std::string& destination) {
    entries_.push_back({staged_name(destination, false), destination, false});
    return entries_.back().staged;
}

std::string OutputSet::stage_dir(const std::string& destination) {
    fs::path d(destination);
    if (d.filename().empty()) d = d.parent_path();  // "maps/" is "maps"
    Entry e{staged_name(d, true), d.string(), true};
    std::error_code ec;
    fs::remove_all(e.staged, ec);  // a leftover of a killed run of this pid
    fs::create_directory(e.staged, ec);
    entries_.push_back(e);
    return e.staged;
}

std::string OutputSet::stage_replacement_dir(const std::string& destination) {
    std::string staged = stage_dir(destination);
    entries_.back().replaces = true;
    return staged;
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
    for (const Entry& e : entries_) {
        std::error_code status;
        if (e.replaces && fs::exists(e.destination, status) && !fs::is_directory(e.destination, status))
            problem = "'" + e.destination + "' is a file, not a folder";
        if (e.replaces) continue;  // its files go with their folder
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
    }
    if (!problem.empty()) return problem + "; no output was written";
    for (const Entry& e : entries_) {
        if (e.replaces) {
            problem = swap_into_place(e.staged, e.destination);
            if (!problem.empty()) return problem;
            continue;
        }
        for_each_file(e.staged, e.destination, e.directory, [&](const fs::path& from, const fs::path& to) {
            if (!problem.empty()) return;
            std::error_code ec;
            // A directory output's subfolders (report/images) are made; a file's folder exists.
            if (e.directory) fs::create_directories(to.parent_path(), ec);
            if (std::rename(from.c_str(), to.c_str()) != 0)
                problem = "cannot move '" + to.string() + "' into place: " + std::strerror(errno);
        });
        if (!problem.empty()) return problem;
    }
    return "";
}

}  // namespace crex
