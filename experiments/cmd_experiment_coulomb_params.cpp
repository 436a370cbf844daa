// cshapes experiment coulomb-params --data DIR --out DIR [--shapes cat0,michael0] [--configs a,b] [--bridges K]
//
// The parameter study behind the Coulomb defaults. For every shape and every configuration (the defaults with
// one choice changed: k, step rule, L1/L2, tearing time/fraction, scheme), it canonizes the clean shape and a
// glued version of it — the same vertices with K bridge edges between vertex pairs that are close in space but
// far along the surface (the paper's topological noise) — and records the violation, the energy, iterations,
// time, how many bridges were torn, and the RMS distance between the glued and the clean canonical forms after
// rigid alignment (same vertex order), relative to the clean form's bounding-box diagonal. With --partners, it
// also canonizes another pose of the same class and measures pose invariance: the RMS distance between
// ground-truth corresponding samples (corres/*.vts) of the two canonical forms after rigid alignment, beside the
// same for the two input poses.
// Writes OUT/coulomb_params.csv and OUT/coulomb_params.md (also printed).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <queue>
#include <sstream>

#include "canon/coulomb.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/geodesics.h"
#include "core/io.h"
#include "experiments/command.h"

namespace cshapes::cli {
namespace {

struct StudyArgs {
  std::string data, out;
  std::string shapes = "cat0,michael0";
  std::string partners = "cat1,michael1";  // another pose of each shape's class, for the pose-invariance column
  std::string configs = "all";
  int bridges = 8;
  int max_iterations = 600;
} args;

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) parts.push_back(item);
  }
  return parts;
}

// Bridges: K vertex pairs (i, j) closer than 8 mean edges in space whose graph distance is at least 15 mean
// edges, all at one site (the closest such pair and the pairs near it): like gluing a foot to a foot.
// The bridge's rest length is its Euclidean length, as for an edge of added faces.
Edges glue_bridges(const Points& V, const Edges& E, int count) {
  const Index n = V.rows();
  const Eigen::VectorXd lengths = edge_lengths(V, E);
  const double h = lengths.mean();
  const Adjacency adj = adjacency(n, E);
  // Hop-limited BFS rejects the pairs that are near along the surface (most near pairs) cheaply.
  const int hops = 10;
  struct Pair {
    double distance;
    int i, j;
  };
  std::vector<Pair> pairs;
  std::vector<int> seen(n, -1);
  for (Index i = 0; i < n; ++i) {
    std::vector<int> frontier{static_cast<int>(i)};
    seen[i] = static_cast<int>(i);
    for (int hop = 0; hop < hops; ++hop) {
      std::vector<int> next;
      for (int v : frontier)
        for (int k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k)
          if (seen[adj.neighbors[k]] != i) {
            seen[adj.neighbors[k]] = static_cast<int>(i);
            next.push_back(adj.neighbors[k]);
          }
      frontier.swap(next);
    }
    for (Index j = i + 1; j < n; ++j) {
      if (seen[j] == i) continue;
      const double d = (V.row(i) - V.row(j)).norm();
      if (d < 8 * h) pairs.push_back({d, static_cast<int>(i), static_cast<int>(j)});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return a.distance != b.distance ? a.distance < b.distance : (a.i != b.i ? a.i < b.i : a.j < b.j);
  });
  std::vector<Pair> chosen;
  std::vector<char> used(n, 0);
  for (const Pair& p : pairs) {
    if (static_cast<int>(chosen.size()) >= count) break;
    if (used[p.i] || used[p.j]) continue;
    if (!chosen.empty()) {
      // Same site as the first bridge: both ends near its ends.
      const Pair& f = chosen.front();
      if ((V.row(p.i) - V.row(f.i)).norm() > 8 * h && (V.row(p.i) - V.row(f.j)).norm() > 8 * h) continue;
      if ((V.row(p.j) - V.row(f.i)).norm() > 8 * h && (V.row(p.j) - V.row(f.j)).norm() > 8 * h) continue;
    }
    const Eigen::VectorXd graph = dijkstra(n, adj, lengths, {p.i});
    if (graph(p.j) < 15 * h) continue;
    chosen.push_back(p);
    used[p.i] = used[p.j] = 1;
  }
  CSHAPES_REQUIRE(!chosen.empty(), "coulomb-params: found no vertex pair to glue");
  Edges bridges(static_cast<Index>(chosen.size()), 2);
  for (size_t k = 0; k < chosen.size(); ++k)
    bridges.row(static_cast<Index>(k)) << std::min(chosen[k].i, chosen[k].j), std::max(chosen[k].i, chosen[k].j);
  return bridges;
}

