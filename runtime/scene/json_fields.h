/// \file json_fields.h
/// Typed, located reading of JSON objects (the native scene format, camera path files): each
/// field checked for its type and range and reported at its own position (E302 wrong type,
/// E303 out of range, E304 missing), unknown fields warned about with the nearest known name
/// (W301). The document is read with positions first (base/json_positions.h).
#pragma once

#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "base/diagnostic.h"
#include "base/json_positions.h"
#include "runtime/base/vec3.h"

namespace crex {

/// "a number", "an object", ... for "expected X, got Y".
std::string json_type_name(const nlohmann::json& v);
/// A value as written, shortened to about 40 characters.
std::string json_shown(const nlohmann::json& v);

/// An interval of accepted numbers, and how a message says it.
struct Range {
    double lo = -INFINITY, hi = INFINITY;
    bool lo_open = false, hi_open = false;
    bool contains(double x) const { return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi); }
    std::string text() const;  ///< " >= 0", " in (0, 180)", or "" for any number
};

inline const Range kAny{};
inline const Range kUnit{0, 1};
inline const Range kNonNegative{0, INFINITY};
inline const Range kPositive{0, INFINITY, true};

/// Typed access to one JSON object of a positioned document, reporting at the field's own
/// position. Each accessor returns false (and leaves `out` alone) when the field is absent
/// or was reported.
class ObjectReader {
public:
    ObjectReader(const PositionedJson& doc, DiagnosticSink& sink, const nlohmann::json& obj, std::string pointer)
        : doc_(doc), sink_(sink), obj_(obj), pointer_(std::move(pointer)) {}

    std::string path(const std::string& key) const { return readable_json_path(pointer_ + "/" + key); }
    SourceSpan span(const std::string& key) const { return doc_.span(pointer_ + "/" + key); }
    SourceSpan key_span(const std::string& key) const { return doc_.key_span(pointer_ + "/" + escape_pointer_token(key)); }
    bool has(const std::string& key) const { return obj_.contains(key); }
    const nlohmann::json& at(const std::string& key) const { return obj_.at(key); }
    const std::string& pointer() const { return pointer_; }

    void missing(const std::string& key, const std::string& what);
    void wrong(const std::string& key, const std::string& expected);

    bool number(const std::string& key, double& out, const Range& r = kAny, bool required = false);
    bool integer(const std::string& key, int& out, int lo, int hi);
    bool boolean(const std::string& key, bool& out);
    bool string(const std::string& key, std::string& out, bool required = false);
    bool vec3(const std::string& key, Vec3& out, const Range& r = kAny, bool required = false);
    bool vec3_list(const std::string& key, std::vector<Vec3>& out, bool required);
    /// The optional "format" (must be `format`) and "version" (must be 1) of a file's top object.
    void format_and_version(std::string_view format);
    /// W301 for every key not in `known`, with the nearest known name as help.
    void warn_unknown(std::initializer_list<std::string_view> known);

    static bool vec3_of(const nlohmann::json& v, Vec3& out);

private:
    const PositionedJson& doc_;
    DiagnosticSink& sink_;
    const nlohmann::json& obj_;
    std::string pointer_;
};

}  // namespace crex
