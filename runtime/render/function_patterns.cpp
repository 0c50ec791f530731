#include "runtime/render/function_patterns.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "runtime/base/sampling.h"
#include "runtime/render/bsdf.h"
#include "runtime/io/image_io.h"
#include "runtime/scene/data_table.h"
#include "runtime/scene/text_pattern.h"
#include "runtime/scene/radiance/calc.h"

namespace crex {

namespace calc = radiance::calc;
using NodePtr = std::shared_ptr<const calc::Node>;

struct PatternChain::Compiled {
    FunctionPattern::Kind kind = FunctionPattern::Kind::kBrightFunc;
    std::string name;
    calc::Program program;
    std::vector<NodePtr> functions;    // func: the factor's expressions
    std::vector<NodePtr> applied;      // data, pict: per channel, its function of the looked-up values _v1.._v3
    std::vector<NodePtr> coordinates;
    std::vector<DataTable> tables;     // data: its tables; pict: the picture's red, green, blue
    std::vector<double> args;
    std::array<double, 12> m{};
    double scale = 1;
    std::unique_ptr<TextLayout> text;  // text: where the letters are
    Vec3 inside, outside;              // text: the factor in letters and out of them
};

namespace {

// The ray as a pattern's expressions see it, in the pattern's coordinates (RADIANCE's
// chanvalue): direction, normal, point, distance, cosine, scale and the frame's axes.
struct RayValues {
    double D[3], N[3], P[3], T, Rdot, S, origin[3], I[3], J[3], K[3];
    double NP[3], RdotP;  // the normal turned towards the ray, and its cosine (BRTDfunc's)
    double Lu, Lv;        // a mesh's texture coordinates
    double L[3];          // a directional function's light direction
};

std::optional<double> ray_variable(const RayValues& r, const std::string& n) {
    if (n.size() == 2) {
        const int axis = n[1] == 'x' ? 0 : n[1] == 'y' ? 1 : n[1] == 'z' ? 2 : -1;
        if (axis >= 0) switch (n[0]) {
            case 'D': return r.D[axis];
            case 'N': return r.N[axis];
            case 'P': return r.P[axis];
            case 'T': return r.origin[axis];
            case 'I': return r.I[axis];
            case 'J': return r.J[axis];
            case 'K': return r.K[axis];
            default: break;
            }
        if (n == "Ts") return r.T;
    }
    if (n.size() == 3 && n[0] == 'N' && n[2] == 'P') {
        const int axis = n[1] == 'x' ? 0 : n[1] == 'y' ? 1 : n[1] == 'z' ? 2 : -1;
        if (axis >= 0) return r.NP[axis];
    }
    if (n == "RdotP") return r.RdotP;
    if (n == "Lu") return r.Lu;
    if (n == "DxA" || n == "DyA" || n == "DzA") return 0.0;  // RADIANCE's virtual-source direction: none here
    if (n.size() == 7 && n[0] == 'L' && n.compare(2, 5, "_crex") == 0) {
        const int axis = n[1] == 'x' ? 0 : n[1] == 'y' ? 1 : n[1] == 'z' ? 2 : -1;
        if (axis >= 0) return r.L[axis];
    }
    if (n == "Lv") return r.Lv;
    if (n == "CrP" || n == "CgP" || n == "CbP") return 1.0;  // no pattern colours a BRTDfunc here
    if (n == "T") return r.T;
    if (n == "S") return r.S;
    if (n == "Rdot") return r.Rdot;
    return std::nullopt;
}

RayValues ray_values(const PatternChain::Compiled& c, const PatternRay& ray, const Vec3& world_point) {
    RayValues v{};
    const auto& m = c.m;
    const double s = c.scale;
    auto rotate = [&](const Vec3& a, double* out) {
        for (int k = 0; k < 3; ++k) out[k] = (m[4 * k] * a.x + m[4 * k + 1] * a.y + m[4 * k + 2] * a.z) / s;
    };
    rotate(ray.direction, v.D);
    rotate(ray.normal, v.N);
    rotate(ray.light, v.L);
    for (int k = 0; k < 3; ++k)
        v.P[k] = ray.distant ? 0.0 : m[4 * k] * world_point.x + m[4 * k + 1] * world_point.y + m[4 * k + 2] * world_point.z + m[4 * k + 3];
    v.T = ray.distance * s;
    v.Rdot = std::clamp(-dot(ray.direction, ray.normal), -1.0, 1.0);
    v.RdotP = std::fabs(v.Rdot);
    v.Lu = ray.u, v.Lv = ray.v;
    for (int k = 0; k < 3; ++k) v.NP[k] = v.Rdot < 0 ? -v.N[k] : v.N[k];
    v.S = s;
    for (int k = 0; k < 3; ++k) {
        v.origin[k] = m[4 * k + 3];
        v.I[k] = m[4 * k] / s, v.J[k] = m[4 * k + 1] / s, v.K[k] = m[4 * k + 2] / s;
    }
    return v;
}

bool direction_only(const calc::Program& program, const NodePtr& expr) {
    // _v1.._v3: the values a data or picture pattern looked up (at coordinates checked too).
    static const std::set<std::string> fixed{"_v1", "_v2", "_v3", "Dx", "Dy", "Dz", "S", "Tx", "Ty", "Tz", "Ix", "Iy", "Iz", "Jx", "Jy", "Jz", "Kx", "Ky", "Kz"};
    for (const std::string& n : program.free_names(*expr))
        if (!fixed.count(n) && n != "AC" && !(n.size() >= 2 && n[0] == 'A' && n.find_first_not_of("0123456789", 1) == std::string::npos))
            return false;
    return true;
}

// A NaN or infinite value of a float picture (EXR, PFM, HDR) would spread through every
// interpolation that touches it: each becomes the mean of the finite values of its channel in
// its 3x3 neighbourhood (oiiotool's --fixnan box3), 0 where there are none. Returns how many.
size_t repair_non_finite(std::vector<float>& rgb, int w, int h) {
    std::vector<size_t> bad;
    for (size_t i = 0; i < rgb.size(); ++i)
        if (!std::isfinite(rgb[i])) bad.push_back(i);
    if (bad.empty()) return 0;
    const std::vector<float> before = rgb;
    for (size_t i : bad) {
        const int c = static_cast<int>(i % 3), x = static_cast<int>(i / 3 % static_cast<size_t>(w)), y = static_cast<int>(i / 3 / static_cast<size_t>(w));
        double sum = 0;
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int u = x + dx, v = y + dy;
                if (u < 0 || v < 0 || u >= w || v >= h) continue;
                const float f = before[(static_cast<size_t>(v) * static_cast<size_t>(w) + static_cast<size_t>(u)) * 3 + static_cast<size_t>(c)];
                if (std::isfinite(f)) sum += f, ++n;
            }
        rgb[i] = n > 0 ? static_cast<float>(sum / n) : 0.0f;
    }
    return bad.size();
}

// A picture as RADIANCE's patterns address it: (v, u) from its lower-left corner, the shorter
// side 1 long; one table per channel. `repaired`: its values that were not finite.
std::string picture_tables(const std::string& file, std::vector<DataTable>& out, size_t& repaired) {
    int w = 0, h = 0;
    std::vector<float> rgb;
    if (std::string error = read_image(file, w, h, rgb); !error.empty()) return error;
    if (w < 2 || h < 2) return fmt::format("it is {}x{} pixels (at least 2x2 are needed)", w, h);
    repaired = repair_non_finite(rgb, w, h);
    DataTable t;
    DataTable::Axis rows, cols;
    rows.count = h, cols.count = w;
    rows.size = w <= h ? static_cast<double>(h) / w : 1.0;
    cols.size = w <= h ? 1.0 : static_cast<double>(w) / h;
    t.axes = {rows, cols};
    out.assign(3, t);
    for (int c = 0; c < 3; ++c) {
        std::vector<double>& v = out[static_cast<size_t>(c)].values;
        v.resize(static_cast<size_t>(w) * static_cast<size_t>(h));
        for (int y = 0; y < h; ++y)  // the file's top row is the table's last
            for (int x = 0; x < w; ++x)
                v[static_cast<size_t>(h - 1 - y) * static_cast<size_t>(w) + static_cast<size_t>(x)] =
                    rgb[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 3 + static_cast<size_t>(c)];
    }
    return "";
}

constexpr int kTableWidth = 512, kTableHeight = 256;

}  // namespace