// corres/NAME.vts: one 1-based vertex index per common sample of the class.
std::vector<int> read_correspondence(const std::string& path) {
  std::ifstream in(path);
  CSHAPES_REQUIRE(in, path, ": cannot open (ground-truth correspondence of the shape)");
  std::vector<int> samples;
  int index = 0;
  while (in >> index) samples.push_back(index - 1);
  CSHAPES_REQUIRE(!samples.empty(), path, ": no vertex indices");
  return samples;
}

// RMS distance between corresponding samples of two shapes after rigid alignment, over A's bbox diagonal:
// 0 when the two poses have the same canonical form up to a rigid motion.
double pose_distance(const Points& A, const std::vector<int>& a, const Points& B, const std::vector<int>& b) {
  CSHAPES_REQUIRE(a.size() == b.size(), "correspondences of different lengths: ", a.size(), " vs ", b.size());
  Points SA(static_cast<Index>(a.size()), 3), SB(static_cast<Index>(b.size()), 3);
  for (size_t s = 0; s < a.size(); ++s) {
    SA.row(static_cast<Index>(s)) = A.row(a[s]);
    SB.row(static_cast<Index>(s)) = B.row(b[s]);
  }
  return rigid_rms_distance(SB, SA) / bbox_diagonal(A);
}

struct Config {
  std::string name;
  std::function<void(CoulombCanonOptions&)> apply;
};

std::vector<Config> all_configs() {
  return {
      {"default", [](CoulombCanonOptions&) {}},
      {"paper-1/1", [](CoulombCanonOptions& o) {
         o.scheme = CoulombScheme::Paper;
         o.step_rule = CoulombStepRule::MaxEdge;
         o.projection.steps = 1;
       }},
      {"scheme=paper", [](CoulombCanonOptions& o) { o.scheme = CoulombScheme::Paper; }},
      {"k=1", [](CoulombCanonOptions& o) { o.projection.steps = 1; }},
      {"k=3", [](CoulombCanonOptions& o) { o.projection.steps = 3; }},
      {"k=30", [](CoulombCanonOptions& o) { o.projection.steps = 30; }},
      {"k=100", [](CoulombCanonOptions& o) { o.projection.steps = 100; }},
      {"step=max-edge", [](CoulombCanonOptions& o) { o.step_rule = CoulombStepRule::MaxEdge; }},
      {"step=mean-edge", [](CoulombCanonOptions& o) { o.step_rule = CoulombStepRule::MeanEdge; }},
      {"step=median-edge", [](CoulombCanonOptions& o) { o.step_rule = CoulombStepRule::MedianEdge; }},
      {"step=max-edge,k=100", [](CoulombCanonOptions& o) {
         o.step_rule = CoulombStepRule::MaxEdge;
         o.projection.steps = 100;
       }},
      {"factor=0.3,k=30", [](CoulombCanonOptions& o) {
         o.step_factor = 0.3;
         o.projection.steps = 30;
       }},
      {"momentum=0.97", [](CoulombCanonOptions& o) { o.momentum = 0.97; }},
      {"l1", [](CoulombCanonOptions& o) { o.projection.norm = ProjectionNorm::L1; }},
      {"tear=50", [](CoulombCanonOptions& o) { o.tear_after = 50; }},
      {"tear=150", [](CoulombCanonOptions& o) { o.tear_after = 150; }},
      {"tear=200", [](CoulombCanonOptions& o) { o.tear_after = 200; }},
      {"tear=200 x3/30", [](CoulombCanonOptions& o) {
         o.tear_after = 200;
         o.tear_interval = 30;
       }},
      {"tear=convergence", [](CoulombCanonOptions& o) { o.tear_after = 1000000; }},
      {"p=0.5%", [](CoulombCanonOptions& o) { o.tear_fraction = 0.005; }},
      {"p=2%", [](CoulombCanonOptions& o) { o.tear_fraction = 0.02; }},
      {"tear once", [](CoulombCanonOptions& o) { o.tear_times = 1; }},
      {"tear x3/100", [](CoulombCanonOptions& o) { o.tear_interval = 100; }},
      {"no tearing", [](CoulombCanonOptions& o) { o.tear_fraction = 0; }},
      {"guard=vertex", [](CoulombCanonOptions& o) { o.tear_guard = TearGuard::Vertex; }},
      // The fast summation's accuracy during the iterations (relative L2 error of the gradient).
      {"accuracy=3e-4", [](CoulombCanonOptions& o) { o.energy.accuracy = 3e-4; }},
      {"accuracy=1e-3", [](CoulombCanonOptions& o) { o.energy.accuracy = 1e-3; }},
      {"accuracy=3e-3", [](CoulombCanonOptions& o) { o.energy.accuracy = 3e-3; }},
      {"accuracy=1e-2", [](CoulombCanonOptions& o) { o.energy.accuracy = 1e-2; }},
  };
}

