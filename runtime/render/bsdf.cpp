#include "runtime/render/bsdf.h"

#include <cmath>

#include "runtime/base/sampling.h"

namespace crex {
namespace {

struct Split {
    Vec3 diffuse;           // D reflection
    Vec3 specular;          // G or S reflection
    Vec3 diffuse_transmit;  // D transmission
    Vec3 specular_transmit; // T
};

Split split_of(const Material& m) {
    Split s;
    double spec = m.specularity;
    double trans = m.type == MaterialType::kTrans ? m.transmissivity : 0.0;
    s.diffuse = m.color * ((1 - spec) * (1 - trans));
    s.specular = m.type == MaterialType::kMetal ? m.color * spec : Vec3{spec, spec, spec};
    if (m.type == MaterialType::kTrans) {
        s.diffuse_transmit = m.color * ((1 - spec) * trans * (1 - m.transmitted_specular));
        s.specular_transmit = m.color * ((1 - spec) * trans * m.transmitted_specular);
    }
    return s;
}

bool positive(const Vec3& v) { return max_component(v) > 0; }

}  // namespace

Vec3 diffuse_albedo(const Material& m) {
    switch (m.type) {
    case MaterialType::kPlastic:
    case MaterialType::kMetal:
    case MaterialType::kTrans: return split_of(m).diffuse;
    default: return {};
    }
}

double phong_exponent(double roughness) {
    double r = std::fmax(roughness, 1e-4);  // r -> 0 is S, handled apart; keep the exponent finite
    return std::fmax(2.0 / (r * r) - 2.0, 0.0);
}

double fresnel_dielectric(double cos_i, double eta) {
    cos_i = std::fmin(std::fmax(cos_i, 0.0), 1.0);
    double sin_t2 = eta * eta * (1 - cos_i * cos_i);
    if (sin_t2 >= 1) return 1;
    double cos_t = std::sqrt(1 - sin_t2);
    double rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    double rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

bool has_direct_response(const Material& m) {
    switch (m.type) {
    case MaterialType::kPlastic:
    case MaterialType::kMetal:
    case MaterialType::kTrans: {
        Split s = split_of(m);
        return positive(s.diffuse) || positive(s.diffuse_transmit) || (m.roughness > 0 && positive(s.specular));
    }
    default: return false;
    }
}

int scatter(const Material& m, const HitFrame& f, uint64_t path, uint32_t depth, std::array<Lobe, kMaxLobes>& out) {
    int n = 0;
    const Vec3& nrm = f.normal;
    const Vec3& d = f.incoming;
    switch (m.type) {
    case MaterialType::kPlastic:
    case MaterialType::kMetal:
    case MaterialType::kTrans: {
        Split s = split_of(m);
        if (positive(s.diffuse)) {
            Vec3 dir = sample_cosine(nrm, random_at(path, depth, RandomUse::kLobeD, 0), random_at(path, depth, RandomUse::kLobeD, 1));
            out[n++] = {Component::kD, dir, s.diffuse, false, false};
        }
        if (m.specularity > 0 && positive(s.specular)) {
            Vec3 mirror = reflect(d, nrm);
            if (m.roughness > 0) {
                double e = phong_exponent(m.roughness);
                Vec3 dir = sample_phong(mirror, e, random_at(path, depth, RandomUse::kLobeG, 0), random_at(path, depth, RandomUse::kLobeG, 1));
                double c = dot(dir, nrm);
                if (c > 0) out[n++] = {Component::kG, dir, s.specular * ((e + 2) / (e + 1) * c), false, false};
            } else {
                out[n++] = {Component::kS, mirror, s.specular, false, true};
            }
        }
        if (positive(s.diffuse_transmit)) {
            Vec3 dir = sample_cosine(-nrm, random_at(path, depth, RandomUse::kLobeDT, 0), random_at(path, depth, RandomUse::kLobeDT, 1));
            out[n++] = {Component::kD, dir, s.diffuse_transmit, true, false};
        }
        if (positive(s.specular_transmit)) out[n++] = {Component::kT, d, s.specular_transmit, true, true};
        break;
    }
    case MaterialType::kGlass:
    case MaterialType::kDielectric: {
        double eta = f.front ? 1.0 / m.ior : m.ior;
        double cos_i = -dot(d, nrm);
        double fr = fresnel_dielectric(cos_i, eta);
        Vec3 mirror = reflect(d, nrm);
        if (fr >= 1) {  // total internal reflection
            out[n++] = {Component::kR, mirror, {1, 1, 1}, false, true};
            break;
        }
        out[n++] = {Component::kR, mirror, {fr, fr, fr}, false, true};
        if (positive(m.color)) {
            double cos_t = std::sqrt(std::fmax(0.0, 1 - eta * eta * (1 - cos_i * cos_i)));
            Vec3 dir = normalize_or_zero(d * eta + nrm * (eta * cos_i - cos_t));
            if (dir != Vec3{}) out[n++] = {Component::kT, dir, m.color * (1 - fr), true, true};
        }
        break;
    }
    case MaterialType::kMirror:
        if (positive(m.color)) out[n++] = {Component::kM, reflect(d, nrm), m.color, false, true};
        break;
    case MaterialType::kVoid:
    case MaterialType::kLight:
    case MaterialType::kGlow: break;
    }
    return n;
}

Vec3 eval_direct(const Material& m, const HitFrame& f, const Vec3& wi) {
    if (m.type != MaterialType::kPlastic && m.type != MaterialType::kMetal && m.type != MaterialType::kTrans) return {};
    Split s = split_of(m);
    double c = dot(wi, f.normal);
    Vec3 out;
    if (c > 0) {
        out += s.diffuse * (c / kPi);
        if (m.specularity > 0 && m.roughness > 0) {
            double e = phong_exponent(m.roughness);
            double ca = dot(wi, reflect(f.incoming, f.normal));
            if (ca > 0) out += s.specular * ((e + 2) / (2 * kPi) * std::pow(ca, e) * c);
        }
    } else if (c < 0) {
        out += s.diffuse_transmit * (-c / kPi);
    }
    return out;
}

Vec3 emitted(const Material& m, const HitFrame& f, bool camera_or_delta, bool camera) {
    Vec3 e;
    if (m.type == MaterialType::kLight && f.front && camera_or_delta) e += m.color;
    if (m.type == MaterialType::kGlow && f.front && (camera || m.glow_radius <= 0 || f.distance <= m.glow_radius)) e += m.color;
    if (m.emission) e += *m.emission;
    return e;
}

}  // namespace crex
