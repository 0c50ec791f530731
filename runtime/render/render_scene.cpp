#include "runtime/render/render_scene.h"

#include "runtime/render/hot_surfaces.h"
#include "runtime/render/light_visibility.h"
#include "runtime/render/surface.h"

#include <algorithm>
#include <cmath>

#include "runtime/base/sampling.h"
#include "runtime/scene/material.h"
#include "runtime/scene/sky_model.h"
#include "runtime/texture/surface_textures.h"

namespace crex {
namespace {

// A sky's brightness table: cells of equal solid angle, fine enough for the circumsolar peak
// of a clear sky (a few degrees wide) to get its share of the samples.
constexpr int kSkyCellsZ = 64, kSkyCellsPhi = 128;

}  // namespace

// ---- distant sources ----------------------------------------------------------------------

DistantEmitters::DistantEmitters(const Scene& scene, double scene_radius, const ScenePatterns* patterns) {
    scene_area_ = kPi * (scene_radius > 0 ? scene_radius * scene_radius : 1.0);  // relative: no floor in units
    for (const DistantLight& l : scene.distant_lights) {
        const Material* m = scene.find_material(l.material);
        if (!m || !(max_component(m->color) > 0)) continue;
        // A glow source with a negative radius never lights the scene: camera and specular
        // rays see it (escaped()), direct lighting does not sample it.
        Source s;
        s.axis = normalize_or_zero(l.direction);
        orthonormal_basis(s.axis, s.t, s.b);
        s.cos_max = std::cos(std::clamp(l.angle_deg, 0.0, 360.0) * kPi / 360.0);
        s.color = m->color;
        s.sky = l.sky;
        s.pattern = patterns ? patterns->of(scene, l.material) : nullptr;
        const double solid_angle = 2 * kPi * (1 - s.cos_max);
        double mean = 1;  // mean brightness of the pattern over the cone
        if (s.sky || s.pattern) {
            s.cells_z = kSkyCellsZ, s.cells_phi = kSkyCellsPhi;
            s.cdf.reserve(static_cast<size_t>(s.cells_z * s.cells_phi));
            double acc = 0;
            for (int i = 0; i < s.cells_z; ++i)
                for (int j = 0; j < s.cells_phi; ++j) {
                    const double z = s.cos_max + (1 - s.cos_max) * (i + 0.5) / s.cells_z;
                    const double r = std::sqrt(std::fmax(0.0, 1 - z * z)), phi = 2 * kPi * (j + 0.5) / s.cells_phi;
                    const Vec3 d = s.axis * z + s.t * (r * std::cos(phi)) + s.b * (r * std::sin(phi));
                    acc += brightness_of(s, d);
                    s.cdf.push_back(acc);
                }
            mean = acc / static_cast<double>(s.cdf.size());
            if (acc > 0)
                for (double& c : s.cdf) c /= acc;
            else
                s.cdf.clear();  // a black sky: sample the cone uniformly
        }
        s.weight = std::fmax(luminance(s.color) * mean, 1e-12) * solid_angle;
        if (m->type == MaterialType::kGlow && m->glow_radius < 0) s.weight = 0;
        s.weak = m->type == MaterialType::kGlow;
        sources_.push_back(std::move(s));
    }
}

Vec3 DistantEmitters::pattern_of(const Source& s, const Vec3& d) {
    Vec3 f{1, 1, 1};
    if (s.sky) f = f * std::fmax(sky_brightness(*s.sky, d), 0.0);
    if (s.pattern) {
        PatternRay r;
        r.direction = d;
        r.normal = -d;
        r.distance = INFINITY;
        r.distant = true;
        f = f * s.pattern->value(r);
    }
    return f;
}

double DistantEmitters::brightness_of(const Source& s, const Vec3& d) { return luminance(pattern_of(s, d)); }

Vec3 DistantEmitters::radiance_of(const Source& s, const Vec3& d) const {
    return s.sky || s.pattern ? s.color * pattern_of(s, d) : s.color;
}

void DistantEmitters::sample(size_t i, double u, double v, Vec3& direction, Vec3& radiance, double& pdf) const {
    const Source& s = sources_[i];
    const double band = 1 - s.cos_max;  // solid angle / 2 pi
    double z, turn, cell_pdf = 1;       // cell_pdf: the chosen cell's probability x number of cells
    if (!s.cdf.empty()) {
        // A cell by brightness, then uniformly within it: u picks, its remainder places.
        const size_t n = s.cdf.size();
        size_t k = std::min(static_cast<size_t>(std::lower_bound(s.cdf.begin(), s.cdf.end(), u) - s.cdf.begin()), n - 1);
        const double lo = k == 0 ? 0.0 : s.cdf[k - 1], width = s.cdf[k] - lo;
        const double w = width > 0 ? std::clamp((u - lo) / width, 0.0, 1.0) : 0.5;
        cell_pdf = width * static_cast<double>(n);
        const int iz = static_cast<int>(k) / s.cells_phi, ip = static_cast<int>(k) % s.cells_phi;
        z = s.cos_max + band * (iz + w) / s.cells_z;
        turn = (ip + v) / s.cells_phi;
    } else {
        z = s.cos_max + band * u;
        turn = v;
    }
    z = std::min(z, 1.0);
    const double r = std::sqrt(std::fmax(0.0, 1 - z * z));
    double cos_p, sin_p;
    sincos_2pi(turn, cos_p, sin_p);
    direction = s.axis * z + s.t * (r * cos_p) + s.b * (r * sin_p);
    radiance = radiance_of(s, direction);
    pdf = band > 0 ? cell_pdf / (2 * kPi * band) : 0;
}

double DistantEmitters::cone_pdf(const Source& s, const Vec3& d) {
    const double z = dot(d, s.axis), band = 1 - s.cos_max;
    if (z < s.cos_max || !(band > 0)) return 0;
    if (s.cdf.empty()) return 1 / (2 * kPi * band);
    // The cell sample() places d in: its probability x number of cells, per solid angle.
    const int iz = std::clamp(static_cast<int>((z - s.cos_max) / band * s.cells_z), 0, s.cells_z - 1);
    double turn = std::atan2(dot(d, s.b), dot(d, s.t)) / (2 * kPi);
    if (turn < 0) turn += 1;
    const int ip = std::clamp(static_cast<int>(turn * s.cells_phi), 0, s.cells_phi - 1);
    const size_t k = static_cast<size_t>(iz * s.cells_phi + ip);
    const double probability = s.cdf[k] - (k == 0 ? 0.0 : s.cdf[k - 1]);
    return probability * static_cast<double>(s.cdf.size()) / (2 * kPi * band);
}

void DistantEmitters::sample_above(size_t i, const Vec3& n, double u, double v, Vec3& direction, Vec3& radiance, double& pdf) const {
    const Source& s = sources_[i];
    const double share = s.cdf.empty() ? 1.0 : 0.3;  // of the cosine technique
    if (u < share) {
        direction = sample_cosine(n, u / share, v);
        radiance = dot(direction, s.axis) >= s.cos_max ? radiance_of(s, direction) : Vec3{};
    } else {
        double cone_only;
        sample(i, std::min((u - share) / (1 - share), 1.0), v, direction, radiance, cone_only);
    }
    pdf = share * std::fmax(dot(direction, n), 0.0) * kInvPi + (1 - share) * cone_pdf(s, direction);
}

Vec3 DistantEmitters::escaped(const Vec3& d) const {
    Vec3 sum;
    for (const Source& s : sources_)
        if (dot(d, s.axis) >= s.cos_max) sum += radiance_of(s, d);
    return sum;
}

// ---- the light sampler ---------------------------------------------------------------------

Vec3 TexturedEmission::at(uint32_t prim, double b1, double b2, const Vec3& position) const {
    SurfacePoint p;
    p.position = position + origin_offset;
    p.indirect = p.coarse = true;
    if (!geometry->uvs.empty()) interpolate_uv(*geometry, geometry->indices[prim], b1, b2, p.u, p.v);
    return textures->emission(material, p);
}

LightSampler::LightSampler(const Scene& scene, const EmbreeScene& embree, const ScenePatterns* patterns, const SurfaceTextures* textures)
    : distant_(scene, 0.5 * length(embree.bounds_max() - embree.bounds_min()), patterns) {
    emission_sampled_.assign(embree.geometries().size(), 0);
    auto limits_of = [&](const GeometryInfo& g) -> const EmitterLimits* {
        const Material& m = scene.materials[g.emitter];
        EmitterLimits l;
        if (patterns) l.pattern = patterns->of(g.emitter);
        if (m.spot) {
            l.spot_cos = std::cos(std::clamp(m.spot->angle_deg, 0.0, 360.0) * kPi / 360.0);
            l.spot_axis = normalize_or_zero(m.spot->direction);
            l.focal = length(m.spot->direction);
        }
        if (m.type == MaterialType::kGlow) l.max_distance = m.glow_radius;
        if (!l.limited()) return nullptr;
        limits_.push_back(std::make_unique<EmitterLimits>(l));
        return limits_.back().get();
    };
    // Triangle t of mesh g as an emitter (its radiance, limits and flags left to the caller).
    auto triangle_entry = [](const GeometryInfo& g, const std::array<uint32_t, 3>& t) {
        Entry e;
        e.a = e.d = g.positions[t[0]];
        e.b = g.positions[t[1]];
        e.c = g.positions[t[2]];
        e.area = 0.5 * length(cross(e.b - e.a, e.c - e.a));
        e.normal = normalize_or_zero(cross(e.b - e.a, e.c - e.a));
        e.centre = (e.a + e.b + e.c) / 3.0;
        e.reach = std::fmax(length(e.a - e.centre), std::fmax(length(e.b - e.centre), length(e.c - e.centre)));
        return e;
    };
    // A mesh whose emission is an image: its triangles, each weighed by the emission read at
    // four of its points (a weight only steers the choice; the sample's own radiance is read
    // where it falls), at least a twentieth of the brightest's so that no lit texel is left
    // out. Left unsampled when no point read has any light (its rays still see it).
    auto add_textured = [&](const GeometryInfo& g) {
        auto emission = std::make_unique<TexturedEmission>(TexturedEmission{textures, &g, g.material, embree.origin_offset()});
        auto limits = std::make_unique<EmitterLimits>();
        limits->emission = emission.get();
        std::vector<Entry> added;
        double brightest = 0;
        for (uint32_t prim = 0; prim < g.indices.size(); ++prim) {
            Entry e = triangle_entry(g, g.indices[prim]);
            if (!(e.area > 0)) continue;
            e.limits = limits.get();
            e.prim = prim;
            constexpr double kProbes[4][2] = {{1.0 / 3, 1.0 / 3}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}, {1.0 / 6, 1.0 / 6}};
            for (const auto& b : kProbes) {
                const Vec3 p = e.a * (1 - b[0] - b[1]) + e.b * b[0] + e.c * b[1];
                e.radiance += emission->at(prim, b[0], b[1], p) * 0.25;
            }
            if (!is_finite(e.radiance)) e.radiance = {};
            brightest = std::fmax(brightest, luminance(e.radiance));
            added.push_back(e);
        }
        if (!(brightest > 0)) return;
        for (Entry& e : added) {
            if (luminance(e.radiance) < 0.05 * brightest) e.radiance = Vec3{1, 1, 1} * (0.05 * brightest);
            entries_.push_back(e);
        }
        emission_sampled_[static_cast<size_t>(&g - embree.geometries().data())] = 1;
        textured_.push_back(std::move(emission));
        limits_.push_back(std::move(limits));
    };
    auto add_geometry = [&](const GeometryInfo& g) {
        const Material& m = scene.materials[g.emitter];
        if (textures && !g.sphere && g.emitter == g.material && samples_textured_emission(m)) return add_textured(g);
        if (!is_sampled_emitter(m) || max_component(m.color) <= 0) return;
        const EmitterLimits* limits = limits_of(g);
        const bool weak = m.type == MaterialType::kGlow || m.type == MaterialType::kIllum;
        if (g.sphere) {
            Entry e;
            e.weak = weak;
            e.sphere = true;
            e.a = e.centre = g.center;
            e.b = {g.radius, 0, 0};
            e.radiance = m.color;
            e.area = 4 * kPi * g.radius * g.radius;
            e.reach = g.radius;
            e.limits = limits;
            if (limits && limits->pattern) e.pattern_mean = limits->pattern->mean_over_hemisphere({0, 0, 1}, e.centre);
            entries_.push_back(e);
            return;
        }
        const size_t first = entries_.size();
        for (const auto& t : g.indices) {
            Entry e = triangle_entry(g, t);
            e.weak = weak;
            e.radiance = m.color;
            e.limits = limits;
            if (limits && limits->pattern) e.pattern_mean = limits->pattern->mean_over_hemisphere(e.normal, e.centre);
            if (e.area > 0) entries_.push_back(e);
        }
        // A quad is two consecutive triangles of its mesh (RADIANCE's and OBJ's polygons,
        // glTF's exporters): each such pair becomes one parallelogram.
        size_t kept = first;
        for (size_t i = first; i < entries_.size(); ++i) {
            Entry joined;
            if (i + 1 < entries_.size() && join_parallelogram(entries_[i], entries_[i + 1], joined)) {
                if (limits && limits->pattern) joined.pattern_mean = limits->pattern->mean_over_hemisphere(joined.normal, joined.centre);
                entries_[kept++] = joined;
                ++i;
            } else {
                entries_[kept++] = entries_[i];
            }
        }
        entries_.resize(kept);
    };
    for (const auto& g : embree.geometries()) add_geometry(g);
    for (const auto& g : embree.hidden_emitters()) add_geometry(g);
    for (size_t i = 0; i < distant_.size(); ++i) {
        if (!(distant_.weight(i) > 0)) continue;
        Entry e;
        e.distant = static_cast<int>(i);
        e.area = 1;  // choices are per source; at() turns them into per-steradian pdfs
        e.distant_weight = distant_.weight(i);
        entries_.push_back(e);
    }
    for (auto& e : entries_)
        e.power = e.distant >= 0 ? distant_.power(static_cast<size_t>(e.distant)) : e.area * std::fmax(luminance(e.radiance) * e.pattern_mean, 1e-12);
    make_cdf();
    size_t distant_count = 0;
    for (const Entry& e : entries_) distant_count += e.distant >= 0;
    // A few emitters: weighed two at a time where all are flat with no limit to their reach.
    if (entries_.size() <= kLocalChoiceMax) {
        triangles_ = flat_weights(entries_);
        one_flat_ = triangles_.size() == 1;
        return;
    }
    // Too many emitters to weigh each at every hit: the local ones go in a tree, and the distant
    // ones (a sun and a sky, rarely more) are weighed one by one beside it.
    if (distant_count > kLocalChoiceMax) return;
    std::vector<LightBound> bounds;
    for (size_t i = 0; i < entries_.size(); ++i) {
        const Entry& e = entries_[i];
        if (e.distant >= 0) {
            distant_entries_.push_back(i);
            continue;
        }
        LightBound b;
        if (e.sphere) {
            const Vec3 r{e.b.x, e.b.x, e.b.x};
            b.lo = e.centre - r, b.hi = e.centre + r;
            b.axis = {0, 0, 1}, b.cos_spread = -1;
        } else {
            b.lo = vmin(vmin(e.a, e.d), vmin(e.b, e.c)), b.hi = vmax(vmax(e.a, e.d), vmax(e.b, e.c));
            b.axis = e.normal, b.cos_spread = 1;
        }
        b.power = e.power;
        bounds.push_back(b);
        tree_entries_.push_back(i);
    }
    tree_ = LightTree(bounds);
    tree_slots_.reserve(tree_.slots());
    for (uint32_t slot = 0; slot < tree_.slots(); ++slot) tree_slots_.push_back(entries_[tree_entries_[tree_.emitter_at(slot)]]);
}

