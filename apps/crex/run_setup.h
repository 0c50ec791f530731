/// \file run_setup.h
/// From `crex run`'s options to the driver's settings: image size, shading limits, the budget
/// and the profile it is predicted from, the irradiance cache, the reference the error curve
/// is measured against. Everything here is checked before a ray is traced.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "apps/crex/run_input.h"
#include "apps/crex/run_options.h"
#include "runtime/driver/run_plan.h"
#include "runtime/metrics/metrics.h"
#include "runtime/render/profile.h"

namespace crex::app {

/// --resume: the rows a failed distributed run finished (run_resume.h).
struct ResumedRows {
    std::string path;
    std::vector<float> rgb;        ///< the partial image; rows not final are black
    std::vector<char> final_rows;  ///< per row
    std::string rows;              ///< "0..11" as the header says
};

struct RunSetup {
    RunSettings settings;
    Profile profile;                 ///< read from --profile, measured into during the run
    std::optional<Profile> predicted;  ///< --profile as read: what the budget predicted from
    double full_render_seconds = 0;  ///< the profile's, for budgets in %
    double budget = 0;               ///< seconds, 0: none
    std::optional<metrics::Image> reference;
    std::string reference_file;
    std::vector<std::string> outputs;
    std::string maps_dir;
    std::optional<ResumedRows> resume;
};

/// Fills `setup` (which must not move afterwards: the settings point into it). Returns an exit
/// code on failure (the error printed), std::nullopt when the run can go on.
struct OutputPathFailure {
    std::string message;
    int exit_code;
};
/// Whether an image can be written to `path`: a known format, not a directory, a directory
/// that exists (made if missing) and takes a new file. Checked before rendering.
std::optional<OutputPathFailure> check_output_path(const std::string& path);

std::optional<int> make_run_setup(const RunOptions& opt, const RunInput& in, RunSetup& setup);

/// --ambient: "auto" or a radiance (into opt.ambient / opt.ambient_auto). Returns an exit code
/// on a malformed value (the error printed if `say`: under mpirun by rank 0 only).
std::optional<int> parse_ambient(RunOptions& opt, bool say = true);

}  // namespace crex::app
