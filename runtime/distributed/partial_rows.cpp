#include "runtime/distributed/partial_rows.h"

#include <fmt/format.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>

#include "base/exit_codes.h"
#include "runtime/base/finished_rows_digest.h"
#include "runtime/base/output_set.h"

#ifdef CREX_WITH_MPI
#include "runtime/distributed/rank_watchdog.h"
#endif

namespace crex::distributed {
namespace {

struct Partial {
    std::vector<std::string> outputs;
    int width = 0, height = 0;
    ImageMetadata metadata;
    std::vector<float> rgb;     // black until a row is kept
    std::vector<char> finished;  // per row
};

// The rows are kept by the render's thread and written by a fault (that thread too) or by
// the thread that takes a stop signal (stop_signals.h): under one mutex, so that a buffer
// half-updated is never written. Never destroyed: a signal may come while the process exits.
struct Kept {
    std::mutex mutex;
    std::optional<Partial> partial;  // armed
};
Kept& kept() {
    static auto* k = new Kept;
    return *k;
}

// "0..47" or "0..47, 60..95": the finished rows as ranges.
std::string row_ranges(const std::vector<char>& finished) {
    std::string out;
    for (size_t r = 0; r < finished.size();) {
        if (!finished[r]) {
            ++r;
            continue;
        }
        size_t end = r;
        while (end < finished.size() && finished[end]) ++end;
        out += fmt::format("{}{}..{}", out.empty() ? "" : ", ", r, end - 1);
        r = end;
    }
    return out;
}

// Writes the kept rows and disarms (at most once); `lock` holds kept().mutex.
void write_kept_rows(const std::lock_guard<std::mutex>&) {
    if (!kept().partial) return;
    const Partial p = std::move(*kept().partial);
    kept().partial.reset();
    const std::string rows = row_ranges(p.finished);
    if (rows.empty()) {
        std::cerr << "crex run: rank 0 had no finished row (rows are final from the last exchange of rows on): nothing written\n";
        return;
    }
    const std::string what = fmt::format("rows {} of {} finished", rows, p.height);
    ImageMetadata metadata = p.metadata;
    metadata.push_back({"crex:partial", what + "; the other rows are black (the run failed; crex run ... --resume this file finishes it)"});
    metadata.push_back({"crex:finished_rows", rows});  // what --resume reads (runtime/api/resume.h)
    metadata.push_back({"crex:finished_rows_digest", finished_rows_digest(p.rgb, p.width, p.finished)});
    // Staged and committed together: a fault during the write leaves no half-written file.
    OutputSet files;
    std::vector<std::string> written;
    for (const auto& out : p.outputs) {
        const std::string path = partial_path(out);
        std::string error = write_image(files.stage_file(path), p.width, p.height, {{"", p.rgb}}, metadata);
        if (!error.empty()) {
            std::cerr << "crex run: error: writing the finished rows: " << files.in_user_terms(error) << "\n";
            return;
        }
        written.push_back(path);
    }
    if (std::string error = files.commit(); !error.empty()) {
        std::cerr << "crex run: error: writing the finished rows: " << error << "\n";
        return;
    }
    std::string list;
    for (const auto& w : written) list += (list.empty() ? "" : ", ") + w;
    std::cerr << fmt::format("crex run: {}, written to {} (the other rows black); the requested output{} not written\n", what, list,
                             p.outputs.size() == 1 ? " was" : "s were");
}

// On a fault, rank 0 (rank_watchdog.cpp calls it just before the abort).
void write_finished_rows() {
    const std::lock_guard<std::mutex> lock(kept().mutex);
    write_kept_rows(lock);
}

const char* signal_name(int signal) {
    switch (signal) {
        case SIGTERM: return "SIGTERM";
        case SIGINT: return "SIGINT";
        case SIGHUP: return "SIGHUP";
        default: return "a signal";
    }
}

}  // namespace

std::string partial_path(const std::string& output) {
    std::filesystem::path p(output);
    const std::string ext = p.extension().string();
    return (p.parent_path() / (p.stem().string() + ".partial" + ext)).string();
}

void arm_partial_outputs(const std::vector<std::string>& outputs, int width, int height, ImageMetadata metadata) {
    Partial p;
    p.outputs = outputs;
    p.width = width, p.height = height;
    p.metadata = std::move(metadata);
    p.rgb.assign(3 * static_cast<size_t>(width) * static_cast<size_t>(height), 0.0f);
    p.finished.assign(static_cast<size_t>(height), 0);
    // Now, not when a fault comes: after mpirun's SIGTERM the write has a second (an error
    // loading it is said by the write, as by any other).
    if (std::any_of(outputs.begin(), outputs.end(), needs_image_plugin)) load_image_plugin();
    {
        const std::lock_guard<std::mutex> lock(kept().mutex);
        kept().partial = std::move(p);
    }
#ifdef CREX_WITH_MPI
    set_fault_writer(write_finished_rows);
#endif
}

void keep_finished_rows(const Film& film, const std::vector<double>& ambient, int row_begin, int row_end) {
    {
        const std::lock_guard<std::mutex> lock(kept().mutex);
        if (!kept().partial || film.width() != kept().partial->width || film.height() != kept().partial->height) return;
    }
    // The composite as RunResult::image() makes it for a plan without subsample variables; the
    // film is this thread's, only the copy into the kept rows needs the lock.
    keep_finished_rows(film.composite(&ambient), film.width(), row_begin, row_end);
}

void keep_finished_rows(const std::vector<float>& rgb, int width, int row_begin, int row_end) {
    const std::lock_guard<std::mutex> lock(kept().mutex);
    if (!kept().partial || width != kept().partial->width || rgb.size() != kept().partial->rgb.size()) return;  // or written meanwhile
    Partial& p = *kept().partial;
    const size_t row = 3 * static_cast<size_t>(width);
    row_begin = std::max(row_begin, 0), row_end = std::min(row_end, p.height);
    for (int r = row_begin; r < row_end; ++r) {
        const auto at = static_cast<std::ptrdiff_t>(static_cast<size_t>(r) * row);
        std::copy_n(rgb.begin() + at, row, p.rgb.begin() + at);
        p.finished[static_cast<size_t>(r)] = 1;
    }
}

void disarm_partial_outputs() {
    {
        const std::lock_guard<std::mutex> lock(kept().mutex);  // waits for a write under way
        kept().partial.reset();
    }
#ifdef CREX_WITH_MPI
    set_fault_writer(nullptr);
#endif
}

void write_finished_rows_on_stop(int signal) {
    const std::lock_guard<std::mutex> lock(kept().mutex);
    if (!kept().partial) return;  // nothing armed (or already written): the signal's default action
    std::cerr << fmt::format("crex run: error: the run was ended from outside ({} to rank 0): mpirun does so when a rank dies, "
                             "and names it, or when it is interrupted\n",
                             signal_name(signal));
    write_kept_rows(lock);
    std::cerr << std::flush;
    // Within mpirun's second before SIGKILL; no exit handlers (other threads still render).
    std::_Exit(kExitFailure);
}

}  // namespace crex::distributed