TriangleWeights LightSampler::flat_weights(const std::vector<Entry>& entries) {
    std::vector<WeighedTriangle> triangles;
    for (const Entry& e : entries) {
        if (e.sphere || e.distant >= 0 || (e.limits && std::isfinite(e.limits->max_distance))) return {};
        triangles.push_back({e.a, e.b, e.c, e.d, e.normal, e.centre, e.power, e.area, e.reach});
    }
    return TriangleWeights(triangles);
}

bool LightSampler::join_parallelogram(const Entry& t0, const Entry& t1, Entry& joined) {
    if (t0.sphere || t1.sphere || t0.distant >= 0 || t1.distant >= 0 || t0.weak != t1.weak || t0.limits != t1.limits ||
        (t0.limits && t0.limits->emission) ||
        !(t0.radiance == t1.radiance) || !(dot(t0.normal, t1.normal) >= 1 - 1e-12))
        return false;
    // The corners t0 shares with t1 (exactly: a quad's triangles share its vertices).
    const Vec3 c0[3] = {t0.a, t0.b, t0.c}, c1[3] = {t1.a, t1.b, t1.c};
    int shared0[2], shared1[2], count = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (c0[i] == c1[j] && count < 2) shared0[count] = i, shared1[count] = j, ++count;
    if (count != 2) return false;
    const Vec3 own0 = c0[3 - shared0[0] - shared0[1]], own1 = c1[3 - shared1[0] - shared1[1]];
    const Vec3 s = c0[shared0[0]], t = c0[shared0[1]];
    // A parallelogram's diagonals halve each other: own0 + own1 = s + t, to rounding of its size.
    const double size = std::fmax(t0.reach, t1.reach);
    if (!(length(own0 + own1 - (s + t)) <= 1e-9 * size)) return false;
    joined = t0;
    joined.parallelogram = true;
    joined.a = own0, joined.b = s, joined.c = t, joined.d = own1;
    joined.area = length(cross(s - own0, t - own0));
    joined.centre = (s + t) * 0.5;
    joined.reach = 0;
    for (const Vec3& p : {joined.a, joined.b, joined.c, joined.d}) joined.reach = std::fmax(joined.reach, length(p - joined.centre));
    return joined.area > 0;
}

