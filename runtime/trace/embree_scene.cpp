#include "runtime/trace/embree_scene.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "runtime/scene/shapes.h"
#include "runtime/trace/trace_batch.h"

namespace crex {
namespace {

// Embree's own words for the last error on this thread; check() turns it into an exception.
thread_local std::string last_embree_error;

void on_embree_error(void*, RTCError code, const char* message) {
    last_embree_error = fmt::format("{} (error {})", message ? message : "no message", static_cast<int>(code));
}

void check(RTCDevice device, const char* what) {
    RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
        throw std::runtime_error(fmt::format("Embree failed to {}: {}", what,
                                             last_embree_error.empty() ? fmt::format("error {}", static_cast<int>(e)) : last_embree_error));
}

// Embree's filter for cut-out geometries: a hit the test calls a hole is not a hit, whichever
// query found it.
void cutout_filter(const RTCFilterFunctionNArguments* args) {
    const auto* test = static_cast<const GeometryFilter*>(args->geometryUserPtr)->cutouts;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const Vec3 origin{RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i), RTCRayN_org_z(args->ray, args->N, i)};
        const Vec3 dir{RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i)};
        if (!test->solid(RTCHitN_geomID(args->hit, args->N, i), RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
                         RTCHitN_v(args->hit, args->N, i), origin, dir, RTCRayN_tfar(args->ray, args->N, i)))
            args->valid[i] = 0;
    }
}

// Intersection queries only (RADIANCE's -bv-: shadow rays are still blocked by a back): a hit
// on the back of a surface that hides it is no hit, then holes as above.
void surface_filter(const RTCFilterFunctionNArguments* args) {
    const auto* filter = static_cast<const GeometryFilter*>(args->geometryUserPtr);
    if (filter->hide_back)
        for (unsigned i = 0; i < args->N; ++i) {
            if (args->valid[i] != -1) continue;
            const double facing = RTCRayN_dir_x(args->ray, args->N, i) * RTCHitN_Ng_x(args->hit, args->N, i) +
                                  RTCRayN_dir_y(args->ray, args->N, i) * RTCHitN_Ng_y(args->hit, args->N, i) +
                                  RTCRayN_dir_z(args->ray, args->N, i) * RTCHitN_Ng_z(args->hit, args->N, i);
            if (filter->inward ? facing < 0 : facing > 0) args->valid[i] = 0;
        }
    if (filter->cutouts) cutout_filter(args);
}

}  // namespace

