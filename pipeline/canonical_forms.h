// Canonical forms of a mesh by any registered method (pipeline/canonical_form_methods.h), behind one call,
// and cached on disk.
//
//   coulomb  §2 of the paper (canon/coulomb.h): edge lengths only, O(n log n) per iteration
//   cmds     classical MDS (canon/classical_mds.h) of all-pairs geodesic distances
//   smacof   SMACOF (canon/smacof.h) of the same distances, initialised from classical MDS
//   lbo      eigenmap / GPS of the Laplace–Beltrami eigenpairs (canon/spectral_embedding.h)
//   diffusion  diffusion map at a time relative to the shape's own spectrum (canon/spectral_embedding.h)
//   spectral-mds  classical MDS in the span of the first eigenfunctions from sampled geodesic rows
//                 (canon/spectral_mds.h)
//
// Each method states what it needs of the mesh (canonical_form_requirements) and the mesh is repaired for it
// first (mesh/mesh_repair.h: Coulomb the largest component's edge graph, MDS a manifold surface without
// zero-area faces in one component), unless options.strict, which refuses a mesh that needs repair, naming
// its defects. The result always has the input's vertex count and order: vertices the repair dropped are NaN
// rows of X with valid = 0 (never a shorter result); a vertex split in two takes its first copy's position.
// Point clouds (no faces) use a symmetric kNN graph for the Coulomb constraints and for graph geodesics. The
// cache key is the mesh's content (coordinates and faces) plus every option that changes the result and that
// the method reads (canonical_form_key, built from the options' own field lists), so a cached form is never
// stale and a killed run resumes without recomputing finished shapes.
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cshapes/canon/classical_mds.h"
#include "cshapes/canon/coulomb.h"
#include "cshapes/canon/form_quality.h"
#include "cshapes/canon/landmark_mds.h"
#include "cshapes/canon/smacof.h"
#include "cshapes/canon/spectral_embedding.h"
#include "cshapes/canon/spectral_mds.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/knn_graph.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/data/cache.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `cshapes canon --strict` and strict= of canonical_form() and coulomb() (declared once,
// support/option_declaration.h): CanonicalFormOptions::strict for one mesh.
inline const OptionDeclaration kStrictFormOption{
    "strict", "--strict",
    "refuse a mesh the method would have to repair (non-manifold for MDS, several components, duplicate "
    "faces, ...) instead of repairing it (the summary's repair entry says what a repair did)"};

// SMACOF's start: classical MDS of the same distances ("cmds"), or the input's coordinates ("mesh").
enum class SmacofInit { ClassicalMds, Mesh };
// SMACOF's pair weights: uniform ("uniform"), or w_i·w_j from vertex areas ("area", canon/smacof.h's
// vertex_area_weights).
enum class SmacofWeights { Uniform, Area };
// The names above, in this order; parse_* throws cshapes::Error naming the known ones for any other name.
const std::vector<std::string>& smacof_init_names();
const std::vector<std::string>& smacof_weights_names();
SmacofInit parse_smacof_init(const std::string& name);
SmacofWeights parse_smacof_weights(const std::string& name);
std::string to_string(SmacofInit init);
std::string to_string(SmacofWeights weights);

