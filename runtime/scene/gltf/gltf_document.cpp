#include "runtime/scene/gltf/gltf_document.h"

#include <fmt/format.h>

#include <cstring>
#include <filesystem>
#include <limits>

#include "base/base64.h"
#include "base/input_file.h"

namespace crex::gltf {
namespace {

// tinygltf's file access, bounded and without any path expansion.
bool fs_exists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}
std::string fs_expand(const std::string& path, void*) { return path; }
bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    std::string error;
    auto bytes = read_input_file(path, error, kMaxDataInputBytes);
    if (!bytes) {
        if (err) *err += error + "\n";
        return false;
    }
    out->assign(bytes->begin(), bytes->end());
    return true;
}
bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "crex does not write glTF files\n";
    return false;
}

// Images are not decoded here (OpenImageIO reads them when rendering): keep a data URI's
// bytes; external files and buffer views are found again from the model.
bool keep_image(tinygltf::Image* image, const int index, std::string*, std::string*, int, int, const unsigned char* bytes, int size,
                void* user) {
    auto* doc = static_cast<Document*>(user);
    if (index < 0) return true;
    if (doc->image_bytes.size() <= static_cast<size_t>(index)) doc->image_bytes.resize(static_cast<size_t>(index) + 1);
    if (image->uri.empty() && image->bufferView < 0 && bytes && size > 0)
        doc->image_bytes[static_cast<size_t>(index)].assign(reinterpret_cast<const char*>(bytes), static_cast<size_t>(size));
    return true;
}

std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s;
}

// glTF URIs are percent-encoded ("my%20wood.png").
std::string uri_decode(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// A data URI (RFC 2397: "data:[<media type>][;<parameter>]*[;base64],<data>") as its bytes and
// media type. tinygltf decodes only the media types it lists ("image/png", "image/jpeg", ...);
// files in the wild also say "image/jpg", "image/webp", carry parameters, or say nothing, and
// OpenImageIO finds the format from the bytes anyway. Empty bytes with `problem` set when the
// URI cannot be decoded.
struct DataUri {
    std::string bytes, media_type, problem;
};
DataUri decode_data_uri(const std::string& uri) {
    DataUri out;
    const size_t comma = uri.find(',');
    if (uri.rfind("data:", 0) != 0 || comma == std::string::npos) {
        out.problem = "its data URI has no ',' before the data";
        return out;
    }
    const std::string header = uri.substr(5, comma - 5);
    const bool base64_encoded = header.size() >= 7 && header.compare(header.size() - 7, 7, ";base64") == 0;
    out.media_type = header.substr(0, header.find(';'));
    const std::string_view data(uri.data() + comma + 1, uri.size() - comma - 1);
    if (base64_encoded) {
        if (auto bytes = base64_decode(data)) out.bytes = std::move(*bytes);
        else out.problem = "its data URI says base64 but the data is not base64";
    } else {
        out.bytes = uri_decode(std::string(data));
    }
    if (out.bytes.empty() && out.problem.empty()) out.problem = "its data URI holds no bytes";
    return out;
}

}  // namespace

SourceSpan Document::at(const std::string& pointer) const {
    if (json.value_spans.empty()) return {file, 0, 0};
    return json.span(pointer);
}

