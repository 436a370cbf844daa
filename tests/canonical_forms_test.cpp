// canonical_form on imperfect meshes: every method repairs what it needs, the result keeps the input's vertex
// count and order (NaN rows and valid = 0 for dropped vertices), --strict refuses; forms with NaN rows go
// through pairwise distances using their valid vertices only.
#include "cshapes/pipeline/canonical_forms.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <nlohmann/json.hpp>

#include "cshapes/data/articulated.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/eval/pairwise_distances.h"
#include "tests/imperfect_meshes.h"
#include "tests/test_support.h"

namespace cshapes {
namespace canonical_forms_test {

CanonicalFormOptions quick(const std::string& method) {
  CanonicalFormOptions o;
  o.method = method;
  o.coulomb.max_iterations = 60;  // the shape is not the point here, only which vertices it has
  o.coulomb.tear_after = 30;
  o.smacof.max_iterations = 30;
  o.name = "test mesh";
  return o;
}

struct Case {
  const char* name;
  Mesh mesh;
  std::vector<int> dropped;  // input vertices with valid = 0, the same for every method
};

std::vector<Case> cases() {
  std::vector<Case> c;
  c.push_back({"non-manifold edge", test::two_spheres_sharing(2), {}});
  c.push_back({"isolated vertex", test::sphere_with_isolated_vertex(), {162}});
  std::vector<int> small;
  for (int v = 162; v < 204; ++v) small.push_back(v);
  c.push_back({"two components", test::two_components(), small});
  c.push_back({"duplicate face", test::sphere_with_duplicate_face(), {}});
  return c;
}

TEST(CanonicalFormsOfDegenerateInput, CoincidentPointsAreRefusedByName) {
  // Issue 22: 2,000 coincident points gave exit 0, "form quality ok" and every output point in one place.
  Mesh cloud;
  cloud.V = Points::Constant(2000, 3, 0.25);
  for (const char* method : {"coulomb", "cmds", "smacof"}) {
    CanonicalFormOptions o;
    o.method = method;
    o.name = "same.xyz";
    try {
      canonical_form(cloud, o);
      ADD_FAILURE() << method << ": accepted";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("same.xyz: ", 0), 0u) << message;
      EXPECT_NE(message.find("coincide"), std::string::npos) << message;
    }
  }
}

TEST(CanonicalFormsOfDegenerateInput, MdsMemoryIsCheckedBeforeAnyWork) {
  // Issue 22: `canon --method cmds` on 100,000 points spent 37 s before refusing. 2^21 points (a 17.6 TB
  // matrix) are refused at once, naming the input. (The full solver: auto would take landmark rows here.)
  Mesh cloud;
  cloud.V = Points::Random(1 << 21, 3);
  CanonicalFormOptions o;
  o.method = "cmds";
  o.mds_solver.solver = MdsSolver::Full;
  o.name = "huge.xyz";
  try {
    canonical_form(cloud, o);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("huge.xyz: ", 0), 0u) << message;
    EXPECT_NE(message.find("GB"), std::string::npos) << message;
  }
}

TEST(CanonicalFormsOfDegenerateInput, EveryErrorNamesTheMesh) {
  // Issue 22: "rest length of edge 0 is inf" and "non-finite Coulomb gradient" named no file. Coordinates of
  // 1e308 (infinite edge lengths) gave those errors; they are now computed on a scaled copy (see
  // CanonicalFormsScale), so the failing input here is a single triangle.
  Mesh line;  // one triangle: too few vertices for any form
  line.V.resize(3, 3);
  line.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  line.F.resize(1, 3);
  line.F << 0, 1, 2;
  for (const char* method : {"coulomb", "cmds"}) {
    CanonicalFormOptions o;
    o.method = method;
    o.name = "line.off";
    try {
      canonical_form(line, o);
      ADD_FAILURE() << method << ": accepted";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("line.off: ", 0), 0u) << e.what();
    }
  }
  Mesh huge = icosphere(1);
  huge.V *= 1e308;  // finite coordinates, infinite edge lengths
  for (const char* method : {"coulomb", "cmds"}) {
    CanonicalFormOptions o;
    o.method = method;
    const CanonicalForm f = canonical_form(huge, o);
    EXPECT_TRUE(f.X.allFinite()) << method;
    EXPECT_TRUE(form_summary_json(f)["form_quality"]["ok"].get<bool>()) << method;
  }
}

