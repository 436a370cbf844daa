// The canonical-form methods, each registered once with everything the rest of cshapes asks of a method: its
// name (CanonicalFormOptions::method, `--method`, Python's method=), its title in figures and tables, what it
// needs of its mesh, whether it embeds the all-pairs geodesic matrix, which options it does not read (left
// out of its cache key), and its computation. canonical_form() (pipeline/canonical_forms.h) dispatches
// through this list; the CLI, the Python module and the experiments take their method names from it.
//
//   name     title          file                         computes
//   coulomb  Coulomb        pipeline/method_coulomb.cpp  §2 of the paper (canon/coulomb.h): edge lengths only
//   cmds     classical MDS  pipeline/method_mds.cpp      classical MDS of all-pairs geodesic distances
//   smacof   SMACOF         pipeline/method_mds.cpp      SMACOF of the same distances
//   lbo      eigenmap (GPS) pipeline/method_lbo.cpp      Laplace–Beltrami eigenvectors scaled by 1/√λ
//   diffusion diffusion map pipeline/method_diffusion.cpp  e^{-λt}φ at t relative to the shape's spectrum
//   spectral-mds spectral MDS pipeline/method_spectral_mds.cpp  MDS in the first eigenfunctions' span
//
// Adding a method is one file: pipeline/method_NAME.cpp defining NAME_method() with its options (declared
// below, one line in canonical_form_method_registry()), or any file that registers it with
// register_canonical_form_method (tests/toy_method/method_toy.cpp). Its CLI option group, Python keywords,
// stub entries, cache key and refusals all come from that registration.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cshapes/geodesics/landmark_geodesics.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/method_options.h"
#include "cshapes/support/distance_matrix.h"

