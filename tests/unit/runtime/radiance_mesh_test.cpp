// RADIANCE's compiled meshes (issue 39): a mesh obj2mesh made (tests/data/radiance/quad.rtm,
// two triangles of a unit square, one red and one blue, a tilted normal, texture
// coordinates) read back with its materials, moved by the primitive's transform, in the
// primitive's modifier when that is not void, and a damaged file refused where it is named.
// Instances of a frozen octree oconv made (square_ball.oct) the same way, and obj2rad's
// smoothed triangles (a texfunc over tmesh.cal) read as mesh normals.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/support/scene_helpers.h"
#include "tests/support/scratch_folder.h"

namespace crex {
namespace {

const std::string kQuad = std::string(CREX_SOURCE_DIR) + "/tests/data/radiance/quad.rtm";
const std::string kOctree = std::string(CREX_SOURCE_DIR) + "/tests/data/radiance/square_ball.oct";

const Shape* shape_in(const Scene& s, const std::string& material) {
    for (const Shape& sh : s.shapes)
        if (sh.material == material) return &sh;
    return nullptr;
}

bool has_vertex(const Shape& s, const Vec3& v) {
    for (const Vec3& p : s.vertices)
        if (length(p - v) < 1e-8) return true;
    return false;
}

TEST(RadianceMesh, ItsTrianglesInItsOwnMaterialsMovedByTheTransform) {
    auto r = testing::load_rad_text("void mesh quad 5 " + kQuad + " -t 0 0 1 0 0\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Shape* red = shape_in(*r.scene, "red");
    const Shape* blue = shape_in(*r.scene, "blue");
    ASSERT_TRUE(red && blue);
    EXPECT_EQ(red->type, ShapeType::kMesh);
    ASSERT_EQ(red->triangles.size(), 1u);
    ASSERT_EQ(blue->triangles.size(), 1u);
    for (const Vec3& v : {Vec3{0, 0, 1}, Vec3{1, 0, 1}, Vec3{1, 1, 1}}) EXPECT_TRUE(has_vertex(*red, v)) << v.x << " " << v.y;
    for (const Vec3& v : {Vec3{0, 0, 1}, Vec3{1, 1, 1}, Vec3{0, 1, 1}}) EXPECT_TRUE(has_vertex(*blue, v)) << v.x << " " << v.y;
    // The red triangle's vertex (1, 0) has the tilted normal (0.6, 0, 0.8) (13-bit codes).
    ASSERT_EQ(red->normals.size(), red->vertices.size());
    for (size_t i = 0; i < red->vertices.size(); ++i) {
        const Vec3 want = length(red->vertices[i] - Vec3{1, 0, 1}) < 1e-8 ? Vec3{0.6, 0, 0.8} : Vec3{0, 0, 1};
        EXPECT_LT(length(red->normals[i] - want), 2e-4);
    }
    // Texture coordinates are the vertices' own (vt = x, y), to 2^-32 of their range.
    ASSERT_EQ(red->uvs.size(), red->vertices.size());
    for (size_t i = 0; i < red->vertices.size(); ++i) {
        EXPECT_NEAR(red->uvs[i][0], red->vertices[i].x, 1e-8);
        EXPECT_NEAR(red->uvs[i][1], red->vertices[i].y, 1e-8);
    }
    // Facing +z, as the OBJ's triangles are.
    const auto& t = red->triangles[0];
    const Vec3 n = cross(red->vertices[t[1]] - red->vertices[t[0]], red->vertices[t[2]] - red->vertices[t[0]]);
    EXPECT_GT(n.z, 0);
}

TEST(RadianceMesh, AModifierReplacesItsMaterialsAndAMirrorKeepsItsFront) {
    auto r = testing::load_rad_text("void plastic green 0 0 5 .1 .8 .1 0 0\ngreen mesh quad 2 " + kQuad + " -mz 0 0\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_EQ(r.scene->shapes.size(), 1u);
    const Shape& s = r.scene->shapes[0];
    EXPECT_EQ(s.material, "green");
    ASSERT_EQ(s.triangles.size(), 2u);
    // Mirrored through z = 0 the square stays where it was, but its front is now -z.
    for (const auto& t : s.triangles) {
        const Vec3 n = cross(s.vertices[t[1]] - s.vertices[t[0]], s.vertices[t[2]] - s.vertices[t[0]]);
        EXPECT_LT(n.z, 0);
    }
}

TEST(RadianceInstance, AnOctreesSceneInItsOwnMaterialsMovedByTheTransform) {
    // The octree's own "red" does not replace the file's "red" for what follows it.
    auto r = testing::load_rad_text("void plastic red 0 0 5 .5 .5 .5 0 0\nvoid instance copy 7 " + kOctree +
                                    " -s 2 -t 0 0 1 0 0\nred sphere after 0 0 4 5 5 5 1\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    const Shape *square = nullptr, *ball = nullptr, *after = nullptr;
    for (const Shape& sh : r.scene->shapes) (sh.name == "square" ? square : sh.name == "ball" ? ball : after) = &sh;
    ASSERT_TRUE(square && ball && after);
    for (const Vec3& v : {Vec3{0, 0, 1}, Vec3{2, 0, 1}, Vec3{2, 2, 1}, Vec3{0, 2, 1}}) EXPECT_TRUE(has_vertex(*square, v)) << v.x << " " << v.y;
    EXPECT_LT(length(ball->center - Vec3{1, 1, 2}), 1e-8);
    EXPECT_NEAR(ball->radius, 0.5, 1e-8);
    const Material* inner = r.scene->find_material(square->material);
    const Material* outer = r.scene->find_material(after->material);
    ASSERT_TRUE(inner && outer);
    EXPECT_NEAR(inner->color.x, 0.8, 1e-6);  // the octree's red
    EXPECT_NEAR(outer->color.x, 0.5, 1e-12);  // the file's
    EXPECT_NEAR(r.scene->find_material(ball->material)->color.y, 0.8, 1e-6);
}

TEST(RadianceInstance, AModifierReplacesEveryMaterialInside) {
    auto r = testing::load_rad_text("void plastic grey 0 0 5 .5 .5 .5 0 0\ngrey instance copy 1 " + kOctree + " 0 0\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_EQ(r.scene->shapes.size(), 2u);
    for (const Shape& sh : r.scene->shapes) EXPECT_EQ(sh.material, "grey") << sh.name;
}

TEST(RadianceInstance, SmoothedTrianglesBecomeMeshNormals) {
    // tmesh.cal's normal M (bu, bv, 1) with major axis 2 (z: bu = Px, bv = Py): M makes the
    // normal (Px, Py, 1) before normalising, so the vertices of the triangle (0,0), (1,0),
    // (0,1) at z = 0 get (0,0,1), (1,0,1)/sqrt2 and (0,1,1)/sqrt2. Two such triangles of one
    // object join one mesh.
    const std::string tex = "texfunc smooth 4 dx dy dz tmesh.cal 0 10 2 1 0 0 0 1 0 0 0 1\n";
    auto r = testing::load_rad_text("void plastic grey 0 0 5 .5 .5 .5 0 0\ngrey " + tex + "smooth polygon t 0 0 9 0 0 0 1 0 0 0 1 0\n"
                                    "grey " + tex + "smooth polygon t 0 0 9 1 0 0 1 1 0 0 1 0\n");
    ASSERT_TRUE(r.scene) << (r.diagnostics.empty() ? "" : r.diagnostics[0].message);
    ASSERT_EQ(r.scene->shapes.size(), 1u);
    const Shape& s = r.scene->shapes[0];
    EXPECT_EQ(s.type, ShapeType::kMesh);
    EXPECT_EQ(s.material, "grey");
    ASSERT_EQ(s.triangles.size(), 2u);
    ASSERT_EQ(s.normals.size(), s.vertices.size());
    for (size_t i = 0; i < s.vertices.size(); ++i) {
        const Vec3 want = normalize_or_zero(Vec3{s.vertices[i].x, s.vertices[i].y, 1});
        EXPECT_LT(length(s.normals[i] - want), 1e-9) << i;
    }
}

class RadianceMeshFiles : public testing::ScratchFolderTest {
protected:
    RadianceMeshFiles() : ScratchFolderTest("crex_radiance_mesh_") {}
};

TEST_F(RadianceMeshFiles, ADamagedMeshIsRefusedWhereItIsNamed) {
    std::ifstream in(kQuad, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(path("cut.rtm"), std::ios::binary) << bytes.substr(0, bytes.size() - 20);
    auto r = testing::load_rad_text("void mesh quad 1 " + path("cut.rtm") + " 0 0\n");
    EXPECT_FALSE(r.scene);
    testing::expect_diagnostic(r, "damaged mesh", "E308", 1, 18, "cannot read the compiled mesh");
}

TEST_F(RadianceMeshFiles, AnOctreeThatIsNotFrozenIsRefusedWithItsFiles) {
    // oconv without -f: the header, the object size, the cube, the file names, then no scene.
    std::string bytes = "#?RADIANCE\nFORMAT=Radiance_octree\n\n";
    const int magic = 4 * 8 + 251 + 4;  // RADIANCE's OCTMAGIC for 4-byte objects
    bytes += static_cast<char>(magic >> 8), bytes += static_cast<char>(magic & 0xff);
    for (const char* w : {"0", "0", "0", "1", "car.rad", ""}) bytes += std::string(w) + '\0';
    bytes += std::string(4, '\0');
    std::ofstream(path("car.oct"), std::ios::binary) << bytes;
    auto r = testing::load_rad_text("void instance car 1 " + path("car.oct") + " 0 0\n");
    EXPECT_FALSE(r.scene);
    testing::expect_diagnostic(r, "octree not frozen", "E308", 1, 21, "it is not frozen: it names its scene files (car.rad)");
}

}  // namespace
}  // namespace crex