PatternChain::PatternChain(const std::vector<FunctionPattern>& patterns, const Vec3& origin_offset, std::vector<Diagnostic>& warnings)
    : offset_(origin_offset) {
    bool only_direction = true;
    for (const FunctionPattern& f : patterns) {
        auto c = std::make_unique<Compiled>();
        c->kind = f.kind;
        c->name = f.name;
        c->args = f.args;
        c->m = f.to_pattern;
        c->scale = f.scale > 0 ? f.scale : 1;
        calc::Error e;
        bool ok = c->program.define(f.definitions, e);
        c->program.bind();
        auto parse = [&](const std::string& text) {
            NodePtr n = ok ? c->program.parse(text, e) : nullptr;
            if (!n) ok = false;
            else only_direction = only_direction && direction_only(c->program, n);
            return n;
        };
        using K = FunctionPattern::Kind;
        const bool func = f.kind == K::kBrightFunc || f.kind == K::kColorFunc;
        if (f.kind == K::kBrightText || f.kind == K::kColorText) {
            // A, R, D, then the inside and outside factors (grey or RGB), then the spacing.
            const size_t channels = f.kind == K::kColorText ? 3 : 1, n = 9 + 2 * channels;
            Font font;
            std::string problem;
            const std::vector<double>& a = f.args;
            if (a.size() < n || !parse_font(f.font, font, problem)) {
                warnings.push_back(run_diagnostic("W309", f.name, fmt::format("text pattern '{}': {}: the pattern is left out", f.name,
                                                                              problem.empty() ? "too few arguments" : problem)));
                continue;
            }
            auto factor = [&](size_t at) { return channels == 3 ? Vec3{a[at], a[at + 1], a[at + 2]} : Vec3{a[at], a[at], a[at]}; };
            c->inside = factor(9), c->outside = factor(9 + channels);
            c->text = std::make_unique<TextLayout>(std::move(font), f.text, Vec3{a[0], a[1], a[2]}, Vec3{a[3], a[4], a[5]},
                                                   Vec3{a[6], a[7], a[8]}, a.size() > n, a.size() > n ? a[n] : 0.0);
            if (!c->text->valid()) {
                warnings.push_back(run_diagnostic("W309", f.name, fmt::format("text pattern '{}': its right and down vectors are parallel "
                                                                              "or zero: the pattern is left out", f.name)));
                continue;
            }
            only_direction = false;
            patterns_.push_back(std::move(c));
            continue;
        }
        if (func) {
            for (const std::string& text : f.functions) c->functions.push_back(parse(text));
        } else {
            // Per channel: its function of the channel's value (_v1, _v2 or _v3), of all three
            // (as `red` of a picture), or a variable.
            for (size_t i = 0; i < 3; ++i) {
                const std::string& text = f.functions[std::min(i, f.functions.size() - 1)];
                const bool three = f.kind != K::kBrightData && !c->program.takes(text, 1) && c->program.takes(text, 3);
                const std::string value = f.kind == K::kBrightData ? "_v1" : fmt::format("_v{}", i + 1);
                c->applied.push_back(parse(c->program.has_variable(text) ? text : three ? text + "(_v1, _v2, _v3)" : text + "(" + value + ")"));
            }
        }
        for (const std::string& text : f.coordinates) c->coordinates.push_back(parse(text));
        c->tables = f.tables;
        if (f.kind == K::kColorPict) {
            size_t repaired = 0;
            if (std::string error = picture_tables(f.picture, c->tables, repaired); !error.empty()) {
                warnings.push_back(run_diagnostic("W309", f.name, fmt::format("colorpict '{}': the picture '{}' cannot be read "
                                                       "({}): the pattern is left out", f.name, f.picture, error)));
                continue;
            }
            if (repaired > 0)
                warnings.push_back(run_diagnostic(
                    "W314", f.picture,
                    fmt::format("colorpict '{}': the picture holds {} value{} that {} not finite (NaN or infinite): each reads as the "
                                "mean of its finite neighbours; repair the file, e.g. oiiotool FILE --fixnan box3 -o FIXED",
                                f.name, repaired, repaired == 1 ? "" : "s", repaired == 1 ? "is" : "are")));
        }
        if (!ok) {
            warnings.push_back(run_diagnostic("W309", f.name, fmt::format("pattern '{}': {}: the pattern is left out", f.name,
                                                                                     e.message)));
            continue;
        }
        patterns_.push_back(std::move(c));
    }
    if (patterns_.empty() || !only_direction) return;
    // Tabulate: one evaluation per cell centre of (phi, theta) over the sphere.
    table_w_ = kTableWidth, table_h_ = kTableHeight;
    table_.resize(static_cast<size_t>(table_w_) * static_cast<size_t>(table_h_));
    tbb::parallel_for(0, table_h_, [&](int y) {
        const double theta = kPi * (y + 0.5) / table_h_;
        for (int x = 0; x < table_w_; ++x) {
            const double phi = 2 * kPi * (x + 0.5) / table_w_;
            PatternRay r;
            r.direction = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
            r.normal = -r.direction;
            r.distant = true;
            table_[static_cast<size_t>(y) * static_cast<size_t>(table_w_) + static_cast<size_t>(x)] = evaluate(r);
        }
    });
    // Lookups read the table only: a sky picture's three channels in doubles (384 MB for a
    // 4096 x 4096 photograph) need not outlive it.
    for (auto& c : patterns_) std::vector<DataTable>().swap(c->tables);
}