struct CanonicalFormOptions {
  std::string method = "coulomb";  // a registered method's name: canonical_form_methods()
  CoulombCanonOptions coulomb;     // method coulomb (its defaults: docs/coulomb-defaults.md)
  // MDS: the geodesics behind them. Our heat method, the same default in `canon`, `distmat`, every
  // experiment and Python, so that one method gives one form from every command (9× the speed of CGAL's,
  // about 1% from exact geodesics: docs/results.md); fmm is the paper's [KS98].
  GeodesicOptions geodesics = [] {
    GeodesicOptions g;
    g.method = GeodesicMethod::Heat;
    return g;
  }();
  ClassicalMdsOptions cmds;  // method cmds, and the initialisation of smacof
  SmacofOptions smacof;      // method smacof
  SmacofInit smacof_init = SmacofInit::ClassicalMds;  // method smacof: its start
  // Method smacof: its pair weights (Area replaces smacof.vertex_weights by the mesh's vertex areas).
  SmacofWeights smacof_weights = SmacofWeights::Uniform;
  // cmds/smacof: the full n×n matrix or L landmark rows (canon/landmark_mds.h); auto picks landmarks above
  // 12,000 vertices or when the matrix would take more than half the available memory.
  MdsSolverOptions mds_solver;
  // cmds/smacof: read the all-pairs distances from this .bin (support/distance_matrix.h) instead of computing
  // geodesics; it has the input's or the repaired mesh's vertex count. For one mesh; empty: compute.
  std::string distances_file;
  KnnGraphOptions knn;  // point clouds: the graph that stands in for mesh edges
  LboFormOptions lbo;              // method lbo
  DiffusionFormOptions diffusion;  // method diffusion
  SpectralMdsOptions spectral_mds;  // method spectral-mds (its geodesic rows: `geodesics`)
  // The options of a method registered outside the library, by name (pipeline/method_options.h:
  // option_in_extra): the value's text.
  std::map<std::string, std::string> extra;
  ProgressFn progress;  // stages "geodesics", "coulomb"
  // One line per stage result ("coulomb: 620 iterations ..."), for a front end to print; none when unset.
  std::function<void(const std::string&)> note;
  bool strict = false;  // refuse a mesh that needs repair (throws, naming the defects) instead of repairing
  // A method from outside may give any point set (at least 4 points that span a plane) instead of one row per
  // vertex in the mesh's order: where nothing needs the correspondence (retrieval, distmat). Its quality is
  // then not measured (no edges to measure). A cached point set is refused where rows per vertex are needed.
  bool point_set = false;
  std::string name = "mesh";  // the mesh's name (its path) in messages; not part of the result

  // Every field by name, for cache keys (support/option_fields.h). Self: CanonicalFormOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("method", o.method);
    visit("coulomb", o.coulomb);
    visit("geodesics", o.geodesics);
    visit("cmds", o.cmds);
    visit("smacof", o.smacof);
    visit("smacof_init", o.smacof_init);
    visit("smacof_weights", o.smacof_weights);
    visit("mds_solver", o.mds_solver);
    visit("distances_file", o.distances_file, kFileContent);  // its content is the input, not its name
    visit("knn", o.knn);
    visit("lbo", o.lbo);
    visit("diffusion", o.diffusion);
    visit("spectral_mds", o.spectral_mds);
    visit("extra", o.extra);
    visit("progress", o.progress, kNoEffect);  // reports, computes nothing
    visit("note", o.note, kNoEffect);          // reports, computes nothing
    // Refuses (a mesh that needs repair, a geodesic fallback) instead of computing something else: a form it
    // lets through is the one computed without it.
    visit("strict", o.strict, kNoEffect);
    visit("point_set", o.point_set, kNoEffect);  // lets a form through, computes nothing else
    visit("name", o.name, kNoEffect);  // in messages only
  }
};

// What a method needs of its mesh (its registration's requirements): coulomb the edge graph, cmds and smacof
// a manifold surface. Throws naming the known methods for an unknown one.
MeshRequirements canonical_form_requirements(const std::string& method);
// The mesh a canonical form is computed on (repair_for with the method's requirements, options.name and
// strict): the vertices of a precomputed distance matrix D are this mesh's.
RepairedMesh repair_for_canonical_form(const Mesh& mesh, const CanonicalFormOptions& options);

// A precomputed distance matrix for the mesh repair_for_canonical_form gives: when D has the input's size
// (what `cshapes geodesics` writes), its rows and columns at the repaired vertices (vertex_map); otherwise D
// itself when it has the repaired mesh's size. Throws, naming `source`, for any other size.
DistanceMatrix distances_on_repaired_mesh(const DistanceMatrix& D, const RepairedMesh& repaired,
                                          const std::string& source);

