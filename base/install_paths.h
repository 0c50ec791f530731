/// \file install_paths.h
/// Where an installed crex finds its own files. `cmake --install` lays them out under a prefix:
/// the tool in <prefix>/bin, its image plugin in <prefix>/lib/crex, the stdlib in
/// <prefix>/share/crex/stdlib, the Python package in <prefix>/lib/pythonX.Y/dist-packages/crex.
/// The prefix is found from where the running code is (the executable, or the Python module
/// that holds this code), so an installed tree works wherever it was installed or moved to.
#pragma once

#include <string>

namespace crex {

/// `relative` (to the prefix) of the install tree the running code is in, when that exists;
/// "" when the code does not run from an install tree (the build tree: callers fall back to
/// the build's own paths).
std::string installed_path(const std::string& relative);

}  // namespace crex