PatternChain::~PatternChain() = default;

Vec3 PatternChain::evaluate(const PatternRay& ray) const {
    Vec3 product{1, 1, 1};
    const Vec3 world = ray.point + offset_;
    for (const auto& cp : patterns_) {
        const Compiled& c = *cp;
        const RayValues rv = ray_values(c, ray, world);
        if (c.text) {
            const Vec3 v = c.text->inside(Vec3{rv.P[0], rv.P[1], rv.P[2]}) ? c.inside : c.outside;
            product = product * Vec3{std::fmax(v.x, 0.0), std::fmax(v.y, 0.0), std::fmax(v.z, 0.0)};
            continue;
        }
        double values[3] = {0, 0, 0};  // the looked-up values, _v1.._v3 of the applied functions
        calc::Environment env;
        env.args = c.args;
        env.variable = [&](const std::string& n) -> std::optional<double> {
            if (n.size() == 3 && n[0] == '_' && n[1] == 'v' && n[2] >= '1' && n[2] <= '3') return values[n[2] - '1'];
            return ray_variable(rv, n);
        };
        calc::Error e;
        double out[3] = {0, 0, 0};
        bool ok = true;
        auto eval = [&](const NodePtr& n) {
            std::optional<double> v = ok ? c.program.evaluate(*n, env, e) : std::nullopt;
            if (!v || !std::isfinite(*v)) ok = false;
            return v ? *v : 0.0;
        };
        if (!c.functions.empty()) {
            for (size_t i = 0; i < 3; ++i) out[i] = eval(c.functions[std::min(i, c.functions.size() - 1)]);
        } else {
            double pt[8] = {};
            const size_t dims = std::min<size_t>(c.coordinates.size(), 8);
            for (size_t i = 0; i < dims; ++i) pt[i] = eval(c.coordinates[i]);
            if (c.kind == FunctionPattern::Kind::kColorPict) std::swap(pt[0], pt[1]);  // (u, v) -> rows, columns
            if (!ok) return {};
            for (size_t i = 0; i < c.tables.size() && i < 3; ++i) values[i] = data_value(c.tables[i], pt);
            for (size_t i = 0; i < 3; ++i) out[i] = eval(c.applied[i]);
        }
        if (!ok) return {};
        product = product * Vec3{std::fmax(out[0], 0.0), std::fmax(out[1], 0.0), std::fmax(out[2], 0.0)};
    }
    return is_finite(product) ? product : Vec3{};
}

