#include "runtime/scene/radiance/library_files.h"

namespace crex::radiance {
namespace {

// Luminaire coordinates in degrees, for a ray arriving at the luminaire along (Dx, Dy, Dz):
// theta from the luminaire's -z axis (straight down is 0), phi from +x towards +y; the
// _phi2 and _phi4 forms fold phi for bilateral and quadrilateral symmetry. The corrections
// turn a table of intensities into radiance: flatcorr for a flat emitter (divide by the
// projected area's cosine), boxcorr and cylcorr for a box (A2 x A3 x A4) or cylinder
// (diameter A2, height A3) in metres; A1 multiplies when given.
constexpr const char* kSourceCal = R"cal(
src_theta = Acos(Dz) / DEGREE;
src_phi = mod(Atan2(-Dy, -Dx) / DEGREE, 360);
src_phi2 = tri(src_phi, 180);
src_phi4 = tri(src_phi, 90);
srcB_vert = atan2(-Dx, Dz) / DEGREE;
srcB_horiz = atan2(Dy, Dz) / DEGREE;
srcB_vert2 = abs(srcB_vert);
srcB_horiz2 = abs(srcB_horiz);
corr(v) = if(AC - .5, A1 * v, v);
flatcorr(v) = corr(v) / Rdot;
boxprojection = abs(Dx) * A3 * A4 + abs(Dy) * A2 * A4 + abs(Dz) * A2 * A3;
boxcorr(v) = A1 * v / boxprojection;
lboxprojection = (noneg(abs(Px - Dx * Ts) - A2 / 2) * A3 * A4 + noneg(abs(Py - Dy * Ts) - A3 / 2) * A2 * A4 +
                  noneg(abs(Pz - Dz * Ts) - A4 / 2) * A2 * A3) / Ts;
lboxcorr(v) = A1 * v / lboxprojection;
cylprojection = A2 * A3 * sqrt(1 - Dz * Dz) + PI / 4 * A2 * A2 * abs(Dz);
cylcorr(v) = A1 * v / cylprojection;
)cal";

// mkillum's coordinates: over the sphere, altitude Dz and azimuth from +x; over a
// hemisphere whose frame's unit vectors are A1-A3 (u), A4-A6 (v) and A7-A9 (the normal),
// the squared cosine to the normal and the azimuth in that frame, for the ray leaving
// the surface (-D).
constexpr const char* kIllumCal = R"cal(
norm_rad(r) : if(r, r, r + 2 * PI);
il_alt = Dz;
il_azi = norm_rad(Atan2(Dy, Dx));
il_alth = sq(-Dx * A7 - Dy * A8 - Dz * A9);
il_azih = norm_rad(Atan2(-Dx * A4 - Dy * A5 - Dz * A6, -Dx * A1 - Dy * A2 - Dz * A3));
)cal";

}  // namespace

std::optional<std::string> builtin_function_file(std::string_view name) {
    if (name == "source.cal") return std::string(kSourceCal);
    if (name == "illum.cal") return std::string(kIllumCal);
    return std::nullopt;
}

const std::string& local_frame_definitions() {
    // V is the up vector crossed with the normal (facing the ray), normalised; U completes
    // the right-handed frame U, V, N.
    static const std::string text = R"(
Vux`P. = arg(AC-1)*NzP - arg(AC)*NyP;
Vuy`P. = arg(AC)*NxP - arg(AC-2)*NzP;
Vuz`P. = arg(AC-2)*NyP - arg(AC-1)*NxP;
vnorm`P. = 1/sqrt(Vux`P.*Vux`P. + Vuy`P.*Vuy`P. + Vuz`P.*Vuz`P.);
Vnx`P. = Vux`P.*vnorm`P.;
Vny`P. = Vuy`P.*vnorm`P.;
Vnz`P. = Vuz`P.*vnorm`P.;
Unx`P. = NyP*Vnz`P. - NzP*Vny`P.;
Uny`P. = NzP*Vnx`P. - NxP*Vnz`P.;
Unz`P. = NxP*Vny`P. - NyP*Vnx`P.;
Ldx(dx,dy,dz) = dx*Unx`P. + dy*Uny`P. + dz*Unz`P.;
Ldy(dx,dy,dz) = dx*Vnx`P. + dy*Vny`P. + dz*Vnz`P.;
Ldz(dx,dy,dz) = dx*NxP + dy*NyP + dz*NzP;
Idx = Ldx(-Dx,-Dy,-Dz);
Idy = Ldy(-Dx,-Dy,-Dz);
Idz = RdotP;
)";
    return text;
}

}  // namespace crex::radiance
