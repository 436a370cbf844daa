// The Coulomb parameter study as a library call (experiments/coulomb_params.h): configurations by name, the
// bridges it glues and whether the canonization tore them, and the files it writes.
#include "cshapes/experiments/coulomb_params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cshapes/support/error.h"
#include "tests/test_support.h"

namespace cshapes {
namespace coulomb_params_test {

TEST(CoulombParams, ConfigurationsHaveDistinctNamesAndDefaultFirst) {
  const auto& configs = coulomb_params_configs();
  ASSERT_FALSE(configs.empty());
  EXPECT_EQ(configs.front().name, "default");
  for (size_t a = 0; a < configs.size(); ++a)
    for (size_t b = a + 1; b < configs.size(); ++b) EXPECT_NE(configs[a].name, configs[b].name);
  // "default" changes nothing; "k=3" changes the projection sweeps only.
  CoulombCanonOptions o;
  configs.front().apply(o);
  EXPECT_EQ(o.projection.steps, CoulombCanonOptions{}.projection.steps);
  for (const auto& c : configs)
    if (c.name == "k=3") c.apply(o);
  EXPECT_EQ(o.projection.steps, 3);
}

TEST(CoulombParams, UnknownConfigurationIsRefusedByName) {
  CoulombParamsOptions o;
  o.data = "/nonexistent";
  o.configs = {"default", "k=7"};
  try {
    run_coulomb_params(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'k=7'"), std::string::npos) << e.what();
  }
}

TEST(CoulombParams, GluedBridgesAreMeasuredOnAToscaShape) {
  CSHAPES_REQUIRE_DATA();
  CoulombParamsOptions o;
  o.data = test::data_dir() + "/tosca5k";
  o.shapes = {"cat0"};
  o.partners = {"cat1"};
  o.configs = {"default"};
  o.bridges = 4;
  o.max_iterations = 40;
  const std::vector<CoulombParamsRow> rows = run_coulomb_params(o);
  ASSERT_EQ(rows.size(), 1u);
  const CoulombParamsRow& r = rows[0];
  EXPECT_EQ(r.shape, "cat0");
  EXPECT_EQ(r.config, "default");
  EXPECT_GT(r.bridges, 0);
  EXPECT_LE(r.bridges, 4);
  EXPECT_GE(r.bridges_torn, 0);
  EXPECT_LE(r.bridges_torn, r.bridges);
  EXPECT_LE(r.iterations, 40);
  EXPECT_TRUE(std::isfinite(r.energy) && r.energy > 0);
  // Distances relative to the bbox diagonal: between 0 and a few diagonals.
  EXPECT_GE(r.glued_rms_to_clean, 0);
  EXPECT_LT(r.glued_rms_to_clean, 1);
  EXPECT_GT(r.input_pose_rms, 0);  // two different poses
  EXPECT_LT(r.input_pose_rms, 1);
  EXPECT_GE(r.pose_rms, 0);

  const std::string dir = test::scratch_dir("coulomb_params");
  const std::string md = write_coulomb_params(dir, rows);
  EXPECT_NE(md.find("| cat0 | default |"), std::string::npos) << md;
  std::ifstream csv(dir + "/coulomb_params.csv");
  std::string header, line;
  std::getline(csv, header);
  std::getline(csv, line);
  EXPECT_EQ(header.rfind("shape,config,iterations,", 0), 0u) << header;
  EXPECT_EQ(line.rfind("cat0,default,", 0), 0u) << line;
  std::filesystem::remove_all(dir);

  // --json prints the same rows at full precision; a partner-less shape's pose distances are null.
  const nlohmann::json j = coulomb_params_json(rows);
  ASSERT_EQ(j.at("rows").size(), 1u);
  EXPECT_EQ(j["rows"][0].at("shape"), "cat0");
  EXPECT_EQ(j["rows"][0].at("bridges_torn").get<int>(), r.bridges_torn);
  EXPECT_DOUBLE_EQ(j["rows"][0].at("energy").get<double>(), r.energy);
  EXPECT_DOUBLE_EQ(j["rows"][0].at("pose_rms").get<double>(), r.pose_rms);
  CoulombParamsRow alone = r;
  alone.pose_rms = alone.input_pose_rms = -1;
  EXPECT_TRUE(coulomb_params_json({alone})["rows"][0].at("pose_rms").is_null());
}

}  // namespace coulomb_params_test
}  // namespace cshapes