void LightSampler::make_cdf() {
    double total = 0;
    for (const auto& e : entries_) total += e.power;
    cdf_.clear();
    double acc = 0;
    for (auto& e : entries_) {
        double p = e.power / total;
        e.pdf_area = p / e.area;
        acc += p;
        cdf_.push_back(acc);
    }
    if (!cdf_.empty()) cdf_.back() = 1.0;
}

void LightSampler::weigh_distant(const std::vector<double>& fraction) {
    for (auto& e : entries_) {
        if (e.distant < 0) continue;
        const size_t i = static_cast<size_t>(e.distant);
        const double f = i < fraction.size() && fraction[i] > 0 && fraction[i] <= 1 ? fraction[i] : 1.0;
        e.distant_weight = distant_.weight(i) * f;
        e.power = distant_.power(i) * f;
    }
    make_cdf();
}

void LightSampler::sample_sphere(const Entry& e, double u, double v, LightSample& s) {
    double z = 1 - 2 * u, r = std::sqrt(std::fmax(0.0, 1 - z * z)), cos_p, sin_p;
    sincos_2pi(v, cos_p, sin_p);  // libm's sincos for every shadow ray to a lamp was 1 % of a walk
    s.normal = {r * cos_p, r * sin_p, z};
    s.position = e.a + s.normal * e.b.x;
}