// Whether an MDS form of a mesh of n vertices under `options` embeds landmark rows instead of the all-pairs
// matrix (mds_uses_landmarks with the memory available now; never with a distances_file, which is the
// matrix).
bool mds_uses_landmarks(const CanonicalFormOptions& options, Index n);

// The power of two a canonical form of `mesh` is computed at (the form is scaled back): 1 for a mesh whose
// largest bounding-box extent lies within [2^-20, 2^20]; otherwise the factor that brings it into [0.5, 1)
// (mesh/unit_scale.h). Every method is scale-equivariant to rounding within that range (tests/
// scale_invariance_test.cpp); beyond it float distances, squared lengths and areas underflow or overflow.
inline constexpr double kCanonicalFormLowestScale = 0x1p-21;
inline constexpr double kCanonicalFormHighestScale = 0x1p19;
double canonical_form_scale(const Mesh& mesh);

// Every method name canonical_form accepts, in registration order (pipeline/canonical_form_methods.h).
const std::vector<std::string>& canonical_form_methods();

struct CanonicalForm {
  Points X;                           // n×3, the input mesh's vertex order; NaN rows where valid is 0
  Eigen::VectorXd valid;              // n: 1 for vertices in the form, 0 for vertices the repair dropped
  Eigen::VectorXd torn;               // coulomb: 1 for vertices of torn edges, else 0; empty for MDS
  std::vector<RepairAction> repairs;  // what was repaired before the method ran; empty: nothing
  std::string repair_text;            // one line (mesh/mesh_repair.h), "" when nothing was repaired
  double precompute_seconds = 0;      // geodesics (MDS) or edge lengths and graph (coulomb)
  double solve_seconds = 0;           // the embedding itself
  int iterations = 0;
  double seconds_per_iteration = 0;
  // Per-iteration history as columns (coulomb: energy, mean_violation, ...; smacof: normalized_stress).
  std::vector<std::string> history_columns;
  std::vector<std::vector<double>> history_rows;
  // Its quality (canon/form_quality.h), the same check for every method, made in one place: canonical_form()
  // (canonical_form_quality) from the method's mesh, its edge graph, the form and the two fields below.
  // Empty for a form of a distance matrix alone (classical_mds_form, smacof_form: no mesh).
  std::optional<FormQuality> quality;
  // What only the method knows for that check: the edges it tore (coulomb: vertex pairs of the mesh it was
  // given), left out of the stretch statistics; a breakdown its coordinates cannot show ("normalised stress
  // nan": SMACOF's iteration broke down), which fails the check.
  Edges torn_edges;
  std::string breakdown;
  // The method's own record, a JSON object: coulomb {vertices, edges, torn_edges, iterations, converged,
  // stop_reason, energy, mean/max_violation, ...}; cmds {classical_mds}; smacof {classical_mds, smacof};
  // lbo, diffusion, spectral-mds {laplacian, eigenvalues, ...}; {warning} when the heat method is too coarse
  // or λ3 and λ4 are near-multiple, {computed_at_scale} for a mesh far from unit size. form_summary_json
  // serialises it with the quality: what `canon --json`, Python's summary and the cache hold.
  nlohmann::json details = nlohmann::json::object();
  // MDS: "" when the geodesics were computed by the method asked for; otherwise which method failed on this
  // mesh, its message and the method used instead ("heat geodesics failed (...); fmm instead"). Unless
  // strict, a heat method (heat, heat-cgal) that throws falls back to fast marching; the form is cached
  // under the options asked for (the heat method would fail the same way again).
  std::string geodesics_fallback;
};