std::optional<Document> read_document(const std::string& path, SceneSources& sources, DiagnosticSink& sink) {
    // A regular file of at most 1 GiB (under the 4 GiB a GLB and a SourceFile can address).
    std::string error;
    auto read = read_input_file(path, error, kMaxDataInputBytes);
    if (!read) {
        const SourceFile& f = sources.add(path, "");
        sink.report("E308", {&f, 0, 0}, error);
        return std::nullopt;
    }
    const std::string& bytes = *read;
    Document doc;
    doc.name = std::filesystem::path(path).filename().string();
    doc.directory = std::filesystem::path(path).parent_path().string();
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    // The JSON text: the whole file, or a GLB's first chunk (its bounds checked by tinygltf
    // below; here only read when they hold).
    std::string json_text;
    if (!binary) {
        json_text = bytes;
    } else if (bytes.size() >= 20) {
        uint32_t length = 0;
        std::memcpy(&length, bytes.data() + 12, 4);
        if (uint64_t{length} + 20 <= bytes.size()) json_text = bytes.substr(20, length);
    }
    doc.file = &sources.add(path, json_text);
    {
        // Positions for messages; a syntax error is reported here, located.
        DiagnosticSink json_sink;
        if (!parse_json_with_positions(*doc.file, doc.json, json_sink, "E301")) {
            doc.json = PositionedJson{};
            if (!binary || !json_text.empty()) {
                for (const auto& d : json_sink.diagnostics()) sink.add(d);
                if (json_sink.has_errors()) return std::nullopt;
            }
        }
    }
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&fs_exists, &fs_expand, &fs_read, &fs_write, nullptr});
    loader.SetImageLoader(&keep_image, &doc);
    std::string err, warn;
    const bool ok = binary ? loader.LoadBinaryFromMemory(&doc.model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                                         static_cast<unsigned int>(bytes.size()), doc.directory)
                           : loader.LoadASCIIFromString(&doc.model, &err, &warn, bytes.data(), static_cast<unsigned int>(bytes.size()),
                                                        doc.directory);
    if (!ok) {
        sink.report("E308", {doc.file, 0, 0}, fmt::format("cannot read glTF file '{}': {}", path, trimmed(err.empty() ? "not glTF 2.0" : err)));
        return std::nullopt;
    }
    // Where each image's texels are: a file beside the glTF, or bytes carried in it.
    const size_t n = doc.model.images.size();
    doc.image_files.resize(n), doc.image_bytes.resize(n), doc.image_mime.resize(n), doc.image_problem.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const tinygltf::Image& image = doc.model.images[i];
        doc.image_mime[i] = image.mimeType;
        if (!image.uri.empty() && image.uri.rfind("data:", 0) != 0) {
            std::filesystem::path p = std::filesystem::path(doc.directory) / uri_decode(image.uri);
            std::error_code ec;
            const auto absolute = std::filesystem::absolute(p, ec);
            doc.image_files[i] = (ec ? p : absolute).lexically_normal().string();
        } else if (!image.uri.empty() && doc.image_bytes[i].empty()) {
            // A data URI tinygltf did not decode (a media type it does not list).
            DataUri decoded = decode_data_uri(image.uri);
            doc.image_bytes[i] = std::move(decoded.bytes);
            doc.image_problem[i] = std::move(decoded.problem);
            if (doc.image_mime[i].empty()) doc.image_mime[i] = decoded.media_type;
        } else if (image.bufferView >= 0) {
            // Read from the buffer view here, with its bounds checked. A view that is not there
            // costs the image, not the scene: the texture that uses it says so (W310, magenta).
            const auto& views = doc.model.bufferViews;
            if (static_cast<size_t>(image.bufferView) >= views.size() || views[size_t(image.bufferView)].buffer < 0 ||
                static_cast<size_t>(views[size_t(image.bufferView)].buffer) >= doc.model.buffers.size()) {
                doc.image_problem[i] = "its bufferView does not exist";
                continue;
            }
            const auto& view = views[size_t(image.bufferView)];
            const auto& data = doc.model.buffers[size_t(view.buffer)].data;
            if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
                doc.image_problem[i] = "its bufferView reaches past the end of its buffer";
                continue;
            }
            doc.image_bytes[i].assign(reinterpret_cast<const char*>(data.data()) + view.byteOffset, view.byteLength);
        }
    }
    return doc;
}