TEST(CanonicalFormsOnImperfectMeshes, EveryMethodKeepsTheInputVertices) {
  for (const Case& c : cases())
    for (const std::string& method : canonical_form_methods()) {
      SCOPED_TRACE(std::string(c.name) + ", " + method);
      CanonicalForm f = canonical_form(c.mesh, quick(method));
      ASSERT_EQ(f.X.rows(), c.mesh.num_vertices());
      ASSERT_EQ(f.valid.size(), c.mesh.num_vertices());
      // Coulomb takes a non-manifold edge as it is; everything else here needs a repair.
      EXPECT_EQ(f.repairs.empty(), method == "coulomb" && std::string(c.name) == "non-manifold edge");
      std::vector<int> dropped;
      for (Index v = 0; v < c.mesh.num_vertices(); ++v) {
        if (f.valid[v] == 0) {
          dropped.push_back(static_cast<int>(v));
          EXPECT_TRUE(f.X.row(v).array().isNaN().all()) << "vertex " << v;
        } else {
          EXPECT_TRUE(f.X.row(v).allFinite()) << "vertex " << v;
        }
      }
      if (std::string(c.name) == "non-manifold edge") {
        // Coulomb takes the edge graph as it is; MDS splits the edge and keeps one sphere (the other's
        // vertices, except the two shared ones, dropped).
        if (method == "coulomb") {
          EXPECT_TRUE(dropped.empty());
        } else {
          EXPECT_EQ(dropped.size(), static_cast<size_t>(c.mesh.num_vertices() - 162));
        }
        continue;
      }
      EXPECT_EQ(dropped, c.dropped);
    }
}

TEST(CanonicalFormsOnImperfectMeshes, CleanMeshesNeedNoRepair) {
  CanonicalForm f = canonical_form(icosphere(2), quick("cmds"));
  EXPECT_TRUE(f.repairs.empty());
  EXPECT_EQ(f.repair_text, "");
  EXPECT_EQ(f.valid.sum(), 162);
  EXPECT_TRUE(f.X.allFinite());
}

TEST(CanonicalFormsOnImperfectMeshes, StrictRefusesWhatWouldBeRepaired) {
  for (const Case& c : cases())
    for (const std::string& method : canonical_form_methods()) {
      SCOPED_TRACE(std::string(c.name) + ", " + method);
      CanonicalFormOptions o = quick(method);
      o.strict = true;
      const bool coulomb_takes_it = method == "coulomb" && std::string(c.name) == "non-manifold edge";
      if (coulomb_takes_it) {
        EXPECT_NO_THROW(canonical_form(c.mesh, o));
        continue;
      }
      try {
        canonical_form(c.mesh, o);
        ADD_FAILURE() << "accepted";
      } catch (const Error& e) {
        std::string message = e.what();
        EXPECT_NE(message.find("test mesh"), std::string::npos) << message;
        EXPECT_NE(message.find("--strict"), std::string::npos) << message;
      }
    }
}

TEST(CanonicalFormsOnImperfectMeshes, StrictRefusesACachedFormToo) {
  DiskCache cache(test::scratch_dir("forms"));
  Mesh m = test::sphere_with_isolated_vertex();
  CanonicalFormOptions o = quick("coulomb");
  CanonicalForm first = cached_canonical_form(cache, m, o);
  bool cached = false;
  CanonicalForm again = cached_canonical_form(cache, m, o, &cached);
  EXPECT_TRUE(cached);
  EXPECT_EQ(again.valid, first.valid);
  EXPECT_EQ(again.repair_text, first.repair_text);
  o.strict = true;
  EXPECT_THROW(cached_canonical_form(cache, m, o), Error);
}

