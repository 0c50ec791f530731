#include "runtime/scene/radiance/compiled_mesh.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

#include "base/input_file.h"

namespace crex::radiance {
namespace {

// RADIANCE's format numbers: the first 2-byte integer is MESHMAGIC + sizeof(OBJECT).
constexpr int kMaxObjectSize = 8;
constexpr long kMeshMagic = 1 * kMaxObjectSize + 311;
constexpr long kOctreeMagic = 4 * kMaxObjectSize + 251;
constexpr int kTreeEmpty = 0, kTreeFull = 1, kTreeNode = 2;
constexpr int kVertices = 1, kNormals = 2, kUvs = 4;

class Reader {
public:
    explicit Reader(std::string bytes) : b_(std::move(bytes)) {}
    bool failed() const { return !error_.empty(); }
    const std::string& error() const { return error_; }
    size_t at() const { return i_; }
    void fail(const std::string& message) {
        if (error_.empty()) error_ = fmt::format("{} (at byte {})", message, i_);
    }
    int byte() {
        if (i_ >= b_.size()) {
            fail("the file ends early");
            return -1;
        }
        return static_cast<unsigned char>(b_[i_++]);
    }
    // RADIANCE's portable integers: big-endian, the first byte signed.
    long integer(int size) {
        int c = byte();
        if (c < 0) return 0;
        long r = c & 0x80 ? c - 256 : c;
        for (int k = 1; k < size; ++k) {
            c = byte();
            if (c < 0) return 0;
            r = r * 256 + c;
        }
        return r;
    }
    double real() {
        const long mantissa = integer(4);
        if (mantissa == 0) {
            byte();
            return 0;
        }
        const double d = (mantissa + .5 - (mantissa < 0)) * (1. / 0x7fffffff);
        return std::ldexp(d, static_cast<int>(integer(1)));
    }
    std::string text() {
        const size_t end = b_.find('\0', i_);
        if (end == std::string::npos) {
            fail("a string runs to the end of the file");
            i_ = b_.size();
            return "";
        }
        std::string s = b_.substr(i_, end - i_);
        i_ = end + 1;
        return s;
    }
    // The text header: lines up to an empty one; returns its FORMAT= value.
    std::string header() {
        std::string format;
        if (b_.empty()) {
            fail("the file is empty");
            return format;
        }
        if (b_.rfind("#?RADIANCE", 0) != 0) {
            fail("it is not a RADIANCE file (it does not begin with '#?RADIANCE')");
            return format;
        }
        while (i_ < b_.size()) {
            const size_t end = b_.find('\n', i_);
            if (end == std::string::npos) break;
            const std::string line = b_.substr(i_, end - i_);
            i_ = end + 1;
            if (line.empty()) return format;
            if (line.rfind("FORMAT=", 0) == 0) format = line.substr(7);
        }
        fail("the header does not end");
        return format;
    }

private:
    std::string b_;
    size_t i_ = 0;
    std::string error_;
};

void skip_tree(Reader& r, int object_size, int depth) {
    if (depth > 64) return r.fail("the octree nests too deeply");
    switch (r.byte()) {
    case kTreeEmpty: return;
    case kTreeFull: {
        const long n = r.integer(object_size);
        if (n < 0 || n > 4096) return r.fail("a damaged octree node");
        for (long k = 0; k < n && !r.failed(); ++k) r.integer(object_size);
        return;
    }
    case kTreeNode:
        for (int k = 0; k < 8 && !r.failed(); ++k) skip_tree(r, object_size, depth + 1);
        return;
    default: return r.fail("a damaged octree");
    }
}

// RADIANCE's 32-bit direction code (dircode.c): two 13-bit components, which axes they are
// and the three signs.
Vec3 decode_direction(uint32_t code) {
    if (!code) return {};
    constexpr double kScale = 11584.5;
    const double d1 = (code >> 5 & 0x1fff) / kScale, d2 = (code >> 18 & 0x1fff) / kScale;
    const double rest = std::sqrt(std::fmax(0.0, 1 - d1 * d1 - d2 * d2));
    double v[3];
    static const int order[4][3] = {{1, 0, 2}, {0, 1, 2}, {1, 2, 0}, {0, 2, 1}};
    const int k = ((code & 020) != 0) << 1 | ((code & 010) != 0);
    v[order[k][0]] = d1, v[order[k][1]] = d2, v[order[k][2]] = rest;
    if (code & 01) v[0] = -v[0];
    if (code & 02) v[1] = -v[1];
    if (code & 04) v[2] = -v[2];
    return {v[0], v[1], v[2]};
}

}  // namespace

bool read_binary_scene(Reader& r, int object_size, std::vector<BinaryObject>& out);

bool read_compiled_mesh(const std::string& path, CompiledMesh& out, std::string& error, size_t max_triangles) {
    std::optional<std::string> bytes = read_input_file(path, error, kMaxDataInputBytes);  // never /dev/zero or a FIFO
    if (!bytes) return false;
    Reader r(std::move(*bytes));
    const std::string format = r.header();
    if (!r.failed() && format != "Radiance_tmesh") r.fail(fmt::format("its format is '{}', not a compiled mesh (Radiance_tmesh)", format));
    const int object_size = static_cast<int>(r.integer(2) - kMeshMagic);
    if (!r.failed() && (object_size <= 0 || object_size > kMaxObjectSize)) r.fail("an incompatible mesh format number");
    double cube[4];
    for (double& c : cube) c = std::strtod(r.text().c_str(), nullptr);
    double uv_limits[2][2];
    for (int i = 0; i < 2; ++i) uv_limits[0][i] = r.real(), uv_limits[1][i] = r.real();
    if (!r.failed()) skip_tree(r, object_size, 0);
    CompiledMesh m;
    if (!r.failed()) read_binary_scene(r, object_size, m.materials);
    const long patches = r.integer(4);
    if (!r.failed() && (patches < 0 || patches > (1L << 24))) r.fail("a bad number of patches");
    // Vertex ids are patch << 8 | vertex, resolved once every patch is read (a joining
    // triangle may name a later patch's vertex); each patch's first position in `m.positions`.
    std::vector<size_t> first;
    std::vector<std::array<long, 3>> ids;
    auto vertex = [&](long id) -> uint32_t {
        const long p = id >> 8, v = id & 0xff;
        if (p < 0 || static_cast<size_t>(p) >= first.size() || first[static_cast<size_t>(p)] + static_cast<size_t>(v) >=
                                                                   (static_cast<size_t>(p) + 1 < first.size() ? first[static_cast<size_t>(p) + 1] : m.positions.size())) {
            r.fail(fmt::format("a triangle names vertex {} of patch {}, which does not exist", v, p));
            return 0;
        }
        return static_cast<uint32_t>(first[static_cast<size_t>(p)] + static_cast<size_t>(v));
    };
    auto material = [&](long k) -> int {
        if (k == -1) return -1;
        if (k < 0 || static_cast<size_t>(k) >= m.materials.size()) {
            r.fail(fmt::format("a triangle names material {}, which the mesh does not have", k));
            return -1;
        }
        return static_cast<int>(k);
    };
    const double scale = cube[3] / 4294967296.0;
    for (long p = 0; p < patches && !r.failed(); ++p) {
        const int flags = static_cast<int>(r.integer(1));
        if (!(flags & kVertices) || (flags & ~(kVertices | kNormals | kUvs))) {
            r.fail("bad patch flags");
            break;
        }
        const long n = r.integer(2);
        if (n <= 0 || n > 256) {
            r.fail("a bad number of patch vertices");
            break;
        }
        first.push_back(m.positions.size());
        const size_t base = m.positions.size();
        for (long v = 0; v < n; ++v) {
            double xyz[3];
            for (int k = 0; k < 3; ++k) xyz[k] = cube[k] + (static_cast<double>(static_cast<uint32_t>(r.integer(4))) + .5) * scale;
            m.positions.push_back({xyz[0], xyz[1], xyz[2]});
        }
        m.normals.resize(m.positions.size());
        m.uvs.resize(m.positions.size());
        if (flags & kNormals)
            for (long v = 0; v < n; ++v) {
                m.normals[base + static_cast<size_t>(v)] = decode_direction(static_cast<uint32_t>(r.integer(4)));
                m.has_normals = true;
            }
        if (flags & kUvs)
            for (long v = 0; v < n; ++v) {
                std::array<double, 2>& uv = m.uvs[base + static_cast<size_t>(v)];
                for (int k = 0; k < 2; ++k)
                    uv[static_cast<size_t>(k)] = uv_limits[0][k] + (uv_limits[1][k] - uv_limits[0][k]) *
                                                                      (static_cast<uint32_t>(r.integer(4)) + .5) / 4294967296.0;
                m.has_uvs = true;
            }
        const long local = r.integer(2);
        if (local < 0 || local > 512) {
            r.fail("a bad number of local triangles");
            break;
        }
        std::vector<std::array<long, 3>> tris(static_cast<size_t>(local));
        for (auto& t : tris)
            for (long& v : t) v = r.integer(1) & 0xff;
        const long materials = r.integer(2);
        std::vector<int> mats(static_cast<size_t>(local), -1);
        if (materials > 1) {
            for (int& k : mats) k = material(r.integer(2));
        } else {
            const int sole = material(r.integer(2));
            for (int& k : mats) k = sole;
        }
        for (size_t t = 0; t < tris.size() && !r.failed(); ++t) {
            ids.push_back({p << 8 | tris[t][0], p << 8 | tris[t][1], p << 8 | tris[t][2]});
            m.triangle_material.push_back(mats[t]);
        }
        const long joined1 = r.integer(2);
        if (joined1 < 0 || joined1 > 256) {
            r.fail("a bad number of joining triangles");
            break;
        }
        for (long t = 0; t < joined1 && !r.failed(); ++t) {
            const long a = r.integer(4), b = r.integer(1) & 0xff, c = r.integer(1) & 0xff;
            const int k = material(r.integer(2));
            ids.push_back({a, p << 8 | b, p << 8 | c});
            m.triangle_material.push_back(k);
        }
        const long joined2 = r.integer(2);
        if (joined2 < 0 || joined2 > 256) {
            r.fail("a bad number of doubly joining triangles");
            break;
        }
        for (long t = 0; t < joined2 && !r.failed(); ++t) {
            const long a = r.integer(4), b = r.integer(4), c = r.integer(1) & 0xff;
            const int k = material(r.integer(2));
            ids.push_back({a, b, p << 8 | c});
            m.triangle_material.push_back(k);
        }
        if (ids.size() > max_triangles) r.fail(fmt::format("more than {} triangles", max_triangles));
    }
    m.triangles.reserve(ids.size());
    for (size_t t = 0; t < ids.size() && !r.failed(); ++t) m.triangles.push_back({vertex(ids[t][0]), vertex(ids[t][1]), vertex(ids[t][2])});
    if (r.failed()) {
        error = r.error();
        return false;
    }
    out = std::move(m);
    return true;
}

bool read_octree(const std::string& path, std::vector<BinaryObject>& objects, std::vector<std::string>& files, std::string& error) {
    std::optional<std::string> bytes = read_input_file(path, error, kMaxDataInputBytes);
    if (!bytes) return false;
    Reader r(std::move(*bytes));
    const std::string format = r.header();
    if (!r.failed() && format != "Radiance_octree") r.fail(fmt::format("its format is '{}', not an octree (Radiance_octree)", format));
    const int object_size = static_cast<int>(r.integer(2) - kOctreeMagic);
    if (!r.failed() && (object_size <= 0 || object_size > kMaxObjectSize)) r.fail("an incompatible octree format number");
    for (int k = 0; k < 4 && !r.failed(); ++k) r.text();  // the cube
    std::vector<std::string> names;
    while (!r.failed()) {
        std::string f = r.text();
        if (f.empty()) break;
        names.push_back(std::move(f));
        if (names.size() > 4096) r.fail("a damaged list of scene files");
    }
    const long count = r.integer(object_size);
    if (!r.failed() && (count < 0 || count > (1L << 26))) r.fail("a bad object count");
    std::vector<BinaryObject> scene;
    if (!r.failed() && names.empty()) {
        skip_tree(r, object_size, 0);
        if (!r.failed()) read_binary_scene(r, object_size, scene);
        if (!r.failed() && static_cast<long>(scene.size()) != count)
            r.fail(fmt::format("the octree counts {} objects but holds {}", count, scene.size()));
    }
    if (r.failed()) {
        error = r.error();
        return false;
    }
    objects = std::move(scene);
    files = std::move(names);
    return true;
}

// A binary scene (sceneio.c): the writer's type names (their order is the type numbers), an
// empty name, then objects until a type byte of -1.
bool read_binary_scene(Reader& r, int object_size, std::vector<BinaryObject>& out) {
    std::vector<std::string> types;
    for (;;) {
        std::string t = r.text();
        if (r.failed()) return false;
        if (t.empty()) break;
        types.push_back(std::move(t));
        if (types.size() > 1024) {
            r.fail("a damaged type table");
            return false;
        }
    }
    for (;;) {
        const long type = r.integer(1);
        if (r.failed()) return false;
        if (type == -1) return true;
        if (type < 0 || static_cast<size_t>(type) >= types.size()) {
            r.fail(fmt::format("an object of type number {}, which the type table does not have", type));
            return false;
        }
        BinaryObject o;
        o.type = types[static_cast<size_t>(type)];
        const long mod = r.integer(object_size);
        if (mod != -1 && (mod < 0 || static_cast<size_t>(mod) >= out.size())) {
            r.fail(fmt::format("object {} is modified by object {}, which does not come before it", out.size(), mod));
            return false;
        }
        o.modifier = static_cast<int>(mod);
        o.name = r.text();
        const long strings = r.integer(2);
        if (strings < 0 || strings > 4096) {
            r.fail("a bad number of string arguments");
            return false;
        }
        for (long k = 0; k < strings && !r.failed(); ++k) o.strings.push_back(r.text());
        const long reals = r.integer(2);
        if (reals < 0 || reals > 1 << 20) {
            r.fail("a bad number of real arguments");
            return false;
        }
        for (long k = 0; k < reals && !r.failed(); ++k) o.reals.push_back(r.real());
        if (r.failed()) return false;
        out.push_back(std::move(o));
    }
}

}  // namespace crex::radiance