bool LightSampler::sample_sphere_seen(const Entry& e, const Vec3& x, double u, double v, LightSample& s) {
    const double radius = e.b.x;
    const Vec3 to_centre = e.a - x;
    const double d2c = dot(to_centre, to_centre);
    // Within 0.1 % of the radius of the surface (or inside), the cone is nearly the half space
    // and its point ill-conditioned: area sampling serves as well there.
    if (!(d2c > radius * radius * 1.002) || !std::isfinite(d2c)) return false;
    const double dc = std::sqrt(d2c);
    const Vec3 axis = to_centre / dc;
    // 1 - cos of the cone's half angle, without cancellation for a small, far sphere.
    const double sin2_max = radius * radius / d2c, cos_max = std::sqrt(std::fmax(0.0, 1 - sin2_max));
    const double one_minus_cos_max = sin2_max / (1 + cos_max);
    const double cos_t = 1 - u * one_minus_cos_max, sin2_t = std::fmax(0.0, (1 - cos_t) * (1 + cos_t));
    const Vec3 dir = direction_around(axis, cos_t, v);
    // The near crossing of the ray x + dir t with the sphere.
    const double dist = dc * cos_t - std::sqrt(std::fmax(0.0, radius * radius - d2c * sin2_t));
    if (!(dist > 0)) return false;
    const Vec3 normal = normalize_or_zero(x + dir * dist - e.a);
    const double cos_l = -dot(normal, dir);
    if (!(cos_l > 0)) return false;
    // Uniform in the cone: 1 / (2 pi (1 - cos_max)) per steradian, cos_l / dist^2 steradians
    // per unit area at the point; times the probability of choosing this emitter, which
    // s.pdf_area holds now as that per unit area of the whole sphere.
    const double pdf = s.pdf_area * e.area * cos_l / (2 * kPi * one_minus_cos_max * dist * dist);
    if (!(pdf > 0) || !std::isfinite(pdf)) return false;
    s.normal = normal;
    s.position = e.a + normal * radius;
    s.pdf_area = pdf;
    return true;
}