Vec3 PatternChain::value(const PatternRay& ray) const {
    if (table_.empty()) return evaluate(ray);
    const Vec3& d = ray.direction;
    const double theta = std::acos(std::clamp(d.z, -1.0, 1.0));
    double phi = std::atan2(d.y, d.x);
    if (phi < 0) phi += 2 * kPi;
    const double fx = phi / (2 * kPi) * table_w_ - 0.5, fy = theta / kPi * table_h_ - 0.5;
    const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
    const double ax = fx - x0, ay = fy - y0;
    auto at = [&](int x, int y) {
        x = (x % table_w_ + table_w_) % table_w_;
        y = std::clamp(y, 0, table_h_ - 1);
        return table_[static_cast<size_t>(y) * static_cast<size_t>(table_w_) + static_cast<size_t>(x)];
    };
    return (at(x0, y0) * (1 - ax) + at(x0 + 1, y0) * ax) * (1 - ay) + (at(x0, y0 + 1) * (1 - ax) + at(x0 + 1, y0 + 1) * ax) * ay;
}

double PatternChain::mean_over_hemisphere(const Vec3& n, const Vec3& point) const {
    Vec3 t, b;
    orthonormal_basis(n, t, b);
    constexpr int kSide = 8;
    double sum = 0;
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j) {
            const double u = (i + 0.5) / kSide, v = (j + 0.5) / kSide;
            const double r = std::sqrt(u), phi = 2 * kPi * v, z = std::sqrt(std::fmax(0.0, 1 - u));
            const Vec3 leaving = n * z + t * (r * std::cos(phi)) + b * (r * std::sin(phi));
            PatternRay ray;
            ray.direction = -leaving;
            ray.normal = n;
            ray.point = point;
            sum += luminance(value(ray));
        }
    return sum / (kSide * kSide);
}

