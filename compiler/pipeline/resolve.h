/// \file resolve.h
/// resolve_pipeline(): a checked pipeline, its `extends` chain applied, as plain data for the
/// planner. A child overrides its base field by field: settings by name, maps by name,
/// selective variables by variable, the crex of a stage as a whole. Bases are pipelines earlier
/// in the same file or stdlib pipelines (stdlib/pipelines/NAME.pipe).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "compiler/pipeline/ast.h"

namespace crex::pipeline {

struct ResolvedStage {
    std::optional<ast::Value> crex;      ///< the crex literal (compiled by the planner)
    std::optional<ast::Expr> crex_by;    ///< selective: the map modulating `{ }`
    std::map<std::string, ast::Value> settings;
};

struct ResolvedVariable {
    std::string name;
    ast::Value lo, hi;
    ast::Expr by;
    std::string using_fn;
    std::string component;  ///< "D" of `vary subsample(D) ...`, else ""
    std::optional<double> refine;  ///< `refine T`
    /// "subsample(D)" or "subsample": what the pipeline varies, and what an extension replaces.
    std::string varied() const { return component.empty() ? name : name + "(" + component + ")"; }
};

struct ResolvedPipeline {
    std::string name;
    std::vector<std::string> chain;                       ///< name, then its bases
    std::map<std::string, std::vector<ast::Value>> top;   ///< top-level settings
    ResolvedStage preselective, selective;
    std::vector<std::pair<std::string, ast::Expr>> maps;  ///< guidance, in definition order
    std::vector<ResolvedVariable> vary;
    std::map<std::string, std::vector<ast::Value>> output;  ///< `image` may name several files
};

/// Where `extends NAME` looks for stdlib pipelines: $CREX_STDLIB, else the install tree's
/// (base/install_paths.h), else the source tree's stdlib/.
std::string stdlib_dir();

/// The stdlib file that defines pipeline `name` (stdlib/pipelines/NAME.pipe), parsed once per
/// process; nullptr if there is none or it does not parse (its errors go to `sink`).
const ast::File* stdlib_file(const std::string& name, DiagnosticSink& sink);

/// The pipeline `child` extends: one above it in `file`, else a stdlib pipeline; nullptr if none.
const ast::Pipeline* find_base(const ast::File& file, const ast::Pipeline& child, DiagnosticSink& sink);

/// Resolves from a given pipeline (which may come from a stdlib file).
std::optional<ResolvedPipeline> resolve_from(const ast::File& file, const ast::Pipeline& start, DiagnosticSink& sink);

/// Resolves pipeline `name` of `file` (the last pipeline if `name` is empty). Stdlib files stay
/// loaded for the whole process, so diagnostics may point into them.
std::optional<ResolvedPipeline> resolve_pipeline(const ast::File& file, const std::string& name, DiagnosticSink& sink);

}  // namespace crex::pipeline