LightSample LightSampler::along(const LocalWeights& weights, const Vec3& dir) const {
    if (!finds_along(weights) || !std::isfinite(weights.total)) return {};
    const Vec3& x = weights.point;
    // The nearest crossing with any local emitter, chosen or not: one that light sampling never
    // chooses there still hides those behind it.
    double best = INFINITY, b1 = 0, b2 = 0;
    size_t hit = entries_.size();
    for (size_t i = 0; i < entries_.size(); ++i) {
        const Entry& e = entries_[i];
        if (e.distant >= 0) continue;
        if (e.sphere) {
            const Vec3 oc = x - e.a;
            const double half_b = dot(oc, dir), c = dot(oc, oc) - e.b.x * e.b.x, disc = half_b * half_b - c;
            if (!(disc >= 0)) continue;
            const double root = std::sqrt(disc);
            const double t = -half_b - root > 0 ? -half_b - root : -half_b + root;  // from inside: its inner side
            if (t > 0 && t < best) best = t, hit = i;
            continue;
        }
        // Moller-Trumbore over (a, b, c); a parallelogram takes both coordinates in [0, 1].
        const Vec3 e1 = e.b - e.a, e2 = e.c - e.a, p = cross(dir, e2);
        const double det = dot(e1, p);
        if (!(std::fabs(det) > 0)) continue;
        const double inv = 1 / det;
        const Vec3 s = x - e.a;
        const double u = dot(s, p) * inv;
        if (!(u >= 0 && u <= 1)) continue;
        const Vec3 q = cross(s, e1);
        const double v = dot(dir, q) * inv;
        if (!(v >= 0 && (e.parallelogram ? v <= 1 : u + v <= 1))) continue;
        const double t = dot(e2, q) * inv;
        if (t > 0 && t < best) best = t, hit = i, b1 = u, b2 = v;
    }
    if (hit == entries_.size()) return {};
    const Entry& e = entries_[hit];
    const double chosen = weights.w[hit] / weights.total;  // choose()'s probability of this entry
    if (!(chosen > 0)) return {};
    LightSample s;
    s.radiance = e.radiance;
    s.weak = e.weak;
    s.limits = e.limits;
    s.position = x + dir * best;
    if (e.sphere) {
        s.sphere = true;
        s.normal = normalize_or_zero(s.position - e.a);
        s.position = e.a + s.normal * e.b.x;
        // As sample_sphere_seen() gives the point when x is outside, else as sample_sphere().
        const Vec3 to_centre = e.a - x;
        const double d2c = dot(to_centre, to_centre), radius = e.b.x;
        const Vec3 to = s.position - x;
        const double dist2 = dot(to, to), cos_l = -dot(s.normal, dir);
        if (!(cos_l > 0)) return {};
        if (d2c > radius * radius * 1.002 && std::isfinite(d2c)) {
            const double sin2_max = radius * radius / d2c, one_minus_cos_max = sin2_max / (1 + std::sqrt(std::fmax(0.0, 1 - sin2_max)));
            s.pdf_area = chosen * cos_l / (2 * kPi * one_minus_cos_max * dist2);
        } else {
            s.pdf_area = chosen / e.area;
        }
    } else {
        s.normal = e.normal;
        if (!(-dot(e.normal, dir) > 0)) return {};  // its back: emitters light from their front only
        s.pdf_area = chosen / e.area;
        s.prim = e.prim;
        s.b1 = b1, s.b2 = b2;
    }
    if (!(s.pdf_area > 0) || !std::isfinite(s.pdf_area)) return {};
    return s;
}