// The form's summary as `canon --json`, Python's summary and the cache hold it: its details with
// {form_quality} (pipeline/form_quality_json.h) when measured.
nlohmann::json form_summary_json(const CanonicalForm& form);
// The form's quality: form_quality (canon/form_quality.h) of `mesh` (the mesh the method computed on), its
// constraint edges (constraint_edges: mesh edges, or a point cloud's kNN graph) without form.torn_edges, and
// form.X; failed with form.breakdown when the method gave one.
FormQuality canonical_form_quality(const Mesh& mesh, const CanonicalFormOptions& options,
                                   const CanonicalForm& form);

// Computes the canonical form. D: optional precomputed all-pairs distances for MDS between the vertices of
// repair_for_canonical_form(mesh, options).mesh (the mesh itself when it needs no repair), reused instead
// of computing geodesics (e.g. one matrix shared by cmds and smacof); D_seconds: what computing it took,
// reported as the form's precompute_seconds.
// D_fallback: D's geodesics_fallback (what cached_canonical_forms's shared matrix fell back from).
CanonicalForm canonical_form(const Mesh& mesh, const CanonicalFormOptions& options,
                             const DistanceMatrix* D = nullptr, double D_seconds = 0,
                             const std::string& D_fallback = {});

// Forms of a distance matrix alone (no mesh: no repair, no form quality), described as canonical_form
// describes its MDS forms (summary {classical_mds} or {smacof}, SMACOF's history): the Python module's
// classical_mds() and smacof().
CanonicalForm classical_mds_form(const ClassicalMdsResult& result);
CanonicalForm smacof_form(const SmacofResult& result, const SmacofOptions& options);

// The part of the cache key that depends on the options: options_key (support/option_fields.h) of the fields
// the method reads (method_reads_field: method, knn, its options' fields and its `reads`) that change the
// result: "method=\"cmds\";geodesics.method=fmm;...", then ";results-v2" for a method whose results_version
// is above 1 (pipeline/canonical_form_methods.h). Throws for an unknown method, and naming distances_file when
// it cannot be read.
std::string canonical_form_key(const CanonicalFormOptions& options);
// Content key of a mesh: SHA-256 of its coordinates and faces.
std::string mesh_content_key(const Mesh& mesh);

// canonical_form through a DiskCache (a disabled cache computes every time). *was_cached tells which.
// The cache key of that form.
CanonicalForm cached_canonical_form(const DiskCache& cache, const Mesh& mesh,
                                    const CanonicalFormOptions& options, bool* was_cached = nullptr,
                                    const DistanceMatrix* D = nullptr, double D_seconds = 0,
                                    const std::string& D_fallback = {});
std::string canonical_form_cache_key(const Mesh& mesh, const CanonicalFormOptions& options);

// One mesh's canonical forms by several methods (options[k].method each), through the cache. The methods that
// use the all-pairs geodesic matrix (cmds, smacof) with the same geodesic options share one matrix, computed
// only when one of their forms is missing from the cache (each form computed from it reports its cost as its
// pre-computation): what `experiment paper`, `noise`, `topkids` and `pose` do for every shape.
struct CachedForm {
  CanonicalForm form;
  std::string key;      // canonical_form_cache_key
  bool cached = false;  // read from the cache
  double seconds = 0;   // wall time of this form's call, the shared matrix included
};
// `base` once per method (method set, name = the mesh's name, no progress or note): cached_canonical_forms's
// options for one mesh.
std::vector<CanonicalFormOptions> options_per_method(const CanonicalFormOptions& base,
                                                     const std::vector<std::string>& methods,
                                                     const std::string& name);
// at (when non-null): the index of the method being computed, so when this throws, the one that failed.
std::vector<CachedForm> cached_canonical_forms(const DiskCache& cache, const Mesh& mesh,
                                               const std::vector<CanonicalFormOptions>& options,
                                               size_t* at = nullptr);

// Tests only: called with the geodesic method and the mesh's name before every all-pairs geodesic matrix of
// an MDS form (the fallback's too); it may throw cshapes::Error to make a method fail. Empty: none (default).
void set_geodesics_test_hook(std::function<void(GeodesicMethod, const std::string&)> hook);

}  // namespace cshapes
