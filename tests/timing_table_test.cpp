// experiments/timing_table.h: a Table 1 row measured on a small mesh. No assertion on speed: what is
// checked is what the row holds: every column measured, finite and positive; the MDS columns only when asked
// for; a repeat count below one refused.
#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace timing_table_test
}  // namespace cshapes