namespace {

// Cut-out surfaces that may also let shadow rays through: holes first, then the pass.
void cutout_then_shadow_pass_filter(const RTCFilterFunctionNArguments* args) {
    cutout_filter(args);
    shadow_pass_filter(args);
}

// Materials whose light may go straight through (thin glass, trans): shadow rays may cross them
// (the renderer's ShadowPass decides at each hit).
bool passes_straight(const Material& m) {
    return (m.type == MaterialType::kGlass && m.thin_glass) || m.type == MaterialType::kTrans;
}

// RADIANCE's -bv- hides the backs of the materials whose code asks for it (normal.c, aniso.c,
// glass.c, m_mirror.c, m_brdf2, ashikhmin.c); it leaves dielectrics (a solid's inside is its
// back), emitters, BRTDfunc (m_brdf.c: its back has its own reflectance) and the prisms.
bool hides_back(const Material& m) {
    return m.type != MaterialType::kDielectric && m.type != MaterialType::kLight && m.type != MaterialType::kGlow &&
           m.type != MaterialType::kIllum && !m.surface_functions && m.redirections.empty();
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& scene, const CutoutTest* cutouts) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("Embree: cannot create a device (unsupported CPU?)");
    rtcSetDeviceErrorFunction(device_, on_embree_error, nullptr);
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);

    lo_ = {INFINITY, INFINITY, INFINITY};
    hi_ = {-INFINITY, -INFINITY, -INFINITY};
    for (const auto& s : scene.shapes) expand_bounds(s, lo_, hi_);
    if (!is_finite(lo_) || !is_finite(hi_)) lo_ = hi_ = Vec3{};
    offset_ = (lo_ + hi_) * 0.5;
    // Relative at every size the loaders accept (kMinSpan .. kMaxReach): a floor of 1e-6 made
    // the offset 1e-11 units in a scene 3.5e-11 across, longer than its shadow rays' margins.
    const double span = length(hi_ - lo_);
    extent_ = span > 0 && std::isfinite(span) ? span : 1.0;  // a point, or no shapes: any scale
    // A point at the local origin, reached along a ray of no length, has an error of its own all
    // the same (its neighbours' coordinates are rounded): 1e-9 of the extent.
    epsilon_floor_ = 1e-9 * extent_;

    for (uint32_t i = 0; i < scene.shapes.size(); ++i) {
        const Shape& s = scene.shapes[i];
        GeometryInfo info;
        info.shape = i;
        for (uint32_t m = 0; m < scene.materials.size(); ++m)
            if (scene.materials[m].name == s.material) info.material = m;
        info.emitter = info.material;
        if (!scene.materials[info.material].clips.empty()) continue;  // an antimatter's solid: never seen
        // An illum is sampled as itself and seen as its alternate material (or not at all).
        bool hidden = false;
        if (scene.materials[info.material].type == MaterialType::kIllum) {
            const std::string& alt = scene.materials[info.material].alternate;
            hidden = true;
            for (uint32_t m = 0; m < scene.materials.size(); ++m)
                if (!alt.empty() && scene.materials[m].name == alt) info.material = m, hidden = false;
        }
        info.inward = s.inward;
        info.may_pass_shadows = passes_straight(scene.materials[info.material]);
        RTCGeometry g;
        if (s.type == ShapeType::kSphere) {
            info.sphere = true;
            info.center = s.center - offset_;
            info.radius = s.radius;
            if (hidden) {
                hidden_emitters_.push_back(std::move(info));
                continue;
            }
            g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
            auto* p = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                                  4 * sizeof(float), 1));
            p[0] = static_cast<float>(info.center.x);
            p[1] = static_cast<float>(info.center.y);
            p[2] = static_cast<float>(info.center.z);
            p[3] = static_cast<float>(info.radius);
        } else {
            TriangleMesh mesh;
            tessellate(s, mesh);
            if (mesh.indices.empty()) continue;
            if (hidden) {
                for (auto& v : mesh.positions) v = v - offset_;
                info.positions = std::move(mesh.positions);
                info.indices = std::move(mesh.indices);
                hidden_emitters_.push_back(std::move(info));
                continue;
            }
            for (auto& v : mesh.positions) v = v - offset_;
            info.positions = mesh.positions;
            info.indices = mesh.indices;
            for (const auto& uv : mesh.uvs) info.uvs.push_back({static_cast<float>(uv[0]), static_cast<float>(uv[1])});
            for (const auto& n : mesh.normals) info.vertex_normals.push_back(normalize_or_zero(n));
            for (const auto& c : mesh.colors) info.colors.push_back({static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)});
            info.normals.reserve(mesh.indices.size());
            for (const auto& t : mesh.indices) {
                const Vec3 &p0 = mesh.positions[t[0]], &p1 = mesh.positions[t[1]], &p2 = mesh.positions[t[2]];
                info.normals.push_back(normalize_or_zero(cross(p1 - p0, p2 - p0)));
            }
            g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
            // One extra vertex of padding: Embree may load 16 bytes from the last float3.
            auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                  3 * sizeof(float), mesh.positions.size() + 1));
            for (size_t k = 0; k < mesh.positions.size(); ++k) {
                v[3 * k + 0] = static_cast<float>(mesh.positions[k].x);
                v[3 * k + 1] = static_cast<float>(mesh.positions[k].y);
                v[3 * k + 2] = static_cast<float>(mesh.positions[k].z);
            }
            v[3 * mesh.positions.size()] = v[3 * mesh.positions.size() + 1] = v[3 * mesh.positions.size() + 2] = 0;
            auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(uint32_t), mesh.indices.size()));
            for (size_t k = 0; k < mesh.indices.size(); ++k)
                for (int c = 0; c < 3; ++c) idx[3 * k + static_cast<size_t>(c)] = mesh.indices[k][static_cast<size_t>(c)];
        }
        const bool cut = cutouts && cutouts->cuts_out(info.material);
        const bool hide_back = !scene.back_faces_visible && hides_back(scene.materials[info.material]);
        if (cut || hide_back) {
            filters_.push_back(std::make_unique<GeometryFilter>(GeometryFilter{cut ? cutouts : nullptr, hide_back, info.inward}));
            rtcSetGeometryUserData(g, filters_.back().get());
            rtcSetGeometryIntersectFilterFunction(g, surface_filter);
        }
        if (cut || info.may_pass_shadows)
            rtcSetGeometryOccludedFilterFunction(g, cut && info.may_pass_shadows ? cutout_then_shadow_pass_filter
                                                    : cut                          ? cutout_filter
                                                                                   : shadow_pass_filter);
        any_shadow_passes_ = any_shadow_passes_ || info.may_pass_shadows;
        rtcCommitGeometry(g);
        unsigned id = rtcAttachGeometry(scene_, g);
        rtcReleaseGeometry(g);
        if (id != geometries_.size()) throw std::runtime_error("Embree: unexpected geometry id");
        geometries_.push_back(std::move(info));
    }
    rtcCommitScene(scene_);
    check(device_, "build the scene");
}

EmbreeScene::~EmbreeScene() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

}  // namespace crex