TEST(PairwiseDistancesWithDroppedVertices, NaNRowsAreLeftOut) {
  // The same shape with and without NaN rows appended: distance zero, and finite.
  Points A = icosphere(2).V;
  Points B(A.rows() + 3, 3);
  B << A, Points::Constant(3, 3, std::numeric_limits<double>::quiet_NaN());
  Points C = A * 1.5;
  PairwiseDistanceResult r = pairwise_distances({A, B, C}, {});
  EXPECT_TRUE(r.hausdorff.allFinite());
  EXPECT_NEAR(r.hausdorff(0, 1), 0, 1e-9);
  EXPECT_NEAR(r.hausdorff(0, 2), r.hausdorff(1, 2), 1e-9);
  EXPECT_GT(r.hausdorff(0, 2), 0.1);
}

// --distances (options.distances_file): a matrix of the input's size is restricted to the repaired vertices,
// and the form equals the one computed from the same matrix passed in memory.
TEST(CanonicalFormsFromADistanceFile, InputSizedMatrixIsRestrictedToTheRepairedVertices) {
  const Mesh mesh = test::sphere_with_isolated_vertex();  // vertex 162 is dropped for MDS
  CanonicalFormOptions o = quick("cmds");
  const RepairedMesh repaired = repair_for_canonical_form(mesh, o);
  ASSERT_EQ(repaired.mesh.num_vertices(), mesh.num_vertices() - 1);
  const DistanceMatrix on_repaired = all_pairs_geodesics(repaired.mesh, o.geodesics);
  // The input-sized matrix `geodesics` writes: NaN at the dropped vertex.
  const DistanceMatrix on_input =
      distances_to_input_vertices(on_repaired, repaired.vertex_map, mesh.num_vertices());
  EXPECT_EQ(distances_on_repaired_mesh(on_input, repaired, "D.bin"), on_repaired);
  EXPECT_EQ(distances_on_repaired_mesh(on_repaired, repaired, "D.bin"), on_repaired);
  EXPECT_THROW(distances_on_repaired_mesh(DistanceMatrix::Zero(5, 5), repaired, "D.bin"), Error);
  // A repair that drops one vertex and splits another keeps the count: the matrix is read as the input's.
  RepairedMesh same_count;
  same_count.input_vertices = 3;
  same_count.vertex_map = {0, 2, 2};  // input vertex 1 dropped, input vertex 2 split in two
  same_count.mesh.V = Points::Zero(3, 3);
  same_count.actions.push_back({"test", 1});
  DistanceMatrix input3(3, 3);
  input3 << 0, 1, 2, 1, 0, 3, 2, 3, 0;
  DistanceMatrix expected(3, 3);
  expected << 0, 2, 2, 2, 0, 0, 2, 0, 0;
  EXPECT_EQ(distances_on_repaired_mesh(input3, same_count, "D.bin"), expected);

  const std::string dir = test::scratch_dir("canon_distances_file");
  write_distance_matrix(dir + "/D.bin", on_input);
  o.distances_file = dir + "/D.bin";
  const CanonicalForm from_file = canonical_form(mesh, o);
  CanonicalFormOptions in_memory = quick("cmds");
  const CanonicalForm from_memory = canonical_form(mesh, in_memory, &on_repaired);
  ASSERT_EQ(from_file.X.rows(), mesh.num_vertices());
  EXPECT_TRUE(from_file.X.row(162).array().isNaN().all());
  EXPECT_EQ(from_file.X.topRows(162), from_memory.X.topRows(162));
  // The file's content is part of the cache key.
  EXPECT_NE(canonical_form_key(o), canonical_form_key(in_memory));
}

