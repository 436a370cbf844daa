#include "cshapes/experiments/paper_figures.h"

#include "cshapes/pipeline/experiment_kit.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cshapes/canon/coulomb.h"
#include "cshapes/data/articulated.h"
#include "cshapes/support/format.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/matching/icp.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"

namespace cshapes {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A mesh remeshed to `vertices`, cached by the input's content.
Mesh remeshed(const Mesh& mesh, Index vertices, const DiskCache& cache) {
  if (mesh.num_vertices() == vertices) return mesh;
  const std::string key = cache_key({"remesh-v1", mesh_content_key(mesh), std::to_string(vertices)});
  if (std::optional<json> hit = cache.get_json(key)) return mesh_from_json(*hit);
  RemeshOptions ro;
  ro.target_vertices = vertices;
  Mesh out = remesh(mesh, ro).mesh;
  cache.put_json(key, mesh_to_json(out));
  return out;
}

Eigen::VectorXd indicator(Index n, const std::vector<int>& vertices) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
  for (int i : vertices) v[i] = 1;
  return v;
}

// The shape of Figures 3 and 5: a female pose when the data has one (the paper shows one), else the first
// clean shape; remeshed to options.figure_vertices when that is > 0.
struct FigureShape {
  std::string name;
  Mesh mesh;
};
// left_out: shapes the experiment left out (pipeline/shape_failures.h), never chosen.
FigureShape figure_shape(const PaperExperimentOptions& o, const DiskCache& cache,
                         const std::vector<ShapeFailure>& left_out) {
  Dataset data = read_dataset(o.data, o.allow_outside);
  const DatasetEntry* chosen = nullptr;
  for (const DatasetEntry& e : data.entries) {
    if (e.noisy) continue;
    if (std::any_of(left_out.begin(), left_out.end(),
                    [&](const ShapeFailure& f) { return f.left_out() && f.path == e.path; }))
      continue;
    if (!chosen) chosen = &e;
    if (e.class_name == "victoria" || e.class_name == "female" || e.class_name == "woman") {
      chosen = &e;
      break;
    }
  }
  CSHAPES_REQUIRE(chosen, o.data, ": no clean shape for the figures");
  // As Coulomb and the remeshing need it: one manifold component (mesh/mesh_repair.h).
  Mesh mesh = repair_for(read_mesh(chosen->path), MeshRequirements::manifold_surface()).mesh;
  return {chosen->name, o.figure_vertices > 0 ? remeshed(mesh, o.figure_vertices, cache) : mesh};
}

}  // namespace

