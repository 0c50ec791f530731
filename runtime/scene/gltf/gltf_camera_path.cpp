#include "runtime/scene/gltf/gltf_camera_path.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "runtime/scene/gltf/gltf_document.h"
#include "runtime/scene/gltf/gltf_transform.h"
#include "runtime/base/file_extension.h"
#include "runtime/base/sampling.h"

namespace crex {
namespace {

using gltf::Document;
using gltf::Mat4;

constexpr int kStepsBetweenKeys = 8;     // samples per span of the animation's own keys
constexpr size_t kMostKeyTimes = 100000;  // an hour at 24 fps has 86,400

// One animated property of one node: its key times and values (CUBICSPLINE: in-tangent,
// value, out-tangent per key), `width` numbers a value.
struct Channel {
    int node = -1;
    std::string property;  // translation, rotation, scale
    std::string interpolation;
    std::vector<double> times, values;
    size_t width = 3;
};

std::vector<double> value_at(const Channel& c, size_t key, size_t part) {
    // CUBICSPLINE keeps three values per key: part 0 in-tangent, 1 value, 2 out-tangent.
    const size_t per_key = c.interpolation == "CUBICSPLINE" ? 3 : 1;
    const size_t at = (key * per_key + (per_key == 3 ? part : 0)) * c.width;
    return {c.values.begin() + static_cast<std::ptrdiff_t>(at), c.values.begin() + static_cast<std::ptrdiff_t>(at + c.width)};
}

std::vector<double> normalised(std::vector<double> q) {
    double n = 0;
    for (double v : q) n += v * v;
    n = std::sqrt(n);
    if (n > 0 && std::isfinite(n))
        for (double& v : q) v /= n;
    return q;
}

// Spherical interpolation of unit quaternions along the shorter arc.
std::vector<double> slerp(std::vector<double> a, std::vector<double> b, double u) {
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0) {
        for (double& v : b) v = -v;
        d = -d;
    }
    std::vector<double> out(4);
    if (d > 0.9995) {  // nearly equal: linear, renormalised (the sine below would lose precision)
        for (size_t i = 0; i < 4; ++i) out[i] = a[i] + u * (b[i] - a[i]);
        return normalised(out);
    }
    const double theta = std::acos(std::min(1.0, d)), s = std::sin(theta);
    const double wa = std::sin((1 - u) * theta) / s, wb = std::sin(u * theta) / s;
    for (size_t i = 0; i < 4; ++i) out[i] = wa * a[i] + wb * b[i];
    return normalised(out);
}

// glTF's sampler at time t (clamped to its keys).
std::vector<double> sample(const Channel& c, double t) {
    const size_t n = c.times.size();
    if (t <= c.times.front()) return value_at(c, 0, 1);
    if (t >= c.times.back()) return value_at(c, n - 1, 1);
    const size_t i = static_cast<size_t>(std::upper_bound(c.times.begin(), c.times.end(), t) - c.times.begin()) - 1;
    const double span = c.times[i + 1] - c.times[i];
    const double u = span > 0 ? (t - c.times[i]) / span : 0;
    const bool rotation = c.property == "rotation";
    if (c.interpolation == "STEP") return value_at(c, i, 1);
    if (c.interpolation == "CUBICSPLINE") {
        const std::vector<double> p0 = value_at(c, i, 1), m0 = value_at(c, i, 2), p1 = value_at(c, i + 1, 1), m1 = value_at(c, i + 1, 0);
        const double u2 = u * u, u3 = u2 * u;
        std::vector<double> out(c.width);
        for (size_t k = 0; k < c.width; ++k)
            out[k] = (2 * u3 - 3 * u2 + 1) * p0[k] + span * (u3 - 2 * u2 + u) * m0[k] + (-2 * u3 + 3 * u2) * p1[k] + span * (u3 - u2) * m1[k];
        return rotation ? normalised(out) : out;
    }
    const std::vector<double> a = value_at(c, i, 1), b = value_at(c, i + 1, 1);
    if (rotation) return slerp(normalised(a), normalised(b), u);
    std::vector<double> out(c.width);
    for (size_t k = 0; k < c.width; ++k) out[k] = a[k] + u * (b[k] - a[k]);
    return out;
}

// The default scene's camera nodes in the importer's order (depth first from the roots), each
// with the nodes from its root down to it.
void find_cameras(const tinygltf::Model& m, int node, std::vector<int>& chain, std::vector<std::vector<int>>& cameras,
                  std::vector<bool>& seen) {
    if (node < 0 || static_cast<size_t>(node) >= m.nodes.size() || seen[size_t(node)] || chain.size() > 1000) return;
    seen[size_t(node)] = true;
    chain.push_back(node);
    const tinygltf::Node& n = m.nodes[size_t(node)];
    if (n.camera >= 0 && static_cast<size_t>(n.camera) < m.cameras.size() &&
        (m.cameras[size_t(n.camera)].type == "perspective" || m.cameras[size_t(n.camera)].type == "orthographic"))
        cameras.push_back(chain);
    for (int c : n.children) find_cameras(m, c, chain, cameras, seen);
    chain.pop_back();
}

std::string camera_name(const tinygltf::Model& m, int node, size_t index) {
    const tinygltf::Node& n = m.nodes[size_t(node)];
    return gltf::camera_name(m.cameras[size_t(n.camera)], n, index);
}

}  // namespace

