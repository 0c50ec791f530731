#include "runtime/scene/camera_path_file.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <algorithm>
#include <map>

#include "base/json_positions.h"
#include "runtime/scene/json_fields.h"
#include "runtime/scene/radiance_view.h"

namespace crex {
namespace {

using nlohmann::json;

// Along every segment the camera must still see somewhere: an aim that turns parallel to up,
// or a look-at point the camera reaches, has no frame. Checked at this many points a segment.
constexpr int kAimChecks = 64;

// "{" (or "[") first, past white space and comments (// and /* */ of JSON with comments, # of RADIANCE).
bool looks_like_json(const std::string& t) {
    size_t i = 0;
    while (i < t.size()) {
        if (std::isspace(static_cast<unsigned char>(t[i]))) {
            ++i;
        } else if (t.compare(i, 2, "//") == 0 || t[i] == '#') {
            while (i < t.size() && t[i] != '\n') ++i;
        } else if (t.compare(i, 2, "/*") == 0) {
            size_t end = t.find("*/", i + 2);
            i = end == std::string::npos ? t.size() : end + 2;
        } else {
            return t[i] == '{' || t[i] == '[';  // an array is JSON too (and then told it must be an object)
        }
    }
    return false;
}

// The first segment along which the camera has no frame (no direction, or one parallel to
// up), or -1.
long degenerate_segment(const CameraPath& path) {
    for (size_t s = 0; s < std::max<size_t>(path.segments(), 1); ++s)  // a path of one key: that key
        for (int j = 0; j <= kAimChecks; ++j) {
            Vec3 d, up;
            double vfov = 0, hfov = 0;
            path.orientation({s, double(j) / kAimChecks}, d, up, vfov, hfov);
            if (d == Vec3{} || (path.fields().up && !(length(cross(d, up)) > 1e-6))) return static_cast<long>(s);
        }
    return -1;
}

class PathJsonReader {
public:
    PathJsonReader(const PositionedJson& doc, DiagnosticSink& sink) : doc_(doc), sink_(sink) {}

