// The CLI on imperfect meshes: `info` describes them (known answers per defect kind), `canon` repairs what
// each method needs and writes a form with the input's vertex count (NaN rows and a `valid` flag for dropped
// vertices), `--strict` refuses naming the defect, `distmat` goes through a dataset with imperfect meshes.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <vector>

#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/imperfect_meshes.h"
#include "tests/test_support.h"

namespace cshapes {
namespace imperfect_meshes_cli_test {

nlohmann::json info(const std::string& path) {
  test::CliResult r = test::run_cli("info '" + path + "' --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out.empty() ? "{}" : r.out);
}

TEST(ImperfectMeshesCli, InfoDescribesEachDefectKind) {
  const std::string dir = test::scratch_dir("imperfect_cli");
  write_mesh(dir + "/edge.off", test::two_spheres_sharing(2));
  nlohmann::json j = info(dir + "/edge.off");
  EXPECT_EQ(j["defects"]["nonmanifold_edges"]["count"], 1);
  EXPECT_EQ(j["defects"]["nonmanifold_edges"]["examples"][0][2], 4);
  EXPECT_EQ(j["nonmanifold_edges"], 1);
  EXPECT_EQ(j["genus"], -1);

  write_mesh(dir + "/pinch.off", test::two_spheres_sharing(1));
  EXPECT_EQ(info(dir + "/pinch.off")["defects"]["nonmanifold_vertices"]["count"], 1);

  write_mesh(dir + "/iso.off", test::sphere_with_isolated_vertex());
  j = info(dir + "/iso.off");
  EXPECT_EQ(j["defects"]["isolated_vertices"]["count"], 1);
  EXPECT_EQ(j["defects"]["isolated_vertices"]["examples"][0], 162);

  write_mesh(dir + "/two.off", test::two_components());
  j = info(dir + "/two.off");
  EXPECT_EQ(j["defects"]["components"], 2);
  EXPECT_EQ(j["defects"]["component_sizes"], nlohmann::json::parse("[162, 42]"));

  write_mesh(dir + "/dup.off", test::sphere_with_duplicate_face());
  j = info(dir + "/dup.off");
  EXPECT_EQ(j["defects"]["duplicate_faces"]["count"], 1);
  EXPECT_EQ(j["defects"]["nonmanifold_edges"]["count"], 0);
  EXPECT_EQ(j["nonmanifold_edges"], 0);

  Mesh g = grid(4, 3);
  g.F.conservativeResize(g.num_faces() + 2, 3);
  g.F.row(g.num_faces() - 2) << 0, 1, 2;  // zero area
  g.F.row(g.num_faces() - 1) << 5, 5, 6;  // repeats a vertex
  write_mesh(dir + "/flat.off", g);
  j = info(dir + "/flat.off");
  EXPECT_EQ(j["defects"]["zero_area_faces"]["count"], 1);
  EXPECT_EQ(j["defects"]["repeated_vertex_faces"]["count"], 1);
  EXPECT_EQ(j["defects"]["zero_length_edges"]["count"], 0);

  Mesh c = grid(4, 3);
  c.V.row(1) = c.V.row(0);
  write_mesh(dir + "/coincident.off", c);
  EXPECT_EQ(info(dir + "/coincident.off")["defects"]["zero_length_edges"]["count"], 1);

  EXPECT_EQ(info(dir + "/dup.off")["defects"]["any"], true);
  write_mesh(dir + "/clean.off", icosphere(1));
  EXPECT_EQ(info(dir + "/clean.off")["defects"]["summary"], "none");
}

TEST(ImperfectMeshesCli, CanonKeepsTheInputVertexCountAndStrictRefuses) {
  const std::string dir = test::scratch_dir("imperfect_cli");
  const Mesh two = test::two_components();
  write_mesh(dir + "/two.off", two);
  for (const std::string method : {"coulomb", "cmds", "smacof"}) {
    SCOPED_TRACE(method);
    const std::string out = dir + "/" + method + ".ply";
    // Options of another method are refused, so each method gets only its own.
    const std::string limit = method == std::string("coulomb")  ? " --coulomb-max-iterations 40"
                              : method == std::string("smacof") ? " --smacof-max-iterations 20"
                                                                : "";
    test::CliResult r =
        test::run_cli("canon '" + dir + "/two.off' -o '" + out + "' --method " + method + limit + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("vertices of smaller components dropped 42"), std::string::npos) << r.err;
    nlohmann::json summary = nlohmann::json::parse(r.out);
    EXPECT_EQ(summary["input_vertices"], two.num_vertices());
    EXPECT_EQ(summary["kept_input_vertices"], 162);
    EXPECT_EQ(summary["repaired_vertices"], 162);
    // The PLY has the input's 204 vertices; the small sphere's are NaN with valid = 0, which reading it back
    // leaves out.
    const std::string text = [&] {
      std::ifstream in(out);
      return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    EXPECT_NE(text.find("element vertex 204"), std::string::npos);
    EXPECT_NE(text.find("property double valid"), std::string::npos);
    EXPECT_NE(text.find("nan"), std::string::npos);
    const MeshFile back = read_mesh_file(out);
    EXPECT_EQ(back.invalid_vertices, 42);
    EXPECT_EQ(back.mesh.num_vertices(), 162);

    r = test::run_cli("canon '" + dir + "/two.off' -o '" + dir + "/strict.ply' --method " + method +
                      " --strict");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("2 components"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("two.off"), std::string::npos) << r.err;
  }
  // Nothing dropped (a split edge keeps every vertex for Coulomb): the form reads back with every vertex.
  write_mesh(dir + "/edge.off", test::two_spheres_sharing(2));
  test::CliResult r = test::run_cli("-q canon '" + dir + "/edge.off' -o '" + dir +
                                    "/edge_c.off' --method coulomb "
                                    "--coulomb-max-iterations 40");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_mesh(dir + "/edge_c.off").num_vertices(), test::two_spheres_sharing(2).num_vertices());
  // Dropped vertices cannot go to OFF: said before any work.
  r = test::run_cli("-q canon '" + dir + "/two.off' -o '" + dir + "/two_c.off' --method coulomb");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("write .ply"), std::string::npos) << r.err;
}

TEST(ImperfectMeshesCli, DistmatGoesThroughImperfectMeshesAndSkipsUnusableOnes) {
  const std::string dir = test::scratch_dir("imperfect_cli");
  write_mesh(dir + "/data/ball0.off", test::two_components());
  write_mesh(dir + "/data/ball1.off", test::sphere_with_duplicate_face());
  write_mesh(dir + "/data/ball2.off", test::sphere_with_isolated_vertex());
  test::write_text(dir + "/data/ball3.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");  // 3 vertices
  test::write_text(dir + "/data/notes.txt", "not a mesh\n");
  const std::string base = "distmat '" + dir + "/data' --cache '" + dir +
                           "/cache' --method coulomb "
                           "--coulomb-max-iterations 40 -o '" +
                           dir + "/d.csv'";
  test::CliResult r = test::run_cli(base + " --json");
  ASSERT_EQ(r.exit_code, 3) << r.err;  // a partial result: a file was left out
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["shapes"], 3);
  ASSERT_EQ(j["skipped"].size(), 1u);
  // The forms stopped at the short cap are kept and named "not converged"; the one left out is ball3.off.
  const std::vector<nlohmann::json> left_out = test::left_out_failures(j);
  ASSERT_EQ(left_out.size(), 1u) << j.dump(2);
  EXPECT_NE(left_out[0]["path"].get<std::string>().find("ball3.off"), std::string::npos);
  EXPECT_NE(r.err.find("ball3.off"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("duplicate faces dropped 1"), std::string::npos) << r.err;
  r = test::run_cli(base + " --strict");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--strict"), std::string::npos) << r.err;
}

}  // namespace imperfect_meshes_cli_test
}  // namespace cshapes
