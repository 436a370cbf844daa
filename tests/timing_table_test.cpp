// experiments/timing_table.h: a Table 1 row measured on a small mesh. No assertion on speed: what is
// checked is what the row holds: every column measured, finite and positive; the MDS columns only when asked
// for; a repeat count below one refused.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "cshapes/support/error.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/timing_table.h"

namespace cshapes {
namespace timing_table_test {

TEST(TimingTable, ARowHoldsEveryColumnMeasured) {
  const Mesh mesh = icosphere(2);
  TimingOptions o;
  o.repeats = 2;
  const TimingRow row = time_canonical_forms("sphere", mesh, o);
  EXPECT_EQ(row.shape, "sphere");
  EXPECT_EQ(row.vertices, mesh.num_vertices());
  EXPECT_TRUE(row.mds_measured);
  for (double seconds :
       {row.mds_precompute, row.mds_iteration, row.coulomb_precompute, row.coulomb_iteration}) {
    EXPECT_TRUE(std::isfinite(seconds));
    EXPECT_GT(seconds, 0);
  }
}

TEST(TimingTable, MdsColumnsOnlyWhenAskedFor) {
  TimingOptions o;
  o.repeats = 1;
  o.mds = false;
  const TimingRow row = time_canonical_forms("sphere", icosphere(1), o);
  EXPECT_FALSE(row.mds_measured);
  EXPECT_EQ(row.mds_precompute, 0);
  EXPECT_EQ(row.mds_iteration, 0);
  EXPECT_GT(row.coulomb_iteration, 0);
  EXPECT_GT(coulomb_iteration_seconds(icosphere(1), 1), 0);
  o.repeats = 0;
  EXPECT_THROW(time_canonical_forms("sphere", icosphere(1), o), Error);
}

// Every measurement of a row reports its progress under the row's shape, each stage ending at 100%: Table 1's
// 22,738-vertex geodesic matrix takes minutes, and a run must not go quiet for them.
TEST(TimingTable, EachMeasurementReportsItsProgressUnderTheShapesName) {
  TimingOptions o;
  o.repeats = 2;
  std::map<std::string, std::pair<double, double>> last;  // stage → (done, total) of its last report
  int polls = 0;
  o.progress = [&](const std::string& stage, double done, double total) {
    if (stage.empty()) ++polls;
    else last[stage] = {done, total};
  };
  time_canonical_forms("sphere", icosphere(2), o);
  for (const char* stage : {"Table 1, sphere: all-pairs geodesics", "Table 1, sphere: SMACOF passes",
                            "Table 1, sphere: Coulomb iterations"}) {
    ASSERT_TRUE(last.count(stage)) << stage;
    EXPECT_GT(last[stage].second, 0) << stage;
    EXPECT_EQ(last[stage].first, last[stage].second) << stage << " ends at 100%";
  }
  EXPECT_EQ(last.size(), 3u) << "no report outside the three stages";
}

}  // namespace timing_table_test
}  // namespace cshapes