    std::optional<CameraPath> read() {
        const size_t errors_before = sink_.error_count();
        if (!doc_.value.is_object()) {
            sink_.report("E302", doc_.span(""), fmt::format("a camera path must be a JSON object {{\"keys\": [...]}}, got {}",
                                                            json_type_name(doc_.value)));
            return std::nullopt;
        }
        ObjectReader top(doc_, sink_, doc_.value, "");
        top.warn_unknown({"format", "version", "timing", "keys"});
        top.format_and_version("crex-camera-path");
        PathTiming timing = PathTiming::kConstantSpeed;
        std::string timing_name;
        if (top.string("timing", timing_name)) {
            if (timing_name == "keys") timing = PathTiming::kKeys;
            else if (timing_name != "constant_speed")
                sink_.report("E303", top.span("timing"),
                             fmt::format("timing: expected \"constant_speed\" or \"keys\", got \"{}\"", timing_name));
        }
        if (!top.has("keys")) {
            top.missing("keys", "an array of keys {\"time\", \"position\", \"look_at\" or \"direction\", \"up\", \"vfov\"}");
            return std::nullopt;
        }
        if (!top.at("keys").is_array() || top.at("keys").empty()) {
            sink_.report(top.at("keys").is_array() ? "E303" : "E302", top.span("keys"),
                         fmt::format("keys: expected an array of at least one key, got {}", json_shown(top.at("keys"))));
            return std::nullopt;
        }
        const json& keys = top.at("keys");
        std::vector<CameraKey> out(keys.size());
        std::vector<std::string> pointers(keys.size());
        std::optional<PathAim> aim;
        std::string aim_set_by;  // the key that set the aim's kind, for what is said
        PathFields fields;
        for (size_t i = 0; i < keys.size(); ++i) {
            pointers[i] = "/keys/" + std::to_string(i);
            if (!keys[i].is_object()) {
                sink_.report("E302", doc_.span(pointers[i]),
                             fmt::format("keys[{}]: expected an object, got {}", i, json_type_name(keys[i])));
                continue;
            }
            ObjectReader r(doc_, sink_, keys[i], pointers[i]);
            r.warn_unknown({"time", "position", "look_at", "direction", "up", "vfov"});
            CameraKey& k = out[i];
            r.vec3("position", k.position, kAny, true);
            // The aim: one kind for the whole path, so it interpolates as one quantity.
            const bool look = r.has("look_at"), dir = r.has("direction");
            if (look && dir) {
                sink_.report("E303", r.span("direction"), fmt::format("keys[{}]: give either 'look_at' or 'direction', not both", i));
            } else if (!look && !dir) {
                r.missing("look_at", "a point [x, y, z] the camera looks at, or 'direction'");
            } else {
                const PathAim kind = look ? PathAim::kLookAt : PathAim::kDirection;
                const std::string field = look ? "look_at" : "direction";
                if (aim && *aim != kind) {
                    sink_.report("E303", r.key_span(field),
                                 fmt::format("keys[{}]: this path aims by '{}' ({}); give '{}' here too", i,
                                             *aim == PathAim::kLookAt ? "look_at" : "direction", aim_set_by,
                                             *aim == PathAim::kLookAt ? "look_at" : "direction"));
                } else {
                    aim = kind;
                    aim_set_by = fmt::format("keys[{}]", i);
                    if (r.vec3(field, k.aim) && kind == PathAim::kDirection && !(length(k.aim) > 0))
                        sink_.report("E306", r.span(field), fmt::format("keys[{}].direction: has zero length", i));
                }
            }
            read_optional(r, i, "up", fields.up, [&] {
                Vec3 up;
                if (!r.vec3("up", up)) return false;
                if (!(length(up) > 0)) {
                    sink_.report("E306", r.span("up"), fmt::format("keys[{}].up: has zero length", i));
                    return false;
                }
                k.up = up;
                return true;
            }, [&] { k.up = out[i - 1].up; });
            read_optional(r, i, "vfov", fields.fov, [&] { return r.number("vfov", k.vfov, Range{0, 180, true, true}); },
                          [&] { k.vfov = out[i - 1].vfov; });
            read_time(r, i, keys.size(), timing, k.time);
        }
        if (sink_.error_count() != errors_before || !aim) return std::nullopt;
        if (timing == PathTiming::kConstantSpeed)
            for (size_t i = 1; i < out.size(); ++i)
                if (out[i].position == out[i - 1].position) {
                    Diagnostic& d = sink_.report("E306", doc_.span(pointers[i] + "/position"),
                                                 fmt::format("keys[{}].position: the same as keys[{}]'s; at constant speed the camera "
                                                             "would turn there in no time",
                                                             i, i - 1));
                    d.help = "give \"timing\": \"keys\" and a time to every key, to turn on the spot";
                    return std::nullopt;
                }
        CameraPath path(std::move(out), *aim, timing, std::move(fields));
        if (!std::isfinite(path.length())) {
            sink_.report("E303", doc_.span("/keys"),
                         "keys: the positions are too far apart to measure the path between them (its length overflows)");
            return std::nullopt;
        }
        if (long s = degenerate_segment(path); s >= 0) {
            sink_.report("E306", doc_.span(pointers[static_cast<size_t>(s) + (path.segments() > 0 ? 1 : 0)]),
                         path.segments() == 0
                             ? "keys[0]: the camera has no view: it is at its look-at point, or looks along its up"
                             : fmt::format("keys[{}] to keys[{}]: on the way the camera looks along its up, or reaches its look-at "
                                           "point",
                                           s, s + 1));
            return std::nullopt;
        }
        return path;
    }

private:
    // A field on none of the keys (the scene camera's), or on the first and any later ones
    // (a key without it keeps the one before's).
    template <class Read, class Keep>
    void read_optional(ObjectReader& r, size_t i, const char* field, bool& given, Read read, Keep keep) {
        if (i == 0) {
            given = r.has(field);
            if (given) read();
            return;
        }
        if (r.has(field) && !given) {
            Diagnostic& d = sink_.report("E304", doc_.span("/keys/0"),
                                         fmt::format("keys[0]: missing '{}', which keys[{}] gives", field, i));
            d.help = fmt::format("give '{}' on the first key too (later keys keep the one before's), or on none (the scene "
                                 "camera's then)",
                                 field);
            given = true;  // said once
            return;
        }
        if (!(r.has(field) && read())) keep();
    }