namespace cshapes {

// The all-pairs distances a method that uses the geodesic matrix embeds, when its caller already has them
// (read from options.distances_file, or one matrix shared by several methods: cached_canonical_forms).
struct GivenDistances {
  const DistanceMatrix* D = nullptr;  // n×n between the vertices of the mesh given to compute; null: compute
  double seconds = 0;                 // what computing them took: the form's precompute_seconds
  std::string fallback;               // their geodesics_fallback ("" when the method asked for was used)
};

struct CanonicalFormMethod {
  std::string name;               // "coulomb": CanonicalFormOptions::method, `--method`, Python's method=
  std::string title;              // "Coulomb": the one name of the method in figures, tables and reports
  std::string summary;            // one line: what it computes (`cshapes canon --help`)
  MeshRequirements requirements;  // what it needs of its mesh (mesh/mesh_repair.h)
  // Why, in repair messages: "Coulomb canonization (the largest component's edge graph)".
  std::string repair_purpose;
  // Embeds the all-pairs geodesic matrix (options.geodesics, or options.distances_file): its memory is
  // checked up front, and methods with the same geodesic options share one matrix.
  bool uses_geodesic_matrix = false;
  // Its options, each declared once (pipeline/method_options.h; one read by several methods is the same
  // declaration in each list). They make its CLI option group, its Python keywords and their stub, and the
  // refusal of the others' options.
  std::vector<MethodOption> options;
  // The top-level CanonicalFormOptions fields (for_each_field's names) it reads, besides the ones every
  // method reads (method, knn): {"geodesics", "cmds", "smacof", ...} for smacof, whose start is classical
  // MDS. Its cache key is those fields' values, so a field it reads but does not list would serve stale forms
  // (tests/options_key_test.cpp changes each field a method does not list and checks that its form stays);
  // each of its options sets one of them (checked there too).
  std::vector<std::string> reads;
  // Checks across its options (a count against another, an option that needs one mesh), worded for the
  // front end (`face`), before any work; after each option's own check. Null: none.
  std::function<void(const CanonicalFormOptions& options, const OptionFace& face)> check;
  // Fills CanonicalForm::history_columns/rows (Coulomb's energy, SMACOF's stress per iteration): `canon
  // --history` and Python's history are refused for the other methods, before any work.
  bool has_history = false;
  // Its forms mark the vertices of torn edges (CanonicalForm::torn): figures colour those instead of the
  // glued ones.
  bool marks_torn = false;
  // The version of its arithmetic: raised when a change of its code changes its forms under the same options,
  // so that forms cached before are not served (from 2 on it is part of the cache key: docs/design.md,
  // "Caches").
  int results_version = 1;
  // The memory that grows with the input beyond the mesh (bytes, for n vertices), checked by
  // canonical_form() before any work; null: nothing beyond what uses_geodesic_matrix covers.
  double (*memory_bytes)(Index n, const CanonicalFormOptions& options) = nullptr;
  // The form of `mesh` (already repaired for the method: repair_for_canonical_form), in its vertex order.
  // given: the distances when the caller has them (methods that use the geodesic matrix; ignored otherwise).
  // canonical_form() places the result back at the input's vertices.
  std::function<CanonicalForm(const Mesh& mesh, const CanonicalFormOptions& options, const GivenDistances& given)>
      compute;
  // A method from outside the library (pipeline/outside_methods.h): how it came in ("command", "forms",
  // "python"; "" for the library's own and for a program's register_canonical_form_method) and what it came
  // with (the command, the folder, the function), said in every report.
  std::string door;
  std::string door_text;
  // Appended to its cache key: what identifies its code when its options cannot (the command string and the
  // content of the files it names, a function's source, --method-version).
  std::string key_text;
  // Its forms are cached (false: forms read from a folder, where reading is the computation).
  bool cacheable = true;
  // It gets the mesh as the experiment has it (no repair, no rescaling) and returns one row per vertex: an
  // outside method's forms are checked against the mesh it was given, never repaired for it.
  bool takes_mesh_as_given = false;
};

// Every registered method, in registration order (coulomb, cmds, smacof, lbo, diffusion, spectral-mds, then
// those registered by register_canonical_form_method): the order of help texts and of the experiments'
// default method lists.
const std::vector<CanonicalFormMethod>& canonical_form_method_registry();
// Adds a method from outside the library (a static registrar in its own file, before main):
//   static const bool registered = register_canonical_form_method(toy_method());
// Throws for a name already registered or an option declared twice differently. Returns true.
bool register_canonical_form_method(CanonicalFormMethod method);
// A method from outside, registered for the length of a run (pipeline/outside_methods.h registers and
// removes them): found by name like the others, but not in canonical_form_method_registry() (not a default of
// any experiment). Registering a name in use by a built-in or by another outside method with a different
// key_text throws; the same name and key_text again counts one more user.
void register_outside_canonical_form_method(CanonicalFormMethod method);
void unregister_outside_canonical_form_method(const std::string& name);
// The outside methods registered now, in registration order.
std::vector<const CanonicalFormMethod*> outside_canonical_form_methods();
// The method registered under `name` (built-in first, then outside), or null.
const CanonicalFormMethod* find_canonical_form_method(const std::string& name);
// The method registered under `name`; throws cshapes::Error "unknown canonization method 'x'; known:
// coulomb, cmds, smacof" otherwise.
const CanonicalFormMethod& canonical_form_method(const std::string& name);
// The registered names joined by `separator`: "coulomb, cmds, smacof" (help texts, errors), "coulomb,cmds,
// smacof" (an option's default).
std::string canonical_form_method_list(const std::string& separator = ", ");
// Checks a list of method names (an experiment's, a command line's): each must be registered. Throws
// cshapes::Error "<context>: unknown canonization method 'x'; known: coulomb, cmds, smacof" at the first that
// is not. An empty list passes (the callers that need a method say so themselves).
void require_canonical_form_methods(const std::vector<std::string>& methods, const std::string& context);
// A method's title ("classical MDS" for cmds); a name that is no method's (e.g. "inputs") as it is.
std::string canonical_form_method_title(const std::string& name);

// Which method reads which option, from the methods' own lists. Whether `method` reads the top-level field
// (method and knn: every method; then its `reads`).
bool method_reads_field(const CanonicalFormMethod& method, const std::string& field);
// Whether `method` lists the option named `name` (Python's keyword name).
bool method_reads_option(const CanonicalFormMethod& method, const std::string& name);
// Every option of every registered method, each once (by name), in registration order.
std::vector<const MethodOption*> all_method_options();
// The registered methods for which `predicate` holds, in registration order.
std::vector<std::string> canonical_form_methods_where(
    const std::function<bool(const CanonicalFormMethod&)>& predicate);
// The registered methods that list the option `name`: {"cmds", "smacof", "spectral-mds"} for "geodesics".
std::vector<std::string> canonical_form_methods_reading(const std::string& name);
// Refuses (cshapes::Error, worded for `face`) an option given that none of `methods` lists, naming the
// methods that do: "--geodesics applies to --method cmds, smacof or spectral-mds only, not coulomb".
void refuse_options_not_read(const std::vector<std::string>& methods, const OptionFace& face);
// After the options given are set in `options`: each given option's applies_when, then the check of each of
// `methods` (cshapes::Error worded for `face`).
void check_method_options(const std::vector<std::string>& methods, const CanonicalFormOptions& options,
                          const OptionFace& face);
// Names as a message says them: "a", "a or b", "a, b or c", each between `quote`s.
std::string either_of(const std::vector<std::string>& names, const std::string& quote = "");

// The canonical-form options every experiment (paper, noise, topkids, pose) starts from: the library's
// defaults (heat geodesics for MDS, as a single canonical_form() call uses). The CLI, C++ and Python runs of
// an experiment start from these same options.
CanonicalFormOptions experiment_canonical_form_options();

// The registered methods (one file each; their only other mention is canonical_form_method_registry()).
CanonicalFormMethod coulomb_method();       // pipeline/method_coulomb.cpp
CanonicalFormMethod cmds_method();          // pipeline/method_mds.cpp
CanonicalFormMethod smacof_method();        // pipeline/method_mds.cpp
CanonicalFormMethod lbo_method();           // pipeline/method_lbo.cpp
CanonicalFormMethod diffusion_method();     // pipeline/method_diffusion.cpp
CanonicalFormMethod spectral_mds_method();  // pipeline/method_spectral_mds.cpp

// For the method files: what several methods share.
// --geodesics (GeodesicOptions::method): cmds, smacof and spectral-mds (its rows) read it.
MethodOption geodesics_option();
// The edges standing in for the mesh's: its triangle edges, or the kNN graph of a point cloud (no faces).
Edges constraint_edges(const Mesh& mesh, const KnnGraphOptions& knn);
// The all-pairs geodesic matrix of `mesh` (options.geodesics; a point cloud: graph distances on its kNN
// graph, which must be connected). Unless options.strict, a heat method that fails on this mesh falls back to
// fast marching; *fallback (when non-null) then says which failed and why. Refuses up front when the n×n
// floats do not fit in the available memory.
DistanceMatrix canonical_form_geodesics(const Mesh& mesh, const CanonicalFormOptions& options,
                                        std::string* fallback = nullptr);
// The landmark rows instead (options.mds_solver.landmarks by farthest-point sampling,
// geodesics/landmark_geodesics.h; a point cloud: graph distances on its kNN graph), with the same fallback.
LandmarkGeodesics canonical_form_landmark_geodesics(const Mesh& mesh, const CanonicalFormOptions& options,
                                                    std::string* fallback = nullptr);

}  // namespace cshapes
