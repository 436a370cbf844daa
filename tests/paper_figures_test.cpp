// experiments/paper_figures.h without a run of the whole experiment: the data of Figures 2, 3 and 5 on a
// small generated dataset (figure meshes, convergence.csv, the grids the plot script reads, the convergence
// rows of the report), and its cache (a second call reads Figure 3's snapshots and Figure 5's forms back).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cshapes/experiments/paper_figures.h"
#include "test_support.h"

namespace cshapes {
namespace paper_figures_test {

namespace fs = std::filesystem;

int lines_of(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST(PaperFigures, DataOfFigures2To5FromASmallDataset) {
  const std::string dir = test::scratch_dir("paper-figures");
  PaperExperimentOptions o;
  o.data = test::generated_dataset(dir, 2, 2, 300);
  o.out = dir + "/out";
  o.methods = {"coulomb", "cmds"};
  o.canon.geodesics.method = GeodesicMethod::Graph;  // the hand's MDS forms in a blink
  o.fig3_iterations = {5, 10};
  o.fig5_iterations = 8;
  PaperReport report;
  report.options = o;
  const DiskCache misc(o.out + "/cache/misc"), forms(o.out + "/cache/forms");
  write_figure_data(o, report, misc, forms);

  // Figure 2: the hand by every method, with the ICP overlay; the grid names a row per method.
  for (const std::string m : {"coulomb", "cmds"})
    for (const std::string part : {"hand_separated", "hand_glued", "hand_overlay"})
      EXPECT_TRUE(fs::exists(o.out + "/figures/" + m + "_" + part + ".ply")) << m << " " << part;
  ASSERT_TRUE(report.figure_grids.contains("fig2_hand"));
  EXPECT_EQ(report.figure_grids["fig2_hand"]["rows"].size(), 3u);  // the shape and two methods
  // Figure 3: one snapshot per checkpoint.
  ASSERT_TRUE(report.figure_grids.contains("fig3_iterations"));
  EXPECT_EQ(report.figure_grids["fig3_iterations"]["cells"][0].size(), 3u);  // input, 5, 10 iterations
  EXPECT_TRUE(fs::exists(o.out + "/figures/fig3_10.ply"));
  // Figure 5: 1, 10 and 100 projection steps, 8 outer iterations each (no early stop), one CSV row each.
  ASSERT_EQ(report.convergence.size(), 3u);
  EXPECT_EQ(report.convergence[0].projection_steps, 1);
  EXPECT_EQ(report.convergence[2].projection_steps, 100);
  for (const PaperReport::Convergence& c : report.convergence) {
    EXPECT_GT(c.final_energy, 0);
    EXPECT_GE(c.final_violation, 0);
  }
  EXPECT_EQ(lines_of(o.out + "/convergence.csv"), 1 + 3 * 8);
  EXPECT_FALSE(report.figure_shape.empty());

  // A second call computes nothing new and finds the same convergence.
  PaperReport again;
  again.options = o;
  const long misses_before = misc.misses() + forms.misses();
  write_figure_data(o, again, misc, forms);
  EXPECT_EQ(misc.misses() + forms.misses(), misses_before);
  ASSERT_EQ(again.convergence.size(), 3u);
  for (size_t k = 0; k < 3; ++k)
    EXPECT_EQ(again.convergence[k].final_energy, report.convergence[k].final_energy);
}

}  // namespace paper_figures_test
}  // namespace cshapes