ScenePatterns::ScenePatterns(const Scene& scene, const Vec3& origin_offset, std::vector<Diagnostic>& warnings) {
    chains_.resize(scene.materials.size());
    surfaces_.resize(scene.materials.size());
    mixtures_.resize(scene.materials.size());
    directionals_.resize(scene.materials.size());
    redirects_.resize(scene.materials.size());
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        if (!m.patterns.empty()) chains_[i] = std::make_unique<PatternChain>(m.patterns, origin_offset, warnings);
        if (m.surface_functions) {
            auto s = std::make_unique<SurfaceChains>();
            s->functions = &*m.surface_functions;
            s->reflection = std::make_unique<PatternChain>(std::vector<FunctionPattern>{m.surface_functions->reflection}, origin_offset, warnings);
            s->transmission =
                std::make_unique<PatternChain>(std::vector<FunctionPattern>{m.surface_functions->transmission}, origin_offset, warnings);
            surfaces_[i] = std::move(s);
        }
        if (!m.redirections.empty()) {
            auto r = std::make_unique<RedirectChains>();
            for (const Redirection& x : m.redirections)
                r->parts.push_back({std::make_unique<PatternChain>(std::vector<FunctionPattern>{x.coefficient}, origin_offset, warnings),
                                    std::make_unique<PatternChain>(std::vector<FunctionPattern>{x.direction}, origin_offset, warnings)});
            redirects_[i] = std::move(r);
        }
        if (m.directional)
            directionals_[i] = std::make_unique<PatternChain>(std::vector<FunctionPattern>{m.directional->shape}, origin_offset, warnings);
        if (m.mixture) {
            auto x = std::make_unique<MixtureChain>();
            x->coefficient = std::make_unique<PatternChain>(std::vector<FunctionPattern>{m.mixture->coefficient}, origin_offset, warnings);
            for (size_t k = 0; k < scene.materials.size(); ++k)
                if (scene.materials[k].name == m.mixture->background) x->background = static_cast<uint32_t>(k);
            mixtures_[i] = std::move(x);
        }
    }
}

