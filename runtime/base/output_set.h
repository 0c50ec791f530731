/// \file output_set.h
/// A run's outputs, written all or none. Every file is first written (by the usual atomic
/// writers) to a staged name beside its destination, directories to a staged directory beside
/// theirs; commit() checks that every destination can take its file, then renames them all
/// into place. A run that fails before commit() leaves every old output as it was and no
/// staged file behind (the destructor removes them).
#pragma once

#include <string>
#include <vector>

namespace crex {

class OutputSet {
public:
    OutputSet() = default;
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;
    ~OutputSet();

    /// The path to write the file `destination` to now (same directory and extension, so the
    /// writer picks the same format and the final rename stays on one file system). The
    /// destination's folder must exist (runtime/base/output_folder.h).
    std::string stage_file(const std::string& destination);
    /// A directory to write the files of `destination` (a directory) into now. On commit each
    /// file moves to the same relative path under `destination`; other files there stay.
    std::string stage_dir(const std::string& destination);
    /// A directory that becomes `destination` whole on commit: a sibling folder, swapped in by
    /// one rename; what `destination` held before is removed. The caller decides that the old
    /// folder may go (a report's: runtime/report/run_report.h).
    std::string stage_replacement_dir(const std::string& destination);

    /// Where a staged path (a file staged, or a file under a staged directory) will end up.
    std::string destination_of(const std::string& staged) const;

    /// `message` (a writer's error) with staged paths said as their destinations.
    std::string in_user_terms(std::string message) const;

    /// Moves everything into place; "" on success, else what failed. Every destination is
    /// checked first (its folder exists, it is not a directory itself; a replaced directory is
    /// not a file): if one cannot take its file, nothing is moved.
    std::string commit();

private:
    struct Entry {
        std::string staged, destination;
        bool directory = false;
        bool replaces = false;  ///< a directory that replaces its destination whole
    };
    std::vector<Entry> entries_;
};

}  // namespace crex
