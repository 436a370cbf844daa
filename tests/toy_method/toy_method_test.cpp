// The toy method (tests/toy_method/method_toy.cpp), registered from its one file, as the library, the CLI
// (cshapes_toy: CSHAPES_CLI) and the cache see it. Its Python face: tests/toy_method/check_toy_python.py.
#include <gtest/gtest.h>

#include "cshapes/data/synthetic.h"
#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "tests/test_support.h"

namespace cshapes {
namespace {

TEST(ToyMethod, IsRegisteredWithItsOptions) {
  const std::vector<std::string>& names = canonical_form_methods();
  ASSERT_EQ(names.back(), "toy");
  EXPECT_EQ(canonical_form_methods_reading("toy_scale"), std::vector<std::string>{"toy"});
  EXPECT_EQ(canonical_form_methods_reading("toy_mirror"), std::vector<std::string>{"toy"});
}

TEST(ToyMethod, ComputesItsFormThroughCanonicalForm) {
  const Mesh mesh = icosphere(1, 3.0);
  CanonicalFormOptions o;
  o.method = "toy";
  o.extra["toy_scale"] = "0.5";
  o.extra["toy_mirror"] = "y";
  const CanonicalForm form = canonical_form(mesh, o);
  const Eigen::RowVector3d centre = mesh.V.colwise().mean();
  for (Index i = 0; i < mesh.num_vertices(); ++i) {
    EXPECT_NEAR(form.X(i, 0), 0.5 * (mesh.V(i, 0) - centre(0)), 1e-12);
    EXPECT_NEAR(form.X(i, 1), -0.5 * (mesh.V(i, 1) - centre(1)), 1e-12);
  }
}

// Its key holds its options' values and nothing of the other methods' options; theirs nothing of its.
TEST(ToyMethod, ItsOptionsMakeItsCacheKey) {
  CanonicalFormOptions o;
  o.method = "toy";
  const std::string base = canonical_form_key(o);
  CanonicalFormOptions scaled = o;
  scaled.extra["toy_scale"] = "3";
  EXPECT_NE(canonical_form_key(scaled), base);
  EXPECT_NE(canonical_form_key(scaled).find("\"toy_scale\"=\"3\""), std::string::npos) << canonical_form_key(scaled);
  CanonicalFormOptions other = o;
  other.coulomb.tear_fraction = 0.2;
  other.geodesics.method = GeodesicMethod::Exact;
  EXPECT_EQ(canonical_form_key(other), base);
  CanonicalFormOptions coulomb = scaled;
  coulomb.method = "coulomb";
  CanonicalFormOptions plain;
  EXPECT_EQ(canonical_form_key(coulomb), canonical_form_key(plain));  // coulomb reads no toy option
}

TEST(ToyMethod, TheCliHasItsOptionGroupAndRunsIt) {
  const test::CliResult help = test::run_cli("canon --help");
  EXPECT_EQ(help.exit_code, 0);
  for (const char* text : {"toy: the mesh centred, scaled and mirrored", "[Option Group: toy options]",
                           "--toy-scale FLOAT:in (0, 1000]=2", "--toy-mirror TEXT:{none, x, y, z}=none"})
    EXPECT_NE(help.out.find(text), std::string::npos) << text << "\n" << help.out;
  const std::string dir = test::scratch_dir("toy_cli");
  write_mesh(dir + "/sphere.off", icosphere(1));
  const test::CliResult run =
      test::run_cli("canon " + dir + "/sphere.off -o " + dir + "/toy.off --method toy --toy-scale 4 --toy-mirror z");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Mesh form = read_mesh(dir + "/toy.off");
  const Mesh sphere = icosphere(1);
  EXPECT_NEAR(form.V(0, 2), -4 * (sphere.V(0, 2) - sphere.V.col(2).mean()), 1e-6);
  const test::CliResult refused =
      test::run_cli("canon " + dir + "/sphere.off -o " + dir + "/c.off --method coulomb --toy-scale 4");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("--toy-scale applies to --method toy only, not coulomb"), std::string::npos)
      << refused.err;
  const test::CliResult bad = test::run_cli("canon " + dir + "/sphere.off -o " + dir + "/t.off --method toy "
                                            "--toy-mirror w");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--toy-mirror"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace cshapes