bool is_gltf_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".gltf" || ext == ".glb";
}

std::optional<std::string> gltf_camera_path_json(const std::string& path, const std::string& camera, SceneSources& sources,
                                                 DiagnosticSink& sink) {
    std::optional<Document> doc = gltf::read_document(path, sources, sink);
    if (!doc) return std::nullopt;
    const tinygltf::Model& m = doc->model;
    std::vector<std::vector<int>> cameras;
    std::vector<bool> seen(m.nodes.size(), false);
    for (int root : gltf::scene_roots(m)) {
        std::vector<int> chain;
        find_cameras(m, root, chain, cameras, seen);
    }
    if (cameras.empty()) {
        sink.report("E304", doc->at(""), fmt::format("'{}' has no perspective or orthographic camera in its scene to move", path));
        return std::nullopt;
    }
    // The camera --camera names (by name or index), else the first: the scene's camera.
    size_t chosen = 0;
    if (!camera.empty()) {
        bool found = false;
        std::string names;
        for (size_t i = 0; i < cameras.size() && !found; ++i) {
            const std::string name = camera_name(m, cameras[i].back(), i);
            if (name == camera || std::to_string(i) == camera) chosen = i, found = true;
            names += fmt::format("{}{} '{}'", i ? ", " : "", i, name);
        }
        if (!found) {
            sink.report("E303", doc->at("/cameras"), fmt::format("--camera {}: no such camera in '{}'; its cameras are {}", camera, path, names));
            return std::nullopt;
        }
    }
    const std::vector<int>& chain = cameras[chosen];
    const int camera_node = chain.back();
    const std::string name = camera_name(m, camera_node, chosen);
    // The first animation that moves the camera or a node above it.
    const std::set<int> on_chain(chain.begin(), chain.end());
    int animation = -1;
    for (size_t a = 0; a < m.animations.size() && animation < 0; ++a)
        for (const auto& ch : m.animations[a].channels)
            if (on_chain.count(ch.target_node) && ch.target_path != "weights") animation = static_cast<int>(a);
    if (animation < 0) {
        sink.report("E304", doc->at(fmt::format("/nodes/{}", camera_node)),
                    fmt::format("camera '{}' of '{}' is not animated: no animation moves its node or a node above it", name, path));
        return std::nullopt;
    }
    const tinygltf::Animation& anim = m.animations[size_t(animation)];
    std::vector<Channel> channels;
    std::set<double> times;
    const size_t errors = sink.error_count();
    for (size_t k = 0; k < anim.channels.size(); ++k) {
        const tinygltf::AnimationChannel& ch = anim.channels[k];
        if (!on_chain.count(ch.target_node) || ch.target_path == "weights") continue;
        const std::string at = fmt::format("/animations/{}/channels/{}", animation, k);
        if (m.nodes[size_t(ch.target_node)].matrix.size() == 16) {
            sink.report("E303", doc->at(at), fmt::format("node {} is animated but has a matrix: glTF animates nodes given by translation, "
                                                         "rotation and scale only", ch.target_node));
            continue;
        }
        if (ch.sampler < 0 || static_cast<size_t>(ch.sampler) >= anim.samplers.size()) {
            sink.report("E303", doc->at(at + "/sampler"), fmt::format("sampler {} does not exist", ch.sampler));
            continue;
        }
        const tinygltf::AnimationSampler& s = anim.samplers[size_t(ch.sampler)];
        const std::string sat = fmt::format("/animations/{}/samplers/{}", animation, ch.sampler);
        Channel c;
        c.node = ch.target_node;
        c.property = ch.target_path;
        c.interpolation = s.interpolation.empty() ? "LINEAR" : s.interpolation;
        c.width = c.property == "rotation" ? 4 : 3;
        if (c.interpolation != "LINEAR" && c.interpolation != "STEP" && c.interpolation != "CUBICSPLINE") {
            sink.report("E303", doc->at(sat + "/interpolation"), fmt::format("interpolation '{}': expected LINEAR, STEP or CUBICSPLINE", c.interpolation));
            continue;
        }
        c.times = gltf::read_accessor(*doc, s.input, 1, sat + "/input", sink);
        c.values = gltf::read_accessor(*doc, s.output, static_cast<int>(c.width), sat + "/output", sink);
        const size_t per_key = c.interpolation == "CUBICSPLINE" ? 3 : 1;
        if (c.times.empty()) continue;  // said by read_accessor
        bool increasing = true;
        for (size_t i = 0; i < c.times.size(); ++i)
            increasing = increasing && std::isfinite(c.times[i]) && c.times[i] >= 0 && (i == 0 || c.times[i] > c.times[i - 1]);
        if (!increasing) {
            sink.report("E303", doc->at(sat + "/input"), "key times must be finite, at least 0 and increasing");
            continue;
        }
        if (c.values.size() != c.times.size() * per_key * c.width) {
            sink.report("E303", doc->at(sat + "/output"),
                        fmt::format("{} values for {} keys of {} ({} interpolation)", c.values.size() / c.width, c.times.size(), c.property,
                                    c.interpolation));
            continue;
        }
        times.insert(c.times.begin(), c.times.end());
        channels.push_back(std::move(c));
    }
    if (sink.error_count() != errors) return std::nullopt;
    if (channels.empty() || times.empty()) {
        sink.report("E304", doc->at(fmt::format("/animations/{}", animation)), fmt::format("animation {} moves camera '{}' by no key", animation, name));
        return std::nullopt;
    }
    // The camera's world transform at time t: each node's TRS with its animated properties.
    auto world_at = [&](double t) {
        Mat4 world;
        for (int node : chain) {
            const tinygltf::Node& n = m.nodes[size_t(node)];
            std::vector<double> translation = n.translation, rotation = n.rotation, scale = n.scale;
            for (const Channel& c : channels) {
                if (c.node != node) continue;
                (c.property == "translation" ? translation : c.property == "rotation" ? rotation : scale) = sample(c, t);
            }
            world = world * (n.matrix.size() == 16 ? gltf::local_transform(n) : gltf::trs_transform(translation, rotation, scale));
        }
        return world;
    };
    if (times.size() > kMostKeyTimes) {  // samples and keys grow with them: bounded memory on any file
        sink.report("E303", doc->at(fmt::format("/animations/{}", animation)),
                    fmt::format("{} key times move camera '{}': at most {} are read", times.size(), name, kMostKeyTimes));
        return std::nullopt;
    }
    std::vector<double> at(times.begin(), times.end()), samples;
    for (size_t i = 0; i + 1 < at.size(); ++i)
        for (int k = 0; k < kStepsBetweenKeys; ++k) samples.push_back(at[i] + (at[i + 1] - at[i]) * k / kStepsBetweenKeys);
    samples.push_back(at.back());
    const tinygltf::Camera& cam = m.cameras[size_t(m.nodes[size_t(camera_node)].camera)];
    const bool perspective = cam.type == "perspective";
    const double vfov = cam.perspective.yfov * 180 / kPi;
    nlohmann::json keys = nlohmann::json::array();
    for (double t : samples) {
        const Mat4 w = world_at(t);
        const Vec3 p = w.point({0, 0, 0}), d = normalize_or_zero(w.vector({0, 0, -1})), up = normalize_or_zero(w.vector({0, 1, 0}));
        nlohmann::json key = {{"time", t}, {"position", {p.x, p.y, p.z}}, {"direction", {d.x, d.y, d.z}}, {"up", {up.x, up.y, up.z}}};
        if (perspective && vfov > 0 && vfov < 180) key["vfov"] = vfov;
        keys.push_back(std::move(key));
    }
    const nlohmann::json out = {{"format", "crex-camera-path"}, {"version", 1}, {"timing", "keys"}, {"keys", std::move(keys)}};
    return out.dump(1);
}

}  // namespace crex