// ---- the camera ----------------------------------------------------------------------------

namespace {

// Half of a field of view in the measure each projection spaces the image by, so that
// square pixels mean equal ratios (RADIANCE's view aspect).
double half_extent(Projection p, double fov_deg, bool horizontal) {
    const double a = fov_deg * kPi / 180;
    switch (p) {
    case Projection::kPerspective: return std::tan(a / 2);
    case Projection::kParallel: return fov_deg / 2;  // scene units
    case Projection::kAngular: return a / 2;
    case Projection::kHemispherical: return std::sin(std::fmin(a, kPi) / 2);
    case Projection::kStereographic: return std::tan(a / 4);
    case Projection::kCylindrical: return horizontal ? a / 2 : std::tan(a / 2);
    }
    return 1;
}

}  // namespace

CameraRays::CameraRays(const Camera& c, int width, int height, const Vec3& origin_offset)
    : projection_(c.projection), fore_clip_(c.fore_clip), width_(width), height_(height) {
    origin_ = c.position - origin_offset;
    forward_ = normalize_or_zero(c.direction);
    right_ = normalize_or_zero(cross(forward_, c.up));
    up_ = cross(right_, forward_);
    ext_y_ = half_extent(projection_, c.vfov_deg, false);
    const double aspect = static_cast<double>(width) / std::max(height, 1);
    ext_x_ = ext_y_ * aspect;
    if (c.hfov_deg > 0) {
        // Both fields of view given: pixels stay square, as rpict keeps them, by narrowing the
        // one the image's aspect cannot hold (a 128x64 render of a 40x40 degree view shows 40
        // degrees across and 20.6 down, instead of squashing spheres into ellipses).
        double ex = half_extent(projection_, c.hfov_deg, true);
        if (ex / ext_y_ > aspect) ext_x_ = ext_y_ * aspect;
        else ext_x_ = ex, ext_y_ = ex / aspect;
    }
}