namespace {

int components_of(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

int component_bytes(int type) {
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return 8;
    default: return 0;
    }
}

// One value of type T at p (an accessor's bytes need not be aligned).
template <class T>
double load(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
}

double component_value(const unsigned char* p, int type, bool normalized) {
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return normalized ? std::max(load<int8_t>(p) / 127.0, -1.0) : load<int8_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: return normalized ? std::max(load<int16_t>(p) / 32767.0, -1.0) : load<int16_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return normalized ? load<uint16_t>(p) / 65535.0 : load<uint16_t>(p);
    case TINYGLTF_COMPONENT_TYPE_INT: return load<int32_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return load<uint32_t>(p);
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return load<float>(p);
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return load<double>(p);
    default: return 0;
    }
}

// The bytes of buffer view `view_index` from `offset` for `count` elements of `element` bytes
// every `stride` (0: packed); null with `error` when they are not all inside its buffer.
const unsigned char* view_bytes(const Document& doc, int view_index, size_t offset, size_t count, size_t element, size_t& stride,
                                std::string& error) {
    const auto& m = doc.model;
    if (view_index < 0 || static_cast<size_t>(view_index) >= m.bufferViews.size()) {
        error = fmt::format("bufferView {} does not exist", view_index);
        return nullptr;
    }
    const auto& view = m.bufferViews[static_cast<size_t>(view_index)];
    if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= m.buffers.size()) {
        error = fmt::format("bufferView {} names buffer {}, which does not exist", view_index, view.buffer);
        return nullptr;
    }
    const auto& data = m.buffers[static_cast<size_t>(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
        error = fmt::format("bufferView {} reaches past the end of buffer {} ({} bytes)", view_index, view.buffer, data.size());
        return nullptr;
    }
    stride = view.byteStride > 0 ? view.byteStride : element;
    if (stride < element || stride > 255) {  // glTF allows strides up to 252
        error = fmt::format("bufferView {}: byteStride {} is not between an element's {} bytes and 255", view_index, stride, element);
        return nullptr;
    }
    // The last element ends at offset + (count - 1) stride + element: in 64 bits, with offset,
    // count and stride bounded first, this cannot overflow.
    if (offset > view.byteLength || count > view.byteLength ||
        (count > 0 && uint64_t(offset) + uint64_t(count - 1) * uint64_t(stride) + element > view.byteLength)) {
        error = fmt::format("{} elements of {} bytes from offset {} do not fit in bufferView {} ({} bytes)", count, element, offset,
                            view_index, view.byteLength);
        return nullptr;
    }
    return data.data() + view.byteOffset + offset;
}

}  // namespace

