/// \file ast.h
/// The pipeline syntax tree, as written, with spans (built by parse_pipeline_file()).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "base/source.h"

namespace crex::pipeline::ast {

struct Value {
    enum class Kind { kNumber, kString, kBool, kCross } kind = Kind::kNumber;  ///< kCross: the `x` of `512 x 512`
    double number = 0;
    std::string unit;  ///< "", "s", "ms", "%", "deg"
    std::string text;  ///< kString: without the quotes
    bool boolean = false;
    SourceSpan span;
    SourceSpan text_span;  ///< kString: the characters between the quotes
};

struct Arg;

struct Expr {
    enum class Kind { kCall, kReference, kLiteral } kind = Kind::kReference;
    std::string name;  ///< operator (call) or name (reference)
    std::vector<Arg> args;
    Value literal;
    SourceSpan span;
    SourceSpan name_span;
};

struct Arg {
    std::string name;  ///< "" for a positional argument
    SourceSpan name_span;
    Expr expr;         ///< positional
    Value value;       ///< named (`fovea 2 deg`, `op "+"`, `task 0.5`)
    SourceSpan span;
};

struct Statement {
    enum class Kind { kSection, kDefinition, kVary, kSetting } kind = Kind::kSetting;
    std::string key;  ///< section, defined name, variable or setting
    SourceSpan key_span;
    std::vector<Statement> body;  ///< kSection
    Expr expr;                    ///< kDefinition: the value; kVary and kSetting: the `by` map
    bool has_by = false;
    std::vector<Value> values;    ///< kSetting
    Value lo, hi;                 ///< kVary
    std::string using_fn;         ///< kVary: modulation function (`using ...`)
    SourceSpan using_span;
    std::string component;        ///< kVary: the component of `vary subsample(D) ...`, else ""
    SourceSpan component_span;
    bool has_refine = false;      ///< kVary: `refine T` (capict's corner-difference threshold)
    Value refine;
    SourceSpan span;
};

struct Pipeline {
    std::string name;
    SourceSpan name_span;
    std::string base;  ///< "" unless `extends`
    SourceSpan base_span;
    std::vector<Statement> body;
    SourceSpan span;
};

struct File {
    std::vector<Pipeline> pipelines;
};

}  // namespace crex::pipeline::ast