void RenderScene::set_view(int width, int height, double filter_width) {
    // The footprint is a pinhole's; other projections (fisheyes, parallel views) look textures
    // up at their sharpest rather than with a wrong filter.
    const Camera& c = scene.camera;
    footprint = filter_width > 0 && c.projection == Projection::kPerspective
                    ? PixelFootprint(c, width, height, c.position - embree->origin_offset(), filter_width)
                    : PixelFootprint{};
    // Distant sources get shadow rays by how much of them the surfaces in view can see.
    if (lights->distant().size() > 0) lights->weigh_distant(distant_visibility(*this, width, height));
}

bool CameraRays::generate(double px, double py, Vec3& origin, Vec3& direction) const {
    const double a = (2 * px / width_ - 1) * ext_x_;
    const double b = (1 - 2 * py / height_) * ext_y_;
    origin = origin_;
    switch (projection_) {
    case Projection::kPerspective: {
        const Vec3 d = forward_ + right_ * a + up_ * b;
        origin = origin_ + d * fore_clip_;  // the clipping plane is square to the view
        direction = normalize_or_zero(d);
        return true;
    }
    case Projection::kParallel:
        origin = origin_ + right_ * a + up_ * b + forward_ * fore_clip_;
        direction = forward_;
        return true;
    case Projection::kAngular: {  // distance from the centre is the angle from the view direction
        const double theta = std::sqrt(a * a + b * b);
        if (theta > kPi) break;
        const double s = theta > 1e-12 ? std::sin(theta) / theta : 1.0;
        direction = forward_ * std::cos(theta) + right_ * (a * s) + up_ * (b * s);
        origin = origin_ + direction * fore_clip_;
        return true;
    }
    case Projection::kHemispherical: {  // distance is the angle's sine
        const double z2 = 1 - a * a - b * b;
        if (z2 < 0) break;
        direction = normalize_or_zero(forward_ * std::sqrt(z2) + right_ * a + up_ * b);
        origin = origin_ + direction * fore_clip_;
        return true;
    }
    case Projection::kStereographic: {  // distance is the tangent of half the angle
        const double d = a * a + b * b, z = (1 - d) / (1 + d);
        direction = normalize_or_zero(forward_ * z + right_ * (a * (1 + z)) + up_ * (b * (1 + z)));
        origin = origin_ + direction * fore_clip_;
        return true;
    }
    case Projection::kCylindrical: {  // angle across, perspective up and down
        const Vec3 d = forward_ * std::cos(a) + right_ * std::sin(a) + up_ * b;
        origin = origin_ + d * fore_clip_;
        direction = normalize_or_zero(d);
        return true;
    }
    }
    direction = forward_;
    return false;
}

