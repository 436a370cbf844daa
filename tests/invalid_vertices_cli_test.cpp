// Canonical forms with dropped vertices (NaN rows with valid = 0, as `canon` writes them) read by `info`,
// `convert` and `align`, which use the valid vertices and say how many were invalid.
#include <gtest/gtest.h>

#include <limits>
#include <nlohmann/json.hpp>

#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "test_support.h"

namespace cshapes {
namespace invalid_vertices_cli_test {

TEST(InvalidVerticesCli, InfoConvertAndAlignUseTheValidVertices) {
  // A form as canon writes one when a repair dropped vertices: NaN rows, valid = 0.
  const std::string dir = test::scratch_dir("invalid_vertices_cli");
  Mesh form = icosphere(2);
  const Index n = form.num_vertices();
  Eigen::VectorXd valid = Eigen::VectorXd::Ones(n);
  for (Index i = 0; i < 10; ++i) {
    form.V.row(i).setConstant(std::numeric_limits<double>::quiet_NaN());
    valid[i] = 0;
  }
  WriteOptions wo;
  wo.scalars = {{"valid", valid}};
  write_mesh(dir + "/form.ply", form, wo);
  write_mesh(dir + "/ball.off", icosphere(2));

  test::CliResult r = test::run_cli("info '" + dir + "/form.ply'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("10 invalid vertices (NaN rows, valid = 0) ignored"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("vertices              " + std::to_string(n - 10)), std::string::npos) << r.out;
  r = test::run_cli("info '" + dir + "/form.ply' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["invalid_vertices"], 10);

  r = test::run_cli("convert --no-validate '" + dir + "/form.ply' '" + dir + "/form.off'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("10 invalid vertices (NaN rows, valid = 0)"), std::string::npos) << r.err;
  const Mesh converted = read_mesh(dir + "/form.off");
  EXPECT_EQ(converted.num_vertices(), n - 10);
  EXPECT_TRUE(converted.V.allFinite());

  r = test::run_cli("align '" + dir + "/form.ply' '" + dir + "/ball.off' --json --one-way");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("10 invalid vertices (NaN rows, valid = 0) ignored"), std::string::npos) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["invalid_vertices"]["source"], 10);
  EXPECT_EQ(j["invalid_vertices"]["target"], 0);
  // The valid vertices are points of the ball itself: aligned onto them exactly (a NaN would not be).
  EXPECT_LT(j["directed_source_to_target"].get<double>(), 1e-9);
}

}  // namespace invalid_vertices_cli_test
}  // namespace cshapes
