/// \file stdlib_pipelines.h
/// The stdlib's pipelines by name: `crex run sel_quiet` wherever crex is installed, without
/// the path of its share/ folder.
#pragma once

#include <string>
#include <vector>

namespace crex::pipeline {

/// The names of the stdlib's pipelines (NAME of stdlib_dir()/pipelines/NAME.pipe), sorted.
std::vector<std::string> stdlib_pipeline_names();

/// The stdlib's pipelines as a paragraph of `crex run --help`: that they run by name, where
/// they are, their names wrapped at 94 columns. "" when there are none.
std::string stdlib_pipelines_said();

/// What a command's pipeline argument names.
struct PipelineArgument {
    std::string path;  ///< the file to read: the argument itself, or its stdlib file
    bool stdlib = false;  ///< the argument was a stdlib pipeline's name
    /// For a bare name that is neither a file here nor a stdlib pipeline: what the stdlib has
    /// ("did you mean 'sel_quiet'?" and the names), to say after the read error; else "".
    std::string hint;
};

/// A pipeline argument as given (a path, '-') names that file. A bare name (a pipeline
/// name: letters, digits, '_') that is no file here names the stdlib's NAME.pipe when there is
/// one: a file of the name in the working folder comes first.
PipelineArgument pipeline_argument(const std::string& arg);

}  // namespace crex::pipeline