std::vector<double> read_accessor(const Document& doc, int index, int components, const std::string& pointer, DiagnosticSink& sink) {
    const auto& m = doc.model;
    const std::string where = fmt::format("/accessors/{}", index);
    if (index < 0 || static_cast<size_t>(index) >= m.accessors.size()) {
        sink.report("E303", doc.at(pointer), fmt::format("accessor {} does not exist", index));
        return {};
    }
    const auto& a = m.accessors[static_cast<size_t>(index)];
    const int n = components_of(a.type), bytes = component_bytes(a.componentType);
    if (n != components || bytes == 0) {
        sink.report("E303", doc.at(where), fmt::format("accessor {}: expected {} components per element, it has {}", index, components, n));
        return {};
    }
    // What a file may make us allocate: a count backed by bytes in a buffer, or (sparse
    // without a buffer view) at most 2^24 elements.
    const size_t element = size_t(n) * size_t(bytes);
    const unsigned char* p = nullptr;
    size_t stride = 0;
    if (a.bufferView >= 0) {
        std::string error;
        p = view_bytes(doc, a.bufferView, a.byteOffset, a.count, element, stride, error);
        if (!p) {
            sink.report("E303", doc.at(where), fmt::format("accessor {}: {}", index, error));
            return {};
        }
    } else if (!a.sparse.isSparse) {
        sink.report("E303", doc.at(where), fmt::format("accessor {}: neither a bufferView nor sparse values", index));
        return {};
    } else if (a.count > (size_t{1} << 24)) {
        sink.report("E303", doc.at(where + "/count"), fmt::format("accessor {}: {} elements is more than crex reads", index, a.count));
        return {};
    }
    std::vector<double> out(a.count * size_t(n), 0.0);
    if (p)
        for (size_t i = 0; i < a.count; ++i)
            for (int c = 0; c < n; ++c)
                out[i * size_t(n) + size_t(c)] = component_value(p + i * stride + size_t(c) * size_t(bytes), a.componentType, a.normalized);
    if (a.sparse.isSparse) {
        const size_t count = a.sparse.count > 0 ? size_t(a.sparse.count) : 0;
        const int index_bytes = component_bytes(a.sparse.indices.componentType);
        size_t istride = 0, vstride = 0;
        std::string error;
        const unsigned char* ip = index_bytes == 0 ? nullptr
                                                   : view_bytes(doc, a.sparse.indices.bufferView, size_t(std::max(a.sparse.indices.byteOffset, 0)),
                                                                count, size_t(index_bytes), istride, error);
        const unsigned char* vp = ip ? view_bytes(doc, a.sparse.values.bufferView, size_t(std::max(a.sparse.values.byteOffset, 0)), count, element,
                                                  vstride, error)
                                     : nullptr;
        if (!ip || !vp) {
            sink.report("E303", doc.at(where + "/sparse"), fmt::format("accessor {}: sparse: {}", index, error.empty() ? "bad index type" : error));
            return {};
        }
        istride = size_t(index_bytes), vstride = element;  // sparse arrays are tightly packed
        for (size_t k = 0; k < count; ++k) {
            const double target = component_value(ip + k * istride, a.sparse.indices.componentType, false);
            if (!(target >= 0) || target >= double(a.count)) {
                sink.report("E303", doc.at(where + "/sparse"), fmt::format("accessor {}: sparse index {} is out of range", index, target));
                return {};
            }
            for (int c = 0; c < n; ++c)
                out[size_t(target) * size_t(n) + size_t(c)] = component_value(vp + k * vstride + size_t(c) * size_t(bytes), a.componentType, a.normalized);
        }
    }
    return out;
}

std::vector<uint32_t> read_indices(const Document& doc, int index, const std::string& pointer, DiagnosticSink& sink) {
    const size_t errors = sink.error_count();
    std::vector<double> values = read_accessor(doc, index, 1, pointer, sink);
    std::vector<uint32_t> out;
    if (sink.error_count() != errors) return out;
    const auto& a = doc.model.accessors[static_cast<size_t>(index)];
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        sink.report("E303", doc.at(fmt::format("/accessors/{}/componentType", index)),
                    fmt::format("accessor {}: indices must be unsigned integers", index));
        return out;
    }
    out.reserve(values.size());
    for (double v : values) out.push_back(static_cast<uint32_t>(v));
    return out;
}

std::string camera_name(const tinygltf::Camera& camera, const tinygltf::Node& node, size_t index) {
    return !camera.name.empty() ? camera.name : !node.name.empty() ? node.name : fmt::format("camera{}", index);
}

std::vector<int> scene_roots(const tinygltf::Model& m) {
    if (!m.scenes.empty()) {
        const size_t s = m.defaultScene >= 0 && static_cast<size_t>(m.defaultScene) < m.scenes.size() ? size_t(m.defaultScene) : 0;
        return m.scenes[s].nodes;
    }
    std::vector<bool> child(m.nodes.size(), false);
    for (const auto& n : m.nodes)
        for (int c : n.children)
            if (c >= 0 && static_cast<size_t>(c) < child.size()) child[size_t(c)] = true;
    std::vector<int> roots;
    for (size_t i = 0; i < m.nodes.size(); ++i)
        if (!child[i]) roots.push_back(static_cast<int>(i));
    return roots;
}

}  // namespace crex::gltf