bool CameraRays::world_to_camera(std::array<double, 16>& m) const {
    if (forward_ == Vec3{} || right_ == Vec3{}) return false;
    m = {};
    const Vec3 axes[3] = {right_, up_, forward_};
    for (int j = 0; j < 3; ++j) {  // column j: the point's coordinate along axis j
        m[0 * 4 + j] = axes[j].x, m[1 * 4 + j] = axes[j].y, m[2 * 4 + j] = axes[j].z;
        m[3 * 4 + j] = -dot(axes[j], origin_);
    }
    m[15] = 1;
    return true;
}

bool CameraRays::world_to_ndc(std::array<double, 16>& m) const {
    std::array<double, 16> view;
    if (!world_to_camera(view) || !(ext_x_ > 0) || !(ext_y_ > 0)) return false;
    // Camera space to NDC, as generate() maps a pixel to a ray: x/z = (2 px/width - 1) ext_x
    // and y/z = (1 - 2 py/height) ext_y (the parallel view: without the division by z).
    std::array<double, 16> ndc{};
    const double sx = 1 / (2 * ext_x_), sy = -1 / (2 * ext_y_);
    switch (projection_) {
    case Projection::kPerspective:
        ndc[0 * 4 + 0] = sx, ndc[2 * 4 + 0] = 0.5;  // x' = x/(2 ext_x) + z/2
        ndc[1 * 4 + 1] = sy, ndc[2 * 4 + 1] = 0.5;  // y' = -y/(2 ext_y) + z/2
        ndc[3 * 4 + 2] = 1;                          // z' = 1: z'/w is the inverse depth
        ndc[2 * 4 + 3] = 1;                          // w = z
        break;
    case Projection::kParallel:
        ndc[0 * 4 + 0] = sx, ndc[3 * 4 + 0] = 0.5;
        ndc[1 * 4 + 1] = sy, ndc[3 * 4 + 1] = 0.5;
        ndc[2 * 4 + 2] = 1, ndc[3 * 4 + 3] = 1;
        break;
    default: return false;
    }
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double sum = 0;
            for (int k = 0; k < 4; ++k) sum += view[i * 4 + k] * ndc[k * 4 + j];
            m[i * 4 + j] = sum;
        }
    return true;
}

RenderScene::RenderScene(const Scene& s, size_t texture_cache_bytes, TextureProgress progress) : scene(s) {
    bool any_texture = false, any_cutout = false, any_pattern = false, any_clip = false;
    for (const Material& m : s.materials)
        any_texture = any_texture || m.textures.any(), any_cutout = any_cutout || m.opacity < 1, any_clip = any_clip || !m.clips.empty();
    if (any_texture || any_cutout) textures = std::make_unique<SurfaceTextures>(s, texture_cache_bytes, warnings, TiledCopies::kMake, std::move(progress));
    if (any_texture || any_cutout || any_clip) {
        cutouts = std::make_unique<SceneCutouts>(s, textures.get());
        if (!cutouts->any()) cutouts.reset();
    }
    embree = std::make_unique<EmbreeScene>(s, cutouts.get());
    if (cutouts) cutouts->attach(*embree);
    for (const Material& m : s.materials) any_pattern = any_pattern || !m.patterns.empty() || m.surface_functions || m.mixture || m.directional || !m.redirections.empty();
    if (any_pattern) patterns = std::make_unique<ScenePatterns>(s, embree->origin_offset(), warnings);
    lights = std::make_unique<LightSampler>(s, *embree, patterns.get(), textures.get());
    for (const Material& m : s.materials) bsdfs.push_back(Bsdf::of(m));
    if (patterns)
        for (uint32_t i = 0; i < bsdfs.size(); ++i) {
            bsdfs[i].patterns = patterns->of(i);
            bsdfs[i].directional = patterns->directional(i);
            bsdfs[i].redirect = patterns->redirect(i);
            // A BRTDfunc's lobes as a ray along its normal sees them: what the paths that do
            // not shade it (a cache ray passing through) weigh it by.
            if (const SurfaceChains* sc = patterns->surface(i)) {
                PatternRay r;
                r.direction = {0, 0, -1};
                r.normal = {0, 0, 1};
                sc->apply(r, bsdfs[i]);
            }
        }
    medium = medium_of(s, embree->origin_offset());
    hot = std::make_unique<HotSurfaces>(*this);
}

RenderScene::~RenderScene() = default;

}  // namespace crex