// A matrix read with --distances is checked as SMACOF checks one, for every method that embeds it: cmds
// embedded an asymmetric matrix and one with a non-zero diagonal (issue 36).
TEST(CanonicalFormsFromADistanceFile, AsymmetricMatricesAndNonZeroDiagonalsAreRefusedByEveryMethod) {
  const Mesh mesh = icosphere(1);
  CanonicalFormOptions o = quick("cmds");
  const DistanceMatrix D = all_pairs_geodesics(mesh, o.geodesics);
  const std::string dir = test::scratch_dir("canon_distances_checked");
  DistanceMatrix asymmetric = D, diagonal = D;
  asymmetric(3, 7) *= 1.5f;
  diagonal(5, 5) = 0.25f * D.maxCoeff();
  write_distance_matrix(dir + "/asymmetric.bin", asymmetric);
  write_distance_matrix(dir + "/diagonal.bin", diagonal);
  for (const char* method : {"cmds", "smacof"}) {
    SCOPED_TRACE(method);
    o = quick(method);
    for (const auto& [file, needle] : {std::pair<std::string, std::string>{"asymmetric.bin", "not symmetric"},
                                       {"diagonal.bin", "(5, 5)"}}) {
      o.distances_file = dir + "/" + file;
      try {
        canonical_form(mesh, o);
        ADD_FAILURE() << file << " accepted";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(o.distances_file), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      }
    }
    o.distances_file = dir + "/good.bin";
    write_distance_matrix(o.distances_file, D);
    EXPECT_NO_THROW(canonical_form(mesh, o));
  }
  std::filesystem::remove_all(dir);
}

// Issue 36: spectral-mds with 100,000 sources on a 100,000-vertex mesh ran for seconds, then failed with an
// unnamed "out of memory"; its rows are checked against the memory before any work, as every other method's.
TEST(CanonicalFormsMemory, SpectralMdsRowsAreCheckedBeforeAnyWork) {
  const Mesh mesh = grid(320, 320);  // 102,400 vertices: 100,000 rows take about 120 GB
  CanonicalFormOptions o = quick("spectral-mds");
  o.name = "big.off";
  o.spectral_mds.sources = 100000;
  if (available_memory_bytes() > 2e11) GTEST_SKIP() << "this machine holds the rows";
  try {
    canonical_form(mesh, o);
    ADD_FAILURE() << "not refused";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("big.off: spectral-mds on 102400 vertices needs", 0), 0u) << message;
  }
}

// Issue 36: smacof on a mesh scaled by 1e20 returned rows of zeros (its single-precision kernel squares the
// distances); a scale the kernel cannot hold is refused naming the mesh, one it can is computed.
TEST(CanonicalFormsScale, FarFromUnitSizeAFormIsComputedOnAScaledCopy) {
  // SMACOF's float kernel refused geodesic distances beyond 1e±20 (its squares leave float's range); far from
  // unit size every method now computes on a copy scaled by a power of two, says so, and scales the form
  // back: the same bits as at unit size.
  const Mesh sphere = icosphere(2);
  const double unit = std::ldexp(1.0, -2);  // the icosphere's extent 2 → 0.5, in [0.5, 1)
  const CanonicalForm reference = canonical_form(Mesh{sphere.V * unit, sphere.F}, quick("smacof"));
  for (int exponent : {-70, 70}) {
    const double scale = std::ldexp(unit, exponent);
    const CanonicalForm f = canonical_form(Mesh{sphere.V * scale, sphere.F}, quick("smacof"));
    EXPECT_EQ(f.X, reference.X * std::ldexp(1.0, exponent)) << scale;
    EXPECT_DOUBLE_EQ(form_summary_json(f)["computed_at_scale"].get<double>(),
                     std::ldexp(1.0, -exponent))
        << scale;
  }
  // Within [2^-20, 2^20] as given, without the field.
  const CanonicalForm f = canonical_form(Mesh{sphere.V * 1e5, sphere.F}, quick("smacof"));
  EXPECT_FALSE(form_summary_json(f).contains("computed_at_scale"));
  EXPECT_EQ(canonical_form_scale(Mesh{sphere.V * 1e5, sphere.F}), 1.0);
  EXPECT_EQ(canonical_form_scale(Mesh{sphere.V * 1e-5, sphere.F}), 1.0);
  EXPECT_NE(canonical_form_scale(Mesh{sphere.V * 1e7, sphere.F}), 1.0);
  EXPECT_NE(canonical_form_scale(Mesh{sphere.V * 1e-7, sphere.F}), 1.0);
}

