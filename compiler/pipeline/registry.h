/// \file registry.h
/// The three name families of the pipeline language, one table each: guidance operators (with
/// their signatures), selective variables (with their ranges) and modulation functions. The
/// checker, the planner and the plan reader look names up here; the runtime binds one
/// implementation per enum value in a table that does not compile with a row missing
/// (runtime/pipeline/guidance_graph.cpp, svt.cpp). Adding a guidance operator: one row in
/// kGuidanceOperators, one enum value, its implementation in stdlib/guidance bound in the
/// runtime's table, its test. Header-only and constexpr, so the runtime needs no compiler library.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace crex::pipeline {

// ---- Guidance operators -------------------------------------------------------------------

enum class GuidanceOperator : uint8_t {
    kSaliency, kEdges, kRadianceDifference, kComponent, kTagged, kTaskMap, kDistractors, kXmap,
    kImportance, kConstant, kNormalise, kBlur, kThreshold, kNoise,
};
inline constexpr size_t kGuidanceOperatorCount = 14;

/// What an expression is (a bit each, so a parameter may accept several).
enum class ValueType : uint8_t { kImage = 1, kBuffer = 2, kMap = 4, kObjects = 8, kComponent = 16 };
constexpr uint8_t operator|(ValueType a, ValueType b) { return static_cast<uint8_t>(static_cast<uint8_t>(a) | static_cast<uint8_t>(b)); }
constexpr bool accepts(uint8_t set, ValueType t) { return (set & static_cast<uint8_t>(t)) != 0; }

/// A literal parameter's kind: kAngle is `N deg` in (0, 180), resolved to radians by the compiler.
enum class LiteralKind : uint8_t { kNone, kNumber, kAngle, kString };

struct ParamSignature {
    std::string_view name;    ///< "" for a positional parameter
    uint8_t accepts = 0;      ///< ValueType bits for an expression parameter
    LiteralKind literal = LiteralKind::kNone;
    bool required = true;
};

struct OperatorSignature {
    GuidanceOperator op;
    std::string_view name;
    ValueType result;
    std::array<ParamSignature, 2> params{};  ///< the first `param_count`
    size_t param_count = 0;
    bool weighted_maps = false;  ///< importance(task 0.5, sal 0.5, op "+"): other named args are maps
    bool needs_scene = false;    ///< reads the scene through the pixel probe
    std::span<const ParamSignature> parameters() const { return {params.data(), param_count}; }
};

namespace registry_detail {
using V = ValueType;
using L = LiteralKind;
constexpr uint8_t kPicture = V::kImage | V::kBuffer;
constexpr uint8_t kMapOnly = static_cast<uint8_t>(V::kMap);
constexpr uint8_t kObjectsOnly = static_cast<uint8_t>(V::kObjects);
}  // namespace registry_detail

inline constexpr std::array<OperatorSignature, kGuidanceOperatorCount> kGuidanceOperators = [] {
    using namespace registry_detail;
    using G = GuidanceOperator;
    return std::array<OperatorSignature, kGuidanceOperatorCount>{{
        {G::kSaliency, "saliency", V::kMap, {{{"", kPicture}}}, 1},
        {G::kEdges, "edges", V::kMap, {{{"", kPicture}}}, 1},
        {G::kRadianceDifference, "radiance_difference", V::kMap, {{{"", kPicture}}}, 1},  // thesis ch. 7
        {G::kComponent, "component", V::kBuffer, {{{"", static_cast<uint8_t>(V::kComponent)}}}, 1},
        {G::kTagged, "tagged", V::kObjects, {{{"", 0, L::kString, false}}}, 1},  // no name: every tagged object
        {G::kTaskMap, "task_map", V::kMap, {{{"", kObjectsOnly}, {"fovea", 0, L::kAngle, false}}}, 2, false, true},
        {G::kDistractors, "distractors", V::kMap, {{{"", kObjectsOnly, L::kNone, false}, {"fovea", 0, L::kAngle, false}}}, 2, false, true},
        {G::kXmap, "xmap", V::kMap, {}, 0, false, true},
        {G::kImportance, "importance", V::kMap, {{{"op", 0, L::kString, false}}}, 1, true},
        {G::kConstant, "constant", V::kMap, {{{"", 0, L::kNumber}}}, 1},
        {G::kNormalise, "normalise", V::kMap, {{{"", kMapOnly}}}, 1},
        {G::kBlur, "blur", V::kMap, {{{"", kMapOnly}, {"sigma", 0, L::kNumber, false}}}, 2},
        {G::kThreshold, "threshold", V::kMap, {{{"", kMapOnly}, {"at", 0, L::kNumber, false}}}, 2},
        {G::kNoise, "noise", V::kMap, {{{"", static_cast<uint8_t>(V::kImage)}}}, 1},  // the cyclic process's error estimate
    }};
}();

