/// \file generators.h
/// RADIANCE's generator programs, built in: the primitives they would print, with the same
/// identifiers (so names, -n prefixes and tags work as on RADIANCE's output).
///   genbox mat name x y z [-i] [-b bevel | -r radius]
///   genprism mat name N x1 y1 .. xN yN [-l lx ly lz] [-c] [-e]   (or the vertices from a file)
///   genrev mat name 'z(t)' 'r(t)' nseg [-e expr] [-f file] [-s]
/// Options they have that crex does not build are located errors naming the option.
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/radiance/command_line.h"
#include "runtime/scene/radiance/scene_text.h"

namespace crex::radiance {

/// Where a generator finds the files it is given (genprism's vertex file, genrev's -f).
struct GeneratorFiles {
    std::string dir;                        ///< the directory the command runs in
    std::vector<std::string> library_dirs;  ///< then these
    SceneSources* sources = nullptr;        ///< files read are kept here (errors point into them)
};

/// True when `name` is a generator crex runs.
bool is_generator(const std::string& name);

/// Runs the generator argv[0]. False (with located errors) when its arguments are wrong.
bool run_generator(const CommandWords& argv, const GeneratorFiles& files, std::vector<Primitive>& out, DiagnosticSink& sink);

/// The file `name` as RADIANCE finds it: as written when it starts with '/', '.' or '~'
/// (relative to `dir`), else in `dir` and then each library directory. Empty if not found.
std::string find_file(const std::string& name, const std::string& dir, const std::vector<std::string>& library_dirs);

}  // namespace crex::radiance
