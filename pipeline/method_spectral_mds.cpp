// Method spectral-mds (pipeline/canonical_form_methods.h): Aflalo & Kimmel's spectral MDS (canon/spectral_mds.h)
// — classical MDS of the squared geodesic distances restricted to the span of the first k Laplace–Beltrami
// eigenfunctions, fitted from L farthest-point geodesic rows (geodesics/landmark_geodesics.h, options.geodesics):
// the fast MDS the paper cites [AK13], O((L + k) n) memory.
#include <algorithm>

#include "cshapes/support/format.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/landmark_geodesics.h"
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/spectral_method.h"

namespace cshapes {

namespace {

CanonicalForm spectral_mds_compute(const Mesh& mesh, const CanonicalFormOptions& options,
                                   const GivenDistances&) {
  CSHAPES_REQUIRE(!mesh.is_point_cloud(), options.name,
                  ": spectral-mds needs a mesh with faces (its geodesic rows and its Laplacian)");
  const SpectralMdsOptions& so = options.spectral_mds;
  const Index n = mesh.num_vertices(), k = so.laplacian.eigenpairs;
  CSHAPES_REQUIRE(k < n, options.name, ": spectral-mds fits its distances in a basis of ", k,
                  " eigenfunctions (basis), which needs more than ", k, " vertices; this mesh has ", n,
                  ". On a mesh this small, method cmds uses the whole geodesic matrix at little cost");
  SpectralSolve s = spectral_eigenpairs(mesh, so.laplacian, options, "spectral-mds");
  CanonicalForm form;
  auto start = WallClock::now();
  LandmarkGeodesicsOptions lo;
  lo.count = std::min<Index>(so.sources, mesh.num_vertices());
  lo.geodesics = options.geodesics;
  if (!lo.geodesics.progress) lo.geodesics.progress = options.progress;  // reports per row, hears a stop
  const LandmarkGeodesics rows = landmark_geodesics(mesh, lo);
  form.precompute_seconds = s.seconds + seconds_since(start);
  start = WallClock::now();
  const SpectralMdsResult r = spectral_mds(s.eigen, rows.landmarks, rows.rows);
  form.X = r.X;
  form.solve_seconds = seconds_since(start);
  s.summary["sources"] = rows.landmarks.size();
  s.summary["coverage_radius"] = rows.coverage_radius;
  s.summary["geodesics"] = to_string(options.geodesics.method);
  s.summary["mds_eigenvalues"] = {r.eigenvalues[0], r.eigenvalues[1], r.eigenvalues[2]};
  s.summary["negative_mass"] = r.negative_mass;
  s.summary["fit_residual"] = r.fit_residual;
  say(options.note, "spectral-mds: " + std::to_string(rows.landmarks.size()) + " geodesic rows (" +
                        to_string(options.geodesics.method) + ", coverage radius " +
                        significant(rows.coverage_radius) + "); the basis misses " +
                        significant(100 * r.fit_residual) + "% of their squared distances");
  form.details = std::move(s.summary);
  return form;
}

// The L × n geodesic rows (float) and their squares (double), and the k eigenfunctions (double): what grows
// with --sources and the mesh (100,000 sources on 100,000 vertices ran 8 s, then an unnamed "out of memory").
double spectral_mds_memory_bytes(Index n, const CanonicalFormOptions& options) {
  const double rows = static_cast<double>(std::min<Index>(options.spectral_mds.sources, n));
  const double basis = static_cast<double>(options.spectral_mds.laplacian.eigenpairs);
  return 12.0 * rows * static_cast<double>(n) + 8.0 * basis * static_cast<double>(n);
}

}  // namespace

CanonicalFormMethod spectral_mds_method() {
  CanonicalFormMethod m = spectral_method_base("spectral-mds");
  m.title = "spectral MDS";
  m.summary =
      "spectral MDS (Aflalo & Kimmel): classical MDS in the span of the first eigenfunctions, from the "
      "geodesic rows of farthest-point sources (--geodesics: their solver)";
  m.compute = spectral_mds_compute;
  m.memory_bytes = spectral_mds_memory_bytes;
  m.results_version = 2;  // 2: sources sampled from the central vertex, ties by position (not from vertex 0)
  using Ref = CanonicalFormOptions&;
  const std::vector<std::string> f = {"spectral_mds"};
  m.options = {laplacian_option(), near_multiple_gap_option(), geodesics_option(),  // geodesics: its rows' solver
               integer_option<int>("basis", "eigenfunctions k spanning the distances (the constant one included)",
                                   laplace_beltrami_limits::kEigenpairs, f,
                                   [](Ref c) -> int& { return c.spectral_mds.laplacian.eigenpairs; }),
               integer_option<Index>("sources", "geodesic rows L (farthest-point sources), at least --basis",
                                     spectral_mds_limits::kLandmarks, f,
                                     [](Ref c) -> Index& { return c.spectral_mds.sources; })};
  m.reads = {"geodesics", "spectral_mds"};
  m.check = [](const CanonicalFormOptions& o, const OptionFace& face) {
    const Index sources = o.spectral_mds.sources, basis = o.spectral_mds.laplacian.eigenpairs;
    if (sources < basis)
      fail(face.cli ? "--sources (" : "sources (", sources, ") must be at least ", face.cli ? "--basis (" : "basis (",
           basis, ")");
  };
  return m;
}

}  // namespace cshapes
