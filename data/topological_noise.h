// Topological noise the paper's way (§3, Results): "adding faces to connect between almost-touching vertices
// with large geodesic and small Euclidean distances". Each glue joins two surface spots by a short tube,
// adding one handle.
//
// Which pairs qualify (a, b vertices of the input):
//   |v_a - v_b| ≤ max_gap                                   (almost touching)
//   g(a, b) ≥ min_ratio · |v_a - v_b|  and  g(a, b) ≥ min_geodesic_fraction · diameter   (far apart on the
//   surface) n_a · (v_b - v_a) ≥ min_facing |v_b - v_a|, and the same at b   (the gap between them is outside
//   the shape) the tube's edges cross no face of the mesh
// g is geodesic_distances(...) (GeodesicOptions), measured on the mesh as glued so far, so later glues cannot
// use an earlier tube as a shortcut; diameter is the geodesic diameter estimated by farthest-point sweeps.
// Among the admissible pairs, shorter gaps are preferred, with a random factor drawn from the seed so that
// different seeds glue different places; spots are kept min_separation_fraction · diameter apart
// (geodesically), halving that separation when the shape offers too few places.
//
// The tube: at each end one triangle incident to the vertex (the one facing the other end) is removed, and
// the two triangular holes are bridged by a strip of 6 triangles (a prism without caps), oriented like the
// mesh. So every glue adds 0 vertices, 6 edges and 4 faces: χ drops by exactly 2, the mesh stays an oriented
// manifold, and vertex indices are unchanged (ground-truth correspondences of the input stay valid).
// Cost: O(n log n) per landmark and per candidate checked (Dijkstra), O(n + pairs) for the candidate sweep.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/support/option_limits.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// The smallest min_ratio accepted (a geodesic is never shorter than the straight line).
constexpr double kMinGlueRatioFloor = 1.0;

// The limits of the options a user sets (support/option_limits.h: the library's check, `cshapes noise` and
// add_topological_noise() all read these), named as on the command line.
namespace noise_limits {
inline constexpr Limit kGlue = integer_limit("glue", 0, 10000);
inline constexpr Limit kMaxGap = number_limit("max-gap", 0);
inline constexpr Limit kGapEdges = number_limit("gap-edges", 0, kNoLimit, /*minimum_open=*/true);
inline constexpr Limit kMinRatio = number_limit("min-ratio", kMinGlueRatioFloor);
inline constexpr Limit kMinFraction = number_limit("min-fraction", 0, 1);
inline constexpr Limit kSeparation = number_limit("separation", 0, 1);
inline constexpr Limit kRelax = integer_limit("relax", 0, 100);
}  // namespace noise_limits

// The options a user sets, each declared once (support/option_declaration.h): `cshapes noise`'s flags and
// add_topological_noise()'s keywords, with one help text.
namespace noise_options {
inline const OptionDeclaration kGlue{
    "glue", "--glue", "tubes to add, K (each adds a handle: the Euler characteristic drops by 2)",
    noise_limits::kGlue};
inline const OptionDeclaration kSeed{
    "seed", "--seed", "the seed that picks among the admissible pairs: the same seed, the same glues"};
inline const OptionDeclaration kMaxGap{
    "max_gap", "--max-gap",
    "the largest Euclidean gap a tube may bridge, in mesh units; 0: {gap_edges} mean edge lengths",
    noise_limits::kMaxGap};
inline const OptionDeclaration kGapEdges{
    "gap_edges", "--gap-edges", "the gap when {max_gap} is 0, in mean edge lengths", noise_limits::kGapEdges};
inline const OptionDeclaration kMinRatio{
    "min_ratio", "--min-ratio",
    "a glued pair's geodesic distance is at least this many times its Euclidean one",
    noise_limits::kMinRatio};
inline const OptionDeclaration kMinFraction{
    "min_fraction", "--min-fraction",
    "a glued pair's geodesic distance is at least this fraction of the geodesic diameter",
    noise_limits::kMinFraction};
inline const OptionDeclaration kSeparation{
    "separation", "--separation",
    "glued spots at least this fraction of the geodesic diameter apart (halved when the shape offers too few "
    "places)",
    noise_limits::kSeparation};
inline const OptionDeclaration kRelax{
    "relax", "--relax",
    "when too few pairs qualify, up to this many times widen the gap 1.5x and lower the ratio 0.8x",
    noise_limits::kRelax};
inline const OptionDeclaration kGeodesics{"geodesics", "--geodesics",
                                          "the geodesic method that measures the pairs: graph (Dijkstra on "
                                          "the edges, the fastest), heat, heat-cgal, "
                                          "fmm (fast marching) or exact",
                                          std::nullopt, geodesic_method_names()};
// In the order `cshapes noise --help` lists them.
inline const std::vector<const OptionDeclaration*> kAll = {
    &kGlue, &kSeed, &kMaxGap, &kGapEdges, &kMinRatio, &kMinFraction, &kSeparation, &kRelax, &kGeodesics};
}  // namespace noise_options