int run() {
  std::vector<Config> configs;
  const std::vector<Config> known = all_configs();
  if (args.configs == "all") {
    configs = known;
  } else {
    for (const std::string& name : split(args.configs)) {
      auto it = std::find_if(known.begin(), known.end(), [&](const Config& c) { return c.name == name; });
      if (it == known.end()) {
        std::string names;
        for (const Config& c : known) names += (names.empty() ? "" : ", ") + c.name;
        fail("unknown --configs entry '", name, "'; known: ", names);
      }
      configs.push_back(*it);
    }
  }
  const std::vector<std::string> columns = {
      "shape",      "config",        "iterations",     "seconds",         "converged",       "energy",
      "mean_violation", "max_violation", "glued_iterations", "glued_seconds", "bridges", "bridges_torn",
      "glued_rms_to_clean", "pose_rms", "input_pose_rms"};
  std::vector<std::vector<std::string>> rows;
  const std::vector<std::string> shapes = split(args.shapes), partners = split(args.partners);
  CSHAPES_REQUIRE(partners.empty() || partners.size() == shapes.size(), "--partners needs one pose per shape (",
                  shapes.size(), "), or none");
  for (size_t si = 0; si < shapes.size(); ++si) {
    const std::string& shape = shapes[si];
    const std::string path = args.data + "/" + shape + ".off";
    const Mesh mesh = read_mesh(path);
    Mesh partner;
    std::vector<int> corr, partner_corr;
    double input_pose = -1;
    if (!partners.empty()) {
      partner = read_mesh(args.data + "/" + partners[si] + ".off");
      corr = read_correspondence(args.data + "/corres/" + shape + ".vts");
      partner_corr = read_correspondence(args.data + "/corres/" + partners[si] + ".vts");
      input_pose = pose_distance(mesh.V, corr, partner.V, partner_corr);
    }
    const Edges clean = mesh_edges(mesh.F);
    const Edges bridges = glue_bridges(mesh.V, clean, args.bridges);
    Edges glued(clean.rows() + bridges.rows(), 2);
    glued << clean, bridges;
    {
      std::ostringstream where;
      for (Index k = 0; k < bridges.rows(); ++k)
        where << " (" << bridges(k, 0) << "," << bridges(k, 1) << ": "
              << (mesh.V.row(bridges(k, 0)) - mesh.V.row(bridges(k, 1))).norm() << ")";
      note(shape + ": " + std::to_string(bridges.rows()) + " bridges glued between vertices (i,j: length)" +
           where.str() + "; mean edge " + std::to_string(edge_lengths(mesh.V, clean).mean()));
    }
    for (const Config& config : configs) {
      CoulombCanonOptions o;
      o.max_iterations = args.max_iterations;
      config.apply(o);
      const CoulombCanonResult a = coulomb_canonical_form(mesh.V, clean, o);
      const CoulombCanonResult b = coulomb_canonical_form(mesh.V, glued, o);
      int torn_bridges = 0;
      for (Index t = 0; t < b.torn_edges.rows(); ++t)
        for (Index k = 0; k < bridges.rows(); ++k)
          if (b.torn_edges.row(t) == bridges.row(k)) ++torn_bridges;
      const double rms = rigid_rms_distance(b.X, a.X) / bbox_diagonal(a.X);
      double pose = -1;
      if (!partners.empty()) {
        const CoulombCanonResult c = coulomb_canonical_form(partner.V, mesh_edges(partner.F), o);
        pose = pose_distance(a.X, corr, c.X, partner_corr);
      }
      auto fmt = [](double v, int precision) {
        std::ostringstream s;
        s.precision(precision);
        s << v;
        return s.str();
      };
      rows.push_back({shape, config.name, std::to_string(a.iterations), fmt(a.seconds, 3),
                      a.converged ? "yes" : "no", fmt(a.energy, 6), fmt(a.violation.mean_relative, 3),
                      fmt(a.violation.max_relative, 3), std::to_string(b.iterations), fmt(b.seconds, 3),
                      std::to_string(bridges.rows()), std::to_string(torn_bridges), fmt(rms, 3), fmt(pose, 3),
                      fmt(input_pose, 3)});
      note(shape + " / " + config.name + ": " + rows.back()[2] + " it, violation " + rows.back()[6] +
           ", bridges torn " + rows.back()[11] + "/" + rows.back()[10] + ", glued vs clean RMS " + rows.back()[12] +
           ", pose RMS " + rows.back()[13] + " (input " + rows.back()[14] + ")");
    }
  }
  write_file_atomically(args.out + "/coulomb_params.csv", [&](std::ostream& out) {
    for (size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
    out << '\n';
    for (const auto& row : rows) {
      for (size_t c = 0; c < row.size(); ++c) out << (c ? "," : "") << row[c];
      out << '\n';
    }
  });
  std::ostringstream md;
  md << "| shape | config | iterations | s | converged | energy | mean viol. | max viol. | glued it. | glued s "
        "| bridges torn | glued vs clean RMS | pose RMS (input) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    md << "| " << r[0] << " | " << r[1] << " | " << r[2] << " | " << r[3] << " | " << r[4] << " | " << r[5]
       << " | " << r[6] << " | " << r[7] << " | " << r[8] << " | " << r[9] << " | " << r[11] << "/" << r[10]
       << " | " << r[12] << " | " << r[13] << " (" << r[14] << ") |\n";
  write_file_atomically(args.out + "/coulomb_params.md", [&](std::ostream& out) { out << md.str(); });
  std::cout << md.str();
  return 0;
}

const bool registered = register_command(
    {{"experiment", "coulomb-params"},
     "Parameter study of the Coulomb canonization on clean and glued shapes (violation, energy, robustness)",
     [](CLI::App& app) {
       app.add_option("--data", args.data, "folder of OFF shapes (e.g. ../shared/data/tosca5k)")->required();
       app.add_option("--out", args.out, "output folder for coulomb_params.csv/.md")->required();
       app.add_option("--shapes", args.shapes, "comma-separated shape names")->capture_default_str();
       app.add_option("--configs", args.configs, "comma-separated configuration names, or all")
           ->capture_default_str();
       app.add_option("--partners", args.partners,
                      "comma-separated other pose per shape (same class, corres/*.vts), '' for none")
           ->capture_default_str();
       app.add_option("--bridges", args.bridges, "bridge edges glued per shape")->capture_default_str();
       app.add_option("--max-iterations", args.max_iterations, "iteration cap per run")->capture_default_str();
     },
     run});

}  // namespace
}  // namespace cshapes::cli
