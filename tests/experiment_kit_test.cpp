// The experiment kit (pipeline/experiment_kit.h, pipeline/glued_meshes.h, experiments/figures.h): the output
// folder and its atomic files, the numbers of reports, the one glued-mesh cache (computed once, a key that
// changes with every option, failures kept), and the figure scripts found beside the binary.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cshapes/data/articulated.h"
#include "cshapes/support/error.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/pipeline/glued_meshes.h"
#include "test_support.h"

namespace cshapes {
namespace experiment_kit_test {

namespace fs = std::filesystem;

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ExperimentKit, FolderWritesWholeFilesAndNamesItsCaches) {
  const std::string root = test::scratch_dir("kit-folder") + "/a/b";
  const ExperimentFolder folder(root);
  EXPECT_TRUE(fs::is_directory(root));
  folder.write_text("sub/x.txt", "hello\n");
  EXPECT_EQ(read(root + "/sub/x.txt"), "hello\n");
  folder.write_json("j.json", nlohmann::json{{"a", 1}});
  EXPECT_EQ(read(root + "/j.json"), "{\n  \"a\": 1\n}\n");
  EXPECT_EQ(folder.path("sub/x.txt"), root + "/sub/x.txt");
  EXPECT_EQ(folder.cache("forms").directory(), root + "/cache/forms");
  for (const auto& entry : fs::recursive_directory_iterator(root))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << "a temporary file remains";
  // A folder that cannot be made is a write error naming it.
  test::write_text(root + "/file", "x");
  EXPECT_THROW(ExperimentFolder(root + "/file/below"), WriteError);
}

TEST(ExperimentKit, NumbersOfReports) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(fixed(0.12345, 3), "0.123");
  EXPECT_EQ(fixed(2, 0), "2");
  EXPECT_EQ(fixed(nan, 2), "—");
  EXPECT_EQ(fixed(std::numeric_limits<double>::infinity(), 2), "—");
  EXPECT_EQ(percent(0.1234), "12.34%");
  EXPECT_EQ(percent(0.5, 0), "50%");
  EXPECT_EQ(percent(nan), "—");
  EXPECT_EQ(format_number("%+.3f", 0.25), "+0.250");
  EXPECT_EQ(format_number("%.2f", nan), "—");
  std::string said;
  say([&](const std::string& line) { said += line; }, "a line");
  say(NoteFn(), "nobody listens");  // no channel: nothing happens
  EXPECT_EQ(said, "a line");
}

// A generated biped of about 400 vertices: its limbs offer spots close in space and far along the surface.
Mesh biped() {
  ArticulatedDatasetOptions o;
  o.classes = 1;
  o.poses = 1;
  o.noisy = 0;
  o.rest.target_vertices = 400;
  return make_articulated_dataset(o).front().mesh;
}

TEST(GluedMeshes, ComputedOnceThenServedFromTheCache) {
  const Mesh mesh = biped();
  const DiskCache cache(test::scratch_dir("kit-glue") + "/cache");
  TopologicalNoiseOptions o;
  o.glue_count = 1;
  o.seed = 3;
  o.relax_steps = 3;
  const GluedMesh first = cached_glued_mesh(cache, mesh, o);
  ASSERT_TRUE(first.ok()) << first.error;
  EXPECT_FALSE(first.cached);
  EXPECT_EQ(first.glued.size(), 2u);
  EXPECT_TRUE(first.mesh.V == mesh.V) << "gluing keeps the vertices";
  const GluedMesh second = cached_glued_mesh(cache, mesh, o);
  EXPECT_TRUE(second.cached);
  EXPECT_TRUE(second.mesh.F == first.mesh.F);
  EXPECT_EQ(second.glued, first.glued);
  const TopologicalNoiseResult direct = glue_topological_noise(mesh, o);
  EXPECT_TRUE(direct.mesh.F == first.mesh.F) << "the cache serves what the glue computes";
}

TEST(GluedMeshes, EveryOptionChangesTheKey) {
  const Mesh mesh = icosphere(1);
  const TopologicalNoiseOptions base;
  const std::string key = glued_mesh_key(mesh, base);
  std::vector<TopologicalNoiseOptions> changed(12, base);
  changed[0].glue_count += 1;
  changed[1].seed += 1;
  changed[2].max_gap = 0.5;
  changed[3].gap_edge_lengths += 1;
  changed[4].min_ratio += 1;
  changed[5].min_geodesic_fraction += 0.01;
  changed[6].min_separation_fraction += 0.01;
  changed[7].min_facing += 0.1;
  changed[8].landmarks += 1;
  changed[9].max_checks += 1;
  changed[10].geodesic.method = GeodesicMethod::FastMarching;
  changed[11].relax_steps += 1;
  for (size_t k = 0; k < changed.size(); ++k)
    EXPECT_NE(glued_mesh_key(mesh, changed[k]), key) << "option " << k;
  Mesh moved = mesh;
  moved.V(0, 0) += 1e-9;
  EXPECT_NE(glued_mesh_key(moved, base), key) << "the mesh's content";
}

TEST(GluedMeshes, AGlueThatFailsIsAResultAndIsCached) {
  const Mesh mesh = icosphere(1);  // convex: no two spots close in space and far along the surface
  const DiskCache cache(test::scratch_dir("kit-glue-fail") + "/cache");
  TopologicalNoiseOptions o;
  o.glue_count = 3;
  const GluedMesh first = cached_glued_mesh(cache, mesh, o);
  EXPECT_FALSE(first.ok());
  EXPECT_FALSE(first.error.empty());
  EXPECT_EQ(first.mesh.num_vertices(), 0);
  const GluedMesh second = cached_glued_mesh(cache, mesh, o);
  EXPECT_TRUE(second.cached);
  EXPECT_EQ(second.error, first.error);
}

TEST(Figures, ScriptsAreFoundBesideTheBinaryAndAMissingOneIsSaidNotThrown) {
  const std::string dir = plot_scripts_directory();
  ASSERT_FALSE(dir.empty()) << "build/share/cshapes/plots (copied by the build)";
  EXPECT_TRUE(fs::exists(fs::path(dir) / "noise_figure.py"));
  const std::string out = test::scratch_dir("kit-figure");
  const FigureRun run = draw_figure("no_such_script.py", {out}, out + "/x", FigureFormat::png);
  EXPECT_FALSE(run.drawn);
  EXPECT_NE(run.problem.find("no_such_script.py"), std::string::npos) << run.problem;
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
  EXPECT_EQ(find_python("no_module_named_like_this_xyz"), "");
}

}  // namespace experiment_kit_test
}  // namespace cshapes
