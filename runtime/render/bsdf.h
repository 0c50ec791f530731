/// \file bsdf.h
/// The shading model shared by the bin renderer and the recursive test oracle
/// (spec/crex.md §1): at a hit, which lobes spawn which component rays with which weight
/// (lobe splitting: one ray per lobe, no random lobe choice), what emission a ray sees, and
/// how the non-delta lobes respond to direct light.
///
/// Lobes, with c = colour, s = specularity, t = transmissivity, ts = transmitted specularity:
///   plastic, metal, trans  D  diffuse reflection      c(1-s)(1-t)           cosine sampled
///                          G  rough specular          ks = s (plastic) or c s (metal, trans: s)
///                             (normalised Phong lobe, exponent 2/r^2 - 2, sampled exactly)
///                          S  ideal specular          ks
///   trans                  D  diffuse transmission    c(1-s) t (1-ts)
///                          T  specular transmission   c(1-s) t ts            undeviated
///   glass, dielectric      R  Fresnel reflection      F;  T refraction (1-F) c; total internal
///                             reflection spawns R only, weight 1
///   mirror                 M  c
/// Emission: `light` only on camera rays and rays from delta lobes, `glow` on every ray within
/// its radius, both from the front side only; a material's `emission` on every ray, both sides.
#pragma once

#include <array>

#include "compiler/crex/components.h"
#include "runtime/scene/scene.h"

namespace crex {

/// The local geometry of a hit as shading sees it.
struct HitFrame {
    Vec3 position;   ///< local coordinates
    Vec3 geometric;  ///< unit geometric normal as the surface defines it (outward for spheres)
    Vec3 normal;     ///< unit normal on the side the ray came from
    Vec3 incoming;   ///< unit ray direction
    bool front = true;  ///< the ray hit the side `geometric` points to
    double distance = 0;
};

struct Lobe {
    Component component = Component::kD;
    Vec3 direction;
    Vec3 weight;
    bool transmits = false;  ///< leaves on the other side of the surface
    bool delta = false;
};

inline constexpr int kMaxLobes = 4;

/// Fills `out` with the lobes spawned at this hit; returns how many. Random numbers are drawn
/// for path `path` at `depth`.
int scatter(const Material& m, const HitFrame& f, uint64_t path, uint32_t depth, std::array<Lobe, kMaxLobes>& out);

/// Sum over the non-delta lobes of BRDF x |cos| for light arriving from unit direction `wi`.
Vec3 eval_direct(const Material& m, const HitFrame& f, const Vec3& wi);

/// The reflectance of the D reflection lobe (0 for materials without one).
Vec3 diffuse_albedo(const Material& m);

/// True if the material has a lobe that direct lighting can reach.
bool has_direct_response(const Material& m);

/// Emission seen by a ray. `camera_or_delta`: a camera ray or a ray from a delta lobe.
Vec3 emitted(const Material& m, const HitFrame& f, bool camera_or_delta, bool camera);

/// Dielectric Fresnel reflectance; `eta` = n_incident / n_transmitted. Returns 1 for total
/// internal reflection.
double fresnel_dielectric(double cos_i, double eta);

/// Phong exponent of a roughness in (0, 1].
double phong_exponent(double roughness);

}  // namespace crex