// Bit-identical for any thread count, for every method and SMACOF's variants: the whole form at 1, 2 and 3
// threads (SMACOF on a 2,000-vertex shape gave other bytes at 1 and 2 threads, with default options, RRE and
// area weights).
TEST(CanonicalFormsThreads, EveryMethodIsBitIdenticalAtOneTwoAndThreeThreads) {
  ArticulatedOptions ao;
  ao.poses = 1;
  ao.seed = 9;
  ao.rest.target_vertices = 700;
  const Mesh biped = generate_articulated("biped", ao).poses[0];
  std::vector<std::pair<std::string, CanonicalFormOptions>> cases;
  for (const std::string& method : canonical_form_methods()) {
    CanonicalFormOptions o;
    o.method = method;
    o.coulomb.max_iterations = 150;
    o.smacof.max_iterations = 150;
    cases.emplace_back(method, o);
  }
  CanonicalFormOptions rre;
  rre.method = "smacof";
  rre.smacof.max_iterations = 150;
  rre.smacof.acceleration = SmacofAcceleration::Rre;
  cases.emplace_back("smacof, rre", rre);
  CanonicalFormOptions area = rre;
  area.smacof.acceleration = SmacofAcceleration::None;
  area.smacof_weights = SmacofWeights::Area;
  cases.emplace_back("smacof, area weights", area);
  const int before = omp_get_max_threads();
  for (const auto& [name, o] : cases) {
    std::vector<Points> runs;
    for (int threads : {1, 2, 3}) {
      omp_set_num_threads(threads);
      runs.push_back(canonical_form(biped, o).X);
    }
    omp_set_num_threads(before);
    for (size_t k = 1; k < runs.size(); ++k) EXPECT_EQ(runs[k], runs[0]) << name << ", threads " << k + 1;
  }
}

// SMACOF's start and weights: other choices change the cache key and the form; names are parsed strictly.
TEST(CanonicalFormsSmacofOptions, StartAndWeightsAreOptionsOfTheLibrary) {
  const Mesh mesh = icosphere(2);
  CanonicalFormOptions o = quick("smacof");
  const std::string default_key = canonical_form_key(o);
  o.smacof_init = SmacofInit::Mesh;
  o.smacof_weights = SmacofWeights::Area;
  EXPECT_NE(canonical_form_key(o), default_key);
  const CanonicalForm f = canonical_form(mesh, o);
  const CanonicalForm g = canonical_form(mesh, quick("smacof"));
  ASSERT_TRUE(f.X.allFinite());
  EXPECT_GT((f.X - g.X).norm(), 0);  // another start: another (rotated or different) configuration
  const nlohmann::json summary = form_summary_json(f);
  EXPECT_EQ(summary["smacof"]["init"], "mesh");
  EXPECT_EQ(summary["smacof"]["weights"], "area");
  EXPECT_FALSE(summary.contains("classical_mds"));  // started from the mesh: no classical MDS ran
  for (const std::string& name : smacof_init_names()) EXPECT_EQ(to_string(parse_smacof_init(name)), name);
  for (const std::string& name : smacof_weights_names())
    EXPECT_EQ(to_string(parse_smacof_weights(name)), name);
  try {
    parse_smacof_init("random");
    ADD_FAILURE() << "parse_smacof_init accepted 'random'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown 'random'; known: cmds, mesh"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_smacof_weights("areas"), Error);
}

}  // namespace canonical_forms_test
}  // namespace cshapes
