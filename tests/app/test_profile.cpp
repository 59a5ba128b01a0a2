// `tetcontact profile`: PLY frames, exact counts at margin 0, and the case mode's JSON.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "../test_util.hpp"
#include "tetcontact/io/ply.hpp"
#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/mesh/surface.hpp"

using namespace tc;

namespace {

// The surface of a generated sphere, moved by `shift` and squashed by `squash` (a second
// frame), written as a PLY file, ASCII or binary little endian.
void write_sphere_ply(const std::string& path, const Vec3& shift, double squash, bool binary) {
  Mesh mesh;
  add_body(mesh, "s", make_sphere(1.0, 6, HexSplit::six));
  const Surface s = build_surfaces(mesh).front();
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
      << "element vertex " << mesh.x.size() << "\nproperty double x\nproperty double y\n"
      << "property double z\nelement face " << s.faces.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& p0 : mesh.x) {
    const Vec3 p(p0.x(), p0.y(), squash * p0.z());
    const double v[3] = {p.x() + shift.x(), p.y() + shift.y(), p.z() + shift.z()};
    if (binary)
      out.write(reinterpret_cast<const char*>(v), sizeof v);
    else
      out << v[0] << " " << v[1] << " " << v[2] << "\n";
  }
  for (const Face& f : s.faces) {
    if (binary) {
      const unsigned char n = 3;
      out.write(reinterpret_cast<const char*>(&n), 1);
      out.write(reinterpret_cast<const char*>(f.data()), 3 * sizeof(Index));
    } else {
      out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
    }
  }
}

// (edge–edge pairs, vertex–face pairs) of each method, in the order reported.
std::vector<std::pair<long, long>> counts(const std::string& json) {
  std::vector<std::pair<long, long>> out;
  for (const test::Json& m : test::Json::parse(json))
    out.emplace_back(m.at("ee_pairs").get<long>(), m.at("vf_pairs").get<long>());
  return out;
}

}  // namespace

TEST(Profile, AsciiAndBinaryPlyReadTheSame) {
  test::TempDir dir("profile-ply");
  write_sphere_ply(dir / "a.ply", Vec3::Zero(), 1.0, false);
  write_sphere_ply(dir / "b.ply", Vec3::Zero(), 1.0, true);
  const TriangleSurface a = read_ply(dir / "a.ply"), b = read_ply(dir / "b.ply");
  ASSERT_EQ(a.x.size(), b.x.size());
  EXPECT_EQ(a.triangles, b.triangles);
  for (std::size_t i = 0; i < a.x.size(); ++i) EXPECT_NEAR((a.x[i] - b.x[i]).norm(), 0.0, 1e-5);
  // Euler: a closed triangle surface has V − E + F = 2 (V: the vertices faces use; the file
  // also lists the sphere's interior nodes).
  std::vector<char> used(a.x.size(), 0);
  for (const auto& t : a.triangles)
    for (Index v : t) used[v] = 1;
  const long vertices = std::count(used.begin(), used.end(), 1);
  EXPECT_EQ(
      vertices - static_cast<long>(surface_edges(a).size()) + static_cast<long>(a.triangles.size()),
      2);
  test::write_text(dir / "bad.ply",
                   "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n");
  EXPECT_THROW(read_ply(dir / "bad.ply"), PlyError);
}

// With margin 0 every method reports exactly the counts of the plain sort-and-sweep.
TEST(Profile, FramesAtMarginZeroAgreeAcrossMethods) {
  test::TempDir dir("profile-frames");
  write_sphere_ply(dir / "a.ply", Vec3::Zero(), 1.0, true);
  write_sphere_ply(dir / "b.ply", Vec3(0.05, 0.0, -0.1), 0.8, true);
  const auto r = test::run_cli(
      "profile --frames '" + dir / "a.ply" + "' '" + dir / "b.ply" + "' --margin 0 --json",
      dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto c = counts(r.out);
  ASSERT_EQ(c.size(), 5u) << r.out;  // fcl_tree, fcl_sap, grid, sweep, brute_force
  for (const auto& p : c) EXPECT_EQ(p, c[3]) << r.out;  // c[3]: sweep
  EXPECT_GT(c[3].first, 100);
  EXPECT_GT(c[3].second, 100);
  // A margin only adds pairs.
  const auto r2 = test::run_cli("profile --frames '" + dir / "a.ply" + "' '" + dir / "b.ply" +
                                    "' --margin 0.05 --json --broadphase fcl_tree",
                                dir.str());
  ASSERT_EQ(r2.code, 0) << r2.err;
  const auto c2 = counts(r2.out);
  ASSERT_EQ(c2.size(), 1u);
  EXPECT_GT(c2[0].first, c[3].first);
  EXPECT_GT(c2[0].second, c[3].second);
  // Repeated calls list the same pairs (the command checks) and report the last call's times.
  const auto r3 = test::run_cli("profile --frames '" + dir / "a.ply" + "' '" + dir / "b.ply" +
                                    "' --margin 0 --json --broadphase grid --repeat 3",
                                dir.str());
  ASSERT_EQ(r3.code, 0) << r3.err;
  const auto c3 = counts(r3.out);
  ASSERT_EQ(c3.size(), 1u);
  EXPECT_EQ(c3[0], c[3]);
  const test::Json j3 = test::Json::parse(r3.out);
  EXPECT_GE(j3[0].at("last_query_seconds").get<double>(), 0.0);
  EXPECT_GE(j3[0].at("last_build_seconds").get<double>(), 0.0);
  // Mismatched frames are bad input.
  write_sphere_ply(dir / "c.ply", Vec3::Zero(), 1.0, true);
  test::write_text(dir / "d.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                   "property float y\nproperty float z\nelement face 1\n"
                   "property list uchar int vertex_indices\nend_header\n"
                   "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const auto bad =
      test::run_cli("profile --frames '" + dir / "c.ply" + "' '" + dir / "d.ply" + "'", dir.str());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("not the same surface"), std::string::npos) << bad.err;
}

TEST(Profile, CaseModeReportsEveryMethodInJson) {
  test::TempDir dir("profile-case");
  const auto r = test::run_cli("profile '" + test::source_path("data/cases/bars-impact.yaml") +
                                   "' --steps 5 --json --set bodies.0.mesh.box.cells=[20,2,2]"
                                   " --set bodies.1.mesh.box.cells=[20,2,2]",
                               dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const test::Json methods = test::Json::parse(r.out);
  ASSERT_EQ(methods.size(), 5u) << r.out;
  std::vector<std::string> names;
  for (const test::Json& m : methods) {
    names.push_back(m.at("method").get<std::string>());
    for (const char* key :
         {"/primitives", "/candidates_per_step", "/pruning_ratio", "/seconds_per_step/broadphase"})
      EXPECT_GE(test::number(m, key), 0.0) << key;
    // Every method confirms the same contacts.
    EXPECT_EQ(test::number(m, "/contacts_per_step"),
              test::number(methods[0], "/contacts_per_step"));
  }
  EXPECT_NE(std::find(names.begin(), names.end(), "fcl_tree"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "grid"), names.end());
  EXPECT_GT(test::number(methods[0], "/contacts_per_step"), 0.0);
}