// ---- Selective variables ------------------------------------------------------------------

enum class SelectiveVariable : uint8_t { kSpp, kShadowRays, kIcRadius, kSubsample, kMediaSamples, kSpecularThreshold, kIcRays };
inline constexpr size_t kSelectiveVariableCount = 7;

struct VariableSignature {
    SelectiveVariable variable;
    std::string_view name;
    double lo, hi;     ///< allowed values of `vary V A .. B`
    bool integer;      ///< per-pixel values are rounded
    /// May name one component (`vary subsample(D) ...`, capict, thesis ch. 7): the variable
    /// then applies to that component's rays only.
    bool per_component = false;
};

inline constexpr std::array<VariableSignature, kSelectiveVariableCount> kSelectiveVariables = {{
    {SelectiveVariable::kSpp, "spp", 1, 1 << 20, true},
    {SelectiveVariable::kShadowRays, "shadow_rays", 1, 1024, true},
    {SelectiveVariable::kIcRadius, "ic_radius", 1e-9, 1e9, false},
    {SelectiveVariable::kSubsample, "subsample", 1, 1024, true, true},
    {SelectiveVariable::kMediaSamples, "media_samples", 1, 1024, true},
    {SelectiveVariable::kSpecularThreshold, "specular_threshold", 0, 1, false},
    // Hemisphere rays of the irradiance records a pixel's queries make and accept (RADIANCE's
    // -ad, per pixel): quieter records where the map is high.
    {SelectiveVariable::kIcRays, "ic_rays", 16, 65535, true},
}};

// ---- Modulation functions (`vary ... using F`) --------------------------------------------

enum class ModulationFunction : uint8_t { kLinear, kQuadratic, kSqrt, kStep };
inline constexpr size_t kModulationFunctionCount = 4;
inline constexpr std::array<std::string_view, kModulationFunctionCount> kModulationFunctionNames = {"linear", "quadratic", "sqrt", "step"};

// ---- Lookups ------------------------------------------------------------------------------

namespace registry_detail {
// Row i of each table describes enum value i: the enums index the tables.
constexpr bool operators_in_order() {
    for (size_t i = 0; i < kGuidanceOperators.size(); ++i)
        if (static_cast<size_t>(kGuidanceOperators[i].op) != i) return false;
    return true;
}
constexpr bool variables_in_order() {
    for (size_t i = 0; i < kSelectiveVariables.size(); ++i)
        if (static_cast<size_t>(kSelectiveVariables[i].variable) != i) return false;
    return true;
}
static_assert(operators_in_order(), "kGuidanceOperators: row i must describe GuidanceOperator i");
static_assert(variables_in_order(), "kSelectiveVariables: row i must describe SelectiveVariable i");
static_assert(static_cast<size_t>(GuidanceOperator::kNoise) + 1 == kGuidanceOperatorCount);
static_assert(static_cast<size_t>(SelectiveVariable::kIcRays) + 1 == kSelectiveVariableCount);
static_assert(static_cast<size_t>(ModulationFunction::kStep) + 1 == kModulationFunctionCount);
}  // namespace registry_detail

constexpr const OperatorSignature& signature(GuidanceOperator op) { return kGuidanceOperators[static_cast<size_t>(op)]; }
constexpr const VariableSignature& signature(SelectiveVariable v) { return kSelectiveVariables[static_cast<size_t>(v)]; }
constexpr std::string_view name_of(GuidanceOperator op) { return signature(op).name; }
constexpr std::string_view name_of(SelectiveVariable v) { return signature(v).name; }
constexpr std::string_view name_of(ModulationFunction f) { return kModulationFunctionNames[static_cast<size_t>(f)]; }

constexpr std::optional<GuidanceOperator> guidance_operator_from_name(std::string_view name) {
    for (const auto& o : kGuidanceOperators)
        if (o.name == name) return o.op;
    return std::nullopt;
}
constexpr std::optional<SelectiveVariable> selective_variable_from_name(std::string_view name) {
    for (const auto& v : kSelectiveVariables)
        if (v.name == name) return v.variable;
    return std::nullopt;
}
constexpr std::optional<ModulationFunction> modulation_function_from_name(std::string_view name) {
    for (size_t i = 0; i < kModulationFunctionNames.size(); ++i)
        if (kModulationFunctionNames[i] == name) return static_cast<ModulationFunction>(i);
    return std::nullopt;
}

}  // namespace crex::pipeline
