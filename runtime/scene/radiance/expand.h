/// \file expand.h
/// A RADIANCE scene file with its `!` commands carried out, as RADIANCE's own xform would
/// expand it, but natively: no shell is ever run. xform is built in (its transforms, -a
/// arrays, -n names, -m modifiers, -I, -c, nested files read relative to the file that names
/// them); so are the generators (genbox, genprism, genrev, gensky) and pipelines of
/// a generator into xforms. Any other command is a located E307 that names it.
///
/// What comes out is a stream of primitives in world coordinates with their final names and
/// modifiers, each still pointing at the text that made it.
#pragma once

#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/radiance/scene_text.h"

namespace crex::radiance {

/// Receives the expanded scene in order.
class PrimitiveConsumer {
public:
    virtual ~PrimitiveConsumer() = default;
    virtual void primitive(Primitive p) = 0;
    virtual void directive(const Directive& d) = 0;
    /// A `!` command starts (and ends) here: everything it makes lies between. Commands nest
    /// (an xform reading a file with its own commands).
    virtual void command_begins(const SourceSpan& command) = 0;
    virtual void command_ends() = 0;
};

struct ExpandOptions {
    /// Where files named without a directory are looked for after the including file's own
    /// directory (RADIANCE's RAYPATH).
    std::vector<std::string> library_dirs;
};

/// Expands `file` (its directory is where its relative paths start) into `out`.
void expand_scene(const SourceFile& file, SceneSources& sources, const ExpandOptions& options, PrimitiveConsumer& out,
                  DiagnosticSink& sink);

struct RifProject;
/// Expands the files and commands of a project file (`rif`, read by read_rif) into `out`.
void expand_project(const RifProject& project, const SourceFile& rif, SceneSources& sources, const ExpandOptions& options,
                    PrimitiveConsumer& out, DiagnosticSink& sink);

}  // namespace crex::radiance
