// The options of `--method lbo|diffusion|spectral-mds`: spectral canonical forms from the Laplace–Beltrami
// eigenpairs (canon/spectral_embedding.h, canon/spectral_mds.h); pipeline/canonical_forms.h computes them. The
// eigenpair options are in the lbo group and serve diffusion too, --laplacian and --near-multiple-gap also
// spectral-mds (whose basis is --basis; CLI11 needs each name once). Point clouds use the kNN graph of
// --knn (cli/main.cpp: an option of every method).
#include "cshapes/canon/spectral_embedding.h"
#include "cli/command.h"

namespace cshapes::cli {
namespace {

struct SpectralArgs {
  LaplaceBeltramiOptions laplacian;  // the library's defaults
  std::string operator_name = "intrinsic-delaunay";
  double time = DiffusionFormOptions{}.time;
  SpectralMdsOptions spectral_mds;  // the library's defaults
} args;

const std::vector<std::string> kLaplacians = {"intrinsic-delaunay", "cotangent"};

void configure_laplacian(CanonicalFormOptions& o, bool /*single_mesh*/) {
  LaplaceBeltramiOptions laplacian = args.laplacian;
  laplacian.intrinsic_delaunay = args.operator_name == "intrinsic-delaunay";
  o.lbo.laplacian = laplacian;
  o.diffusion.laplacian = laplacian;
}

void configure_diffusion(CanonicalFormOptions& o, bool /*single_mesh*/) {
  o.diffusion.time = args.time;
}

void configure_spectral_mds(CanonicalFormOptions& o, bool /*single_mesh*/) {
  o.spectral_mds = args.spectral_mds;
  o.spectral_mds.laplacian.intrinsic_delaunay = args.operator_name == "intrinsic-delaunay";
  o.spectral_mds.laplacian.near_multiple_gap = args.laplacian.near_multiple_gap;
}

const bool lbo_registered = register_canon_method(
    {"lbo",
     "Laplace-Beltrami eigenmap (GPS): sqrt(area) * phi_i / sqrt(lambda_i), i = 1..3",
     [](CLI::Option_group& g) {
       g.add_option("--laplacian", args.operator_name,
                    "lbo/diffusion: cotangent Laplacian on the intrinsic-delaunay triangulation or on the "
                    "mesh's own triangles (cotangent); point clouds use their kNN graph")
           ->capture_default_str()
           ->check(one_of(kLaplacians));
       g.add_option("--eigenpairs", args.laplacian.eigenpairs,
                    "lbo/diffusion: eigenpairs computed, the constant one included (the form uses 3; the "
                    "rest detect near-multiple eigenvalues)")
           ->capture_default_str()
           ->check(within(laplace_beltrami_limits::kEigenpairs));
       g.add_option("--near-multiple-gap", args.laplacian.near_multiple_gap,
                    "lbo/diffusion: report consecutive eigenvalues closer than this relative gap")
           ->capture_default_str()
           ->check(within(laplace_beltrami_limits::kNearMultipleGap));
     },
     configure_laplacian,
     {"diffusion", "spectral-mds"}});

const bool diffusion_registered = register_canon_method(
    {"diffusion",
     "diffusion map exp(-lambda_i t) phi_i at t = c / lambda_1 (scale-free), in the mesh's units",
     [](CLI::Option_group& g) {
       g.add_option("--diffusion-time", args.time, "diffusion: c in t = c / lambda_1")
           ->capture_default_str()
           ->check(within(spectral_limits::kDiffusionTime));
     },
     configure_diffusion});

const bool spectral_mds_registered = register_canon_method(
    {"spectral-mds",
     "spectral MDS (Aflalo & Kimmel): classical MDS in the span of the first eigenfunctions, from the "
     "geodesic rows of farthest-point sources (--geodesics: their solver)",
     [](CLI::Option_group& g) {
       g.add_option("--basis", args.spectral_mds.laplacian.eigenpairs,
                    "spectral-mds: eigenfunctions k spanning the distances (the constant one included)")
           ->capture_default_str()
           ->check(within(laplace_beltrami_limits::kEigenpairs));
       g.add_option("--sources", args.spectral_mds.sources,
                    "spectral-mds: geodesic rows L (farthest-point sources), at least --basis")
           ->capture_default_str()
           ->check(within(spectral_mds_limits::kLandmarks));
     },
     configure_spectral_mds,
     {},
     [] {
       if (args.spectral_mds.sources < args.spectral_mds.laplacian.eigenpairs)
         usage_fail("--sources (", args.spectral_mds.sources, ") must be at least --basis (",
                    args.spectral_mds.laplacian.eigenpairs, ")");
     }});

}  // namespace
}  // namespace cshapes::cli
