/// \file pattern_json.h
/// An emitter's patterns (scene.h's FunctionPattern) in the native JSON format, the
/// `patterns` array of a light, glow or illum material:
///   {"kind": "brightfunc"|"colorfunc"|"brightdata"|"colordata"|"colorpict", "name": ...,
///    "definitions": "...", "functions": [...], "coordinates": [...],
///    "tables": [{"axes": [{"origin", "size", "count", "points"?}], "values": [...]}],
///    "picture": "file", "args": [...], "to_pattern": [12 numbers], "scale": s}
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "runtime/scene/scene.h"

namespace crex {

nlohmann::json pattern_to_json(const FunctionPattern& p);
/// Reads one; false with `error` (what is wrong, naming the field) when malformed.
bool pattern_from_json(const nlohmann::json& j, FunctionPattern& out, std::string& error);

/// A trans material's `surface_functions` (RADIANCE's BRTDfunc): {"reflection": pattern,
/// "transmission": pattern, "front_diffuse", "back_diffuse", "diffuse_transmit": [r, g, b]}.
nlohmann::json surface_functions_to_json(const SurfaceFunctions& s);
bool surface_functions_from_json(const nlohmann::json& j, SurfaceFunctions& out, std::string& error);

/// A plastic or trans material's `directional_function` (RADIANCE's plasfunc, metfunc,
/// transfunc): {"shape": pattern, "diffuse_reflect", "diffuse_transmit", "reflect",
/// "transmit": [r, g, b]}.
/// A trans material's `redirections` (RADIANCE's prism1, prism2): [{"coefficient": pattern,
/// "direction": pattern}, ...].
nlohmann::json redirections_to_json(const std::vector<Redirection>& r);
bool redirections_from_json(const nlohmann::json& j, std::vector<Redirection>& out, std::string& error);

nlohmann::json directional_function_to_json(const DirectionalFunction& d);
bool directional_function_from_json(const nlohmann::json& j, DirectionalFunction& out, std::string& error);

}  // namespace crex