std::optional<Vec3> PatternChain::raw(const PatternRay& ray) const {
    if (patterns_.empty() || patterns_[0]->functions.empty()) return std::nullopt;
    const Compiled& c = *patterns_[0];
    const RayValues rv = ray_values(c, ray, ray.point + offset_);
    calc::Environment env;
    env.args = c.args;
    env.variable = [&](const std::string& n) { return ray_variable(rv, n); };
    calc::Error e;
    double out[3];
    for (size_t i = 0; i < 3; ++i) {
        std::optional<double> v = c.program.evaluate(*c.functions[std::min(i, c.functions.size() - 1)], env, e);
        if (!v || !std::isfinite(*v)) return std::nullopt;
        out[i] = *v;
    }
    return Vec3{out[0], out[1], out[2]};
}

Vec3 PatternChain::direction_to_world(const Vec3& v) const {
    if (patterns_.empty()) return v;
    // The rows of `m` are the pattern's axes in world coordinates over scale^2.
    const auto& m = patterns_[0]->m;
    Vec3 w;
    for (int k = 0; k < 3; ++k) w += Vec3{m[4 * k], m[4 * k + 1], m[4 * k + 2]} * (k == 0 ? v.x : k == 1 ? v.y : v.z);
    return w;
}

int RedirectChains::lobes(const PatternRay& ray, const Vec3& side, Lobe* out, int n, int max) const {
    for (const Part& p : parts) {
        if (n >= max) break;
        const std::optional<Vec3> coefficient = p.coefficient->raw(ray);
        const std::optional<Vec3> direction = p.direction->raw(ray);
        if (!coefficient || !direction || !(coefficient->x > 0)) continue;
        const Vec3 dir = normalize_or_zero(p.direction->direction_to_world(*direction));
        if (dir == Vec3{} || dot(dir, side) == 0) continue;
        const double w = std::fmin(coefficient->x, 1e6);  // a runaway expression must not blow up the image
        add_lobe(out, n, Component::kT, dir, {w, w, w}, dot(dir, side) < 0, true);
    }
    return n;
}

double MixtureChain::share(const PatternRay& ray) const { return std::clamp(coefficient->value(ray).x, 0.0, 1.0); }

void SurfaceChains::apply(const PatternRay& ray, Bsdf& b) const {
    const bool front = dot(ray.direction, ray.normal) < 0;
    b.diffuse = front ? functions->front_diffuse : functions->back_diffuse;
    b.diffuse_transmit = functions->diffuse_transmit;
    b.specular = reflection->value(ray);
    b.specular_transmit = transmission->value(ray);
    b.glossy = false;
    b.mirror_like = max_component(b.specular) > 0;
    b.direct_response = max_component(b.diffuse) > 0 || max_component(b.diffuse_transmit) > 0;
    b.lambertian = !(max_component(b.diffuse_transmit) > 0);
}

const PatternChain* ScenePatterns::of(const Scene& scene, const std::string& material) const {
    for (size_t i = 0; i < scene.materials.size(); ++i)
        if (scene.materials[i].name == material) return of(static_cast<uint32_t>(i));
    return nullptr;
}

}  // namespace crex