struct TopologicalNoiseOptions {
  int glue_count = 1;                  // K: tubes to add (each adds one handle)
  std::uint64_t seed = 0;              // picks among admissible pairs; same seed, same result
  double max_gap = 0;                  // Euclidean gap allowed, mesh units; 0: gap_edge_lengths × mean edge
  double gap_edge_lengths = 6;         // default gap in mean edge lengths
  double min_ratio = 5;                // geodesic ≥ min_ratio × Euclidean
  double min_geodesic_fraction = 0.1;  // geodesic ≥ this × geodesic diameter
  double min_separation_fraction = 0.15;  // glued spots this × diameter apart (halved while too few places)
  double min_facing = 0.2;                // cosine: each vertex normal points this much towards the other end
  int landmarks = 24;     // farthest-point landmarks for the diameter and geodesic lower bounds
  int max_checks = 3000;  // geodesic evaluations before giving up on finding more pairs
  // How geodesic distances are computed: Dijkstra on the edges by default. The candidate search evaluates
  // up to max_checks sources and Dijkstra needs no set-up per source; it is an upper bound of the surface
  // distance (typically 5-10% longer), so min_ratio is met by the edge-path distance.
  GeodesicOptions geodesic = [] {
    GeodesicOptions g;
    g.method = GeodesicMethod::Graph;
    return g;
  }();
  // Where the shape offers fewer than K admissible pairs: retry up to this many times, each time widening the
  // gap ×1.5 and lowering min_ratio ×0.8 (not below 2). The result's max_gap and min_ratio say what was used.
  int relax_steps = 0;

  // Every field by name, for cache keys (support/option_fields.h). Self: TopologicalNoiseOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("glue_count", o.glue_count);
    visit("seed", o.seed);
    visit("max_gap", o.max_gap);
    visit("gap_edge_lengths", o.gap_edge_lengths);
    visit("min_ratio", o.min_ratio);
    visit("min_geodesic_fraction", o.min_geodesic_fraction);
    visit("min_separation_fraction", o.min_separation_fraction);
    visit("min_facing", o.min_facing);
    visit("landmarks", o.landmarks);
    visit("max_checks", o.max_checks);
    visit("geodesic", o.geodesic);
    visit("relax_steps", o.relax_steps);
  }
};

struct GluedPair {
  int a = -1, b = -1;                   // the almost-touching vertices (indices of input and output alike)
  std::array<int, 3> rim_a{}, rim_b{};  // the removed triangle at each end: the tube's rims (vertex indices)
  double euclidean = 0;                 // |v_a - v_b|
  double geodesic = 0;                  // g(a, b) on the mesh as glued before this pair
};

struct TopologicalNoiseResult {
  Mesh mesh;                     // same vertices as the input; faces: input minus 2K, plus 6K tube faces
  std::vector<GluedPair> pairs;  // in the order glued
  double max_gap = 0;            // the Euclidean threshold used
  double min_ratio = 0;          // the geodesic/Euclidean ratio used (after relax steps)
  int relax_steps_used = 0;
  double geodesic_diameter = 0;  // estimated geodesic diameter of the input
  double mean_edge_length = 0;
  double separation = 0;    // the separation finally in force (geodesic, mesh units)
  Index candidates = 0;     // pairs within the gap whose normals face each other
  int geodesic_checks = 0;  // geodesic evaluations made
};

// Glues options.glue_count pairs. The input must be a valid manifold mesh with one connected component
// (boundaries allowed). Throws cshapes::Error saying how many admissible pairs were found when fewer than K
// exist.
TopologicalNoiseResult glue_topological_noise(const Mesh& mesh, const TopologicalNoiseOptions& options);

// Topological noise as extra edges rather than faces (for methods that take an edge graph, e.g. the Coulomb
// iteration's rest lengths): up to `count` vertex pairs (i, j) closer than 8 mean edge lengths in space and
// at least 15 mean edge lengths apart along the edges (Dijkstra), all at one site: the closest such pair,
// then the closest pairs whose both ends lie within 8 mean edges of its ends, each vertex used once; like
// gluing a foot to a foot. Pairs within 10 hops of each other are never candidates (a cheap pre-filter: most
// near pairs are near along the surface too). Returns the bridges as edges (i < j), by increasing Euclidean
// length, ties by index; a bridge's rest length is its Euclidean length, as for an edge of added faces.
// V: n×3; E: the graph's edges. Throws cshapes::Error when no pair qualifies. Cost: a 10-hop search and a
// scan of later vertices per vertex, O(n²) distance tests, plus one Dijkstra per pair examined.
Edges glue_bridges(const Points& V, const Edges& E, int count);


}  // namespace cshapes