namespace {

// Figure 2: the hand with separated and glued fingers, canonical forms by every method, ICP overlay.
void figure2_hand(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& form_cache,
                  const fs::path& dir) {
  {
    say(o.note, "  Fig. 2: the hand, separated and glued");
    GluedHand hand = generate_glued_hand(o.seed, 3);
    std::vector<int> glued;
    for (const auto& [a, b] : hand.glued_pairs) {
      glued.push_back(a);
      glued.push_back(b);
    }
    WriteOptions flags;
    flags.scalars.push_back({"glued", indicator(hand.glued.num_vertices(), glued)});
    write_mesh((dir / "hand_separated.ply").string(), hand.separated);
    write_mesh((dir / "hand_glued.ply").string(), hand.glued, flags);
    json cells = json::array();
    cells.push_back(json::array(
        {{{"mesh", "figures/hand_separated.ply"}, {"title", "separated"}},
         {{"mesh", "figures/hand_glued.ply"}, {"title", "glued"}, {"red", {{"property", "glued"}}}},
         nullptr}));
    json rows = json::array({"shape"});
    for (const std::string& m : o.methods) {
      CanonicalFormOptions co = o.canon;
      co.method = m;
      // One method's failure on the figure's hand (a method from outside without its forms, a command that
      // fails) leaves its row out of the figure, said; the other rows and the run go on. Both hands are tried,
      // so that a forms door lists both as needed.
      auto form_of = [&](const Mesh& mesh, const std::string& name, CanonicalForm& form) {
        co.name = name;  // the generated hand's names (a forms door looks them up by these)
        try {
          form = cached_canonical_form(form_cache, mesh, co);
          return true;
        } catch (const Error& error) {
          say(o.note, std::string("warning: Fig. 2 leaves out ") + m + ": " + error.what());
          return false;
        }
      };
      CanonicalForm a, b;
      const bool separated_ok = form_of(hand.separated, "hand_separated", a);
      if (!form_of(hand.glued, "hand_glued", b) || !separated_ok) continue;
      WriteOptions wo;
      if (b.torn.size()) wo.scalars.push_back({"torn", b.torn});
      wo.scalars.push_back({"glued", indicator(hand.glued.num_vertices(), glued)});
      write_mesh((dir / (m + "_hand_separated.ply")).string(), Mesh{a.X, hand.separated.F});
      write_mesh((dir / (m + "_hand_glued.ply")).string(), Mesh{b.X, hand.glued.F}, wo);
      // Overlay: the glued hand's form aligned onto the separated one's by ICP, drawn red.
      IcpResult align = icp(b.X, a.X);
      Mesh overlay;
      const Index n = a.X.rows();
      overlay.V.resize(2 * n, 3);
      overlay.V << a.X, align.transform.apply(b.X);
      overlay.F.resize(hand.separated.F.rows() + hand.glued.F.rows(), 3);
      overlay.F << hand.separated.F, (hand.glued.F.array() + static_cast<int>(n)).matrix();
      Eigen::VectorXd second = Eigen::VectorXd::Zero(2 * n);
      second.tail(n).setOnes();
      WriteOptions ov;
      ov.scalars.push_back({"glued_hand", second});
      write_mesh((dir / (m + "_hand_overlay.ply")).string(), overlay, ov);
      const std::string red = canonical_form_method(m).marks_torn ? "torn" : "glued";
      cells.push_back(
          json::array({{{"mesh", "figures/" + m + "_hand_separated.ply"}},
                       {{"mesh", "figures/" + m + "_hand_glued.ply"}, {"red", {{"property", red}}}},
                       {{"mesh", "figures/" + m + "_hand_overlay.ply"},
                        {"title", "ICP alignment (glued: red)"},
                        {"red", {{"property", "glued_hand"}}}}}));
      rows.push_back(method_title(m));
    }
    report.figure_grids["fig2_hand"] = {
        {"title", "Fig. 2: the hand with separated and glued fingers, and its canonical forms"},
        {"rows", rows},
        {"cells", cells}};
  }
}

// Figure 3: the paper's plain scheme after 300, 600, 900, 3000, 10000 iterations. One run, cut at the
// checkpoints: each piece continues from the previous one's shape, edges and rest lengths.
void figure3_iterations(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& misc_cache,
                        const FigureShape& fs_shape, const fs::path& dir) {
  {
    say(o.note, "  Fig. 3: " + report.figure_shape + ", iterations up to " +
                    std::to_string(o.fig3_iterations.back()));
    const std::string key = cache_key({"fig3-v1", mesh_content_key(fs_shape.mesh),
                                       canonical_form_key(o.canon), json(o.fig3_iterations).dump()});
    json cached;
    if (std::optional<json> hit = misc_cache.get_json(key)) cached = *hit;
    json row = json::array({{{"mesh", "figures/fig3_input.ply"}, {"title", fs_shape.name}}});
    write_mesh((dir / "fig3_input.ply").string(), fs_shape.mesh);
    json snapshots = json::array();
    Points X = fs_shape.mesh.V;
    Edges E = mesh_edges(fs_shape.mesh.F);
    Eigen::VectorXd rest = edge_lengths(fs_shape.mesh.V, E);
    Eigen::VectorXd torn = Eigen::VectorXd::Zero(X.rows());
    int done = 0;
    bool torn_already = false;
    for (size_t c = 0; c < o.fig3_iterations.size(); ++c) {
      const int target = o.fig3_iterations[c];
      if (!cached.is_null()) {
        X = points_from_json(cached["snapshots"][c]["X"]);
        CSHAPES_REQUIRE(X.rows() == fs_shape.mesh.num_vertices(), misc_cache.entry_path(key),
                        ": a damaged Figure 3 cache entry (delete it to recompute)");
        std::vector<double> t = cached["snapshots"][c]["torn"].get<std::vector<double>>();
        torn = Eigen::Map<const Eigen::VectorXd>(t.data(), X.rows());
      } else if (target > done) {
        CoulombCanonOptions co = o.canon.coulomb;
        co.scheme = CoulombScheme::Paper;
        // The paper's iteration from the input; each chunk continues from the last one's X, so it must not
        // start again elsewhere.
        co.start = CoulombStart::Input;
        co.flatten = 0;
        co.stop_tolerance = 0;  // no early stop: the figure shows the iterations
        co.max_iterations = target - done;
        // One bar over every piece: the iterations done so far out of the last snapshot's.
        if (const ProgressFn& base = o.progress ? o.progress : o.canon.progress)
          co.progress = [base, done, last = o.fig3_iterations.back()](const std::string& s, double d, double) {
            base(s.empty() ? s : "Fig. 3 iterations", done + d, last);
          };
        co.tear_times = 1;  // the figure tears once, at tear_after
        if (torn_already) {
          co.tear_fraction = 0;
        } else {
          co.tear_after = std::max(0, co.tear_after - done);  // the schedule of one uninterrupted run
        }
        CoulombCanonResult r = coulomb_canonical_form(X, E, co, rest);
        torn_already = torn_already || r.torn_edges.rows() > 0;
        X = r.X;
        E = r.edges;
        rest = r.rest_lengths;
        torn = torn.cwiseMax(r.torn_vertices);
        done = target;
      }
      snapshots.push_back(
          {{"X", points_to_json(X)}, {"torn", std::vector<double>(torn.data(), torn.data() + torn.size())}});
      WriteOptions wo;
      wo.scalars.push_back({"torn", torn});
      const std::string file = "fig3_" + std::to_string(target) + ".ply";
      write_mesh((dir / file).string(), Mesh{X, fs_shape.mesh.F}, wo);
      row.push_back({{"mesh", "figures/" + file},
                     {"title", std::to_string(target) + " iterations"},
                     {"red", {{"property", "torn"}}}});
    }
    if (cached.is_null()) misc_cache.put_json(key, json{{"snapshots", snapshots}});
    report.figure_grids["fig3_iterations"] = {
        {"title", "Fig. 3: coulombization (paper's scheme) of " + report.figure_shape},
        {"cells", json::array({row})}};
  }
}

// Figure 5: energy and mean violation per outer iteration for 1, 10 and 100 projection steps.
void figure5_convergence(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& form_cache,
                         const FigureShape& fs_shape) {
  {
    say(o.note, "  Fig. 5: convergence for 1, 10 and 100 projection steps");
    std::vector<std::vector<double>> rows;
    for (int k : {1, 10, 100}) {
      CanonicalFormOptions co = o.canon;
      co.method = "coulomb";
      co.coulomb.scheme = CoulombScheme::Paper;
      co.coulomb.start = CoulombStart::Input;  // the paper's iteration, from the input
      co.coulomb.flatten = 0;
      co.coulomb.projection.steps = k;
      co.coulomb.tear_fraction = 0;  // the curves of one constraint set
      co.coulomb.stop_tolerance = 0;
      co.coulomb.max_iterations = o.fig5_iterations;
      co.progress = renamed_stage(o.progress ? o.progress : o.canon.progress,
                                  "Fig. 5, " + counted(k, "projection step"));
      CanonicalForm f = cached_canonical_form(form_cache, fs_shape.mesh, co);
      // history columns: iteration, energy, mean_violation, ...
      for (const auto& h : f.history_rows) rows.push_back({double(k), h[0], h[1], h[2]});
      if (!f.history_rows.empty())
        report.convergence.push_back({k, f.history_rows.back()[1], f.history_rows.back()[2]});
    }
    write_file_atomically((fs::path(o.out) / "convergence.csv").string(), [&](std::ostream& out) {
      out << "projection_steps,iteration,energy,mean_violation\n";
      out.precision(10);
      for (const auto& r : rows) out << int(r[0]) << ',' << int(r[1]) << ',' << r[2] << ',' << r[3] << '\n';
    });
  }
}

}  // namespace