    // Times: every key's under keys timing, in increasing order; the first's and the last's at
    // constant speed (the keys between are passed where the arc length puts them).
    void read_time(ObjectReader& r, size_t i, size_t n, PathTiming timing, double& time) {
        const bool needed = timing == PathTiming::kKeys || i == 0 || i + 1 == n;
        if (!needed) {
            if (r.has("time")) {
                Diagnostic& d = sink_.report("W301", r.key_span("time"),
                                             fmt::format("keys[{}].time is ignored: at constant speed only the first and the last "
                                                         "key's times count",
                                                         i));
                d.help = "give \"timing\": \"keys\" to reach every key at its own time";
            }
            time = last_time_.value_or(0);
            return;
        }
        if (!r.number("time", time, kNonNegative, i > 0)) {
            if (i == 0 && !r.has("time")) last_time_ = time = 0;  // the first key's time defaults to 0
            return;
        }
        if (last_time_ && !(time > *last_time_))
            sink_.report("E303", r.span("time"),
                         fmt::format("keys[{}].time: {:g} s is not after the key before's {:g} s; times must increase", i, time,
                                     *last_time_));
        last_time_ = time;
    }

    const PositionedJson& doc_;
    DiagnosticSink& sink_;
    std::optional<double> last_time_;  // of the last key whose time counts
};

// One view per line: RADIANCE's options, each line from RADIANCE's defaults (as rpict -vf reads
// a view file), a leading program name skipped.
std::optional<CameraPath> read_view_lines(const SourceFile& file, double fps, DiagnosticSink& sink) {
    const size_t errors_before = sink.error_count();
    std::map<uint32_t, std::vector<ViewWord>> lines;
    for (ViewWord& w : view_file_words(file)) lines[file.position(w.begin).line].push_back(std::move(w));
    std::vector<CameraKey> keys;
    std::vector<SourceSpan> key_spans;  // each key's line
    std::optional<Camera> first;
    std::optional<uint32_t> first_line;
    for (auto& [line, words] : lines) {
        if (!words.empty() && words.front().text.rfind("-", 0) != 0) words.erase(words.begin());
        if (words.empty()) continue;
        Camera cam;
        const size_t before = sink.error_count();
        apply_radiance_view(file, words, cam, true, sink);
        if (sink.error_count() != before) continue;
        if (!first) {
            first = cam;
            first_line = line;
        } else if (cam.projection != first->projection) {
            sink.report("E303", {&file, words.front().begin, words.back().end},
                        fmt::format("this view's type differs from line {}'s: a path keeps one view type", *first_line));
            continue;
        }
        CameraKey k;
        k.time = double(keys.size()) / fps;
        k.position = cam.position;
        k.aim = cam.direction;
        k.up = cam.up;
        k.vfov = cam.vfov_deg;
        k.hfov = cam.hfov_deg;
        keys.push_back(k);
        key_spans.push_back({&file, words.front().begin, words.back().end});
    }
    if (sink.error_count() != errors_before) return std::nullopt;
    if (keys.empty()) {
        sink.report("E304", {&file, 0, 0}, "a view file for a path needs at least one line of view options (-vp x y z -vd x y z ...)");
        return std::nullopt;
    }
    PathFields fields;
    fields.up = fields.fov = true;
    fields.base = first;
    CameraPath path(std::move(keys), PathAim::kDirection, PathTiming::kKeys, std::move(fields));
    if (!std::isfinite(path.length())) {
        sink.report("E303", {&file, 0, static_cast<uint32_t>(file.line_text(1).size())},
                    "the views' positions are too far apart to measure the path between them (its length overflows)");
        return std::nullopt;
    }
    // Each line's own camera must have an image plane: a -vd too long to normalise (1e301)
    // came out as no direction at all.
    for (size_t i = 0; i < path.keys().size(); ++i) {
        const Camera c = path.camera_at(path.keys()[i].time, *first);
        const bool finite = std::isfinite(length(c.position)) && std::isfinite(length(c.direction)) && std::isfinite(length(c.up));
        if (!finite || !(length(c.direction) > 0) || !(length(cross(normalize_or_zero(c.direction), normalize_or_zero(c.up))) > 1e-6)) {
            sink.report("E306", key_spans[i], "this view has no image plane: its -vd is zero, too long to normalise, or along its -vu");
            return std::nullopt;
        }
    }
    return path;
}

}  // namespace

std::optional<CameraPath> read_camera_path(const SourceFile& file, double fps, DiagnosticSink& sink) {
    if (!looks_like_json(file.text())) return read_view_lines(file, fps, sink);
    PositionedJson doc;
    if (!parse_json_with_positions(file, doc, sink, "E301")) return std::nullopt;
    return PathJsonReader(doc, sink).read();
}

}  // namespace crex