void write_figure_data(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& misc_cache,
                       const DiskCache& form_cache) {
  const fs::path dir = fs::path(o.out) / "figures";
  figure2_hand(o, report, form_cache, dir);
  const bool has_coulomb = std::find(o.methods.begin(), o.methods.end(), "coulomb") != o.methods.end();
  if (!has_coulomb) return;
  FigureShape fs_shape = figure_shape(o, misc_cache, report.summary.failures);
  report.figure_shape = fs_shape.name + (o.figure_vertices > 0 ? " remeshed to " : " at its ") +
                        std::to_string(fs_shape.mesh.num_vertices()) + " vertices";

  figure3_iterations(o, report, misc_cache, fs_shape, dir);
  figure5_convergence(o, report, form_cache, fs_shape);
}

void measure_table1(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& misc_cache) {
  // The data's cat and michael when it has them, else stand-ins from its first classes.
  Dataset data = read_dataset(o.data, o.allow_outside);
  auto first_of = [&](const std::vector<std::string>& wanted, size_t fallback) -> const DatasetEntry* {
    for (const std::string& w : wanted)
      for (const DatasetEntry& e : data.entries)
        if (!e.noisy && e.class_name == w) return &e;
    std::vector<const DatasetEntry*> firsts;
    for (const std::string& c : data.classes)
      for (const DatasetEntry& e : data.entries)
        if (!e.noisy && e.class_name == c) {
          firsts.push_back(&e);
          break;
        }
    return firsts.empty() ? nullptr : firsts[std::min(fallback, firsts.size() - 1)];
  };
  struct Target {
    std::string label;
    const DatasetEntry* entry;
    Index vertices;
  };
  std::vector<Target> targets = {{"swissroll", nullptr, 561},
                                 {"cat", first_of({"cat", "quadruped"}, 0), 3505},
                                 {"michael", first_of({"michael", "biped"}, 1), 22738}};
  TimingOptions to;
  to.repeats = o.timing_repeats;
  to.geodesics = o.canon.geodesics;
  to.progress = o.progress ? o.progress : o.canon.progress;
  std::vector<std::vector<double>> csv;
  for (const Target& t : targets) {
    Mesh mesh;
    std::string label = t.label;
    if (!t.entry) {
      mesh = swiss_roll();
    } else {
      Mesh input = repair_for(read_mesh(t.entry->path), MeshRequirements::manifold_surface()).mesh;
      say(o.note, "  remeshing " + t.entry->name + " to " + std::to_string(t.vertices) + " vertices");
      mesh = remeshed(input, t.vertices, misc_cache);
      if (t.entry->name.rfind(t.label, 0) != 0) label = t.label + " (" + t.entry->name + ")";
    }
    try {
      require_memory(1.2 * distance_matrix_bytes(mesh.num_vertices()), "Table 1's geodesic matrix");
    } catch (const Error&) {
      to.mds = false;
      report.table1_note += label + ": MDS skipped, its distance matrix does not fit in memory. ";
    }
    say(o.note, "  timing " + label + " (" + std::to_string(mesh.num_vertices()) + " vertices)");
    TimingRow row = time_canonical_forms(label, mesh, to);
    report.table1.push_back(row);
    to.mds = true;
  }
  write_file_atomically((fs::path(o.out) / "table1.csv").string(), [&](std::ostream& out) {
    out << "shape,vertices,mds_precompute,mds_iteration,coulomb_precompute,coulomb_iteration\n";
    out.precision(6);
    for (const TimingRow& r : report.table1)
      out << r.shape << ',' << r.vertices << ',' << r.mds_precompute << ',' << r.mds_iteration << ','
          << r.coulomb_precompute << ',' << r.coulomb_iteration << '\n';
  });
}

}  // namespace cshapes
