// cshapes stress --count N --seed S: the corpus of failure-prone meshes (data/stress_corpus.h) through every
// geodesic method, canonical form and ICP (experiments/geodesic_stress.h); one JSON line per mesh on stdout
// (or -o), failing meshes saved. scripts/stress_geodesics.py runs it and prints the table.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <mutex>

#include "cshapes/mesh/io.h"
#include "cli/command.h"
#include "cshapes/experiments/geodesic_stress.h"
#include "cshapes/pipeline/canonical_form_methods.h"

namespace cshapes::cli {
namespace cmd_stress {
namespace {

namespace fs = std::filesystem;

struct StressArgs {
  long long count = 18, first = 0;
  std::uint64_t seed = 1;
  long long min_vertices = 200, max_vertices = 30000;
  std::string tosca, geodesic_methods = "heat,heat-direct,heat-cgal,fmm,exact,graph", save_failures, out,
                     mesh_out;
  std::string methods;  // canonical-form methods; empty: every registered method
  long long exact_max = 6000, canon_max = 4000;
  int sources = 3;
  bool no_canon = false, no_icp = false;
} args;

// A name `--geodesic-methods` takes: a geodesic method, or a heat method without intrinsic Delaunay flips.
bool is_geodesic_method(const std::string& name) {
  if (name == "heat-direct" || name == "heat-cgal-direct") return true;
  try {
    parse_geodesic_method(name);
    return true;
  } catch (const Error&) {
    return false;
  }
}

int run() {
  StressCorpusOptions corpus;
  corpus.min_vertices = args.min_vertices;
  corpus.max_vertices = args.max_vertices;
  corpus.tosca_folder = args.tosca;
  try {
    check_stress_corpus_options(corpus);
  } catch (const Error& e) {
    throw UsageError(std::string("--min-vertices, --max-vertices: ") + e.what());
  }
  if (!args.mesh_out.empty()) {  // one case's mesh only
    require_mesh_output_path(args.mesh_out);
    StressCase c = stress_case(args.seed, args.first, corpus);
    write_mesh(args.mesh_out, make_stress_mesh(c, corpus));
    note(c.describe() + " -> " + args.mesh_out);
    return kExitOk;
  }
  GeodesicStressOptions options;
  options.geodesic_methods = split_list(args.geodesic_methods);
  if (options.geodesic_methods.empty()) usage_fail("--geodesic-methods: give at least one geodesic method");
  for (const std::string& m : options.geodesic_methods)
    if (!is_geodesic_method(m))
      usage_fail("--geodesic-methods: unknown geodesic method ", in_quotes(m),
                 "; known: heat, heat-direct, heat-cgal, heat-cgal-direct, fmm, exact, graph");
  // --methods is canonical-form methods, as in every command; it once meant the geodesic methods here.
  for (const std::string& m : split_list(args.methods))
    if (is_geodesic_method(m))
      usage_fail("--methods takes canonical-form methods (", canonical_form_method_list(), "); ",
                 in_quotes(m), " is a geodesic method: give it to --geodesic-methods");
  options.sources = args.sources;
  options.exact_max_vertices = args.exact_max;
  options.canon = !args.no_canon;
  options.canon_max_vertices = args.canon_max;
  if (!args.methods.empty()) options.canon_methods = methods_option(args.methods);
  options.icp = !args.no_icp;
  if (!args.out.empty()) require_output_path(args.out, {"jsonl", "json"});
  if (!args.save_failures.empty()) fs::create_directories(args.save_failures);

  std::vector<std::string> lines(static_cast<size_t>(args.count));
  std::mutex mutex;
  long long done = 0, failed = 0;
  // Cases in parallel (each method inside runs on one thread: nested parallelism is off).
#pragma omp parallel for schedule(dynamic, 1)
  for (long long k = 0; k < args.count; ++k) {
    const Index index = static_cast<Index>(args.first + k);
    nlohmann::json j;
    bool case_failed = false;
    std::string saved;
    try {
      const StressCase c = stress_case(args.seed, index, corpus);
      const Mesh mesh = make_stress_mesh(c, corpus);
      const StressCaseResult r = run_stress_case(c, mesh, options);
      j = stress_result_json(r);
      case_failed = r.failed();
      if (case_failed && !args.save_failures.empty()) {
        saved = (fs::path(args.save_failures) / (c.name() + ".off")).string();
        write_mesh(saved, mesh);
        j["mesh_file"] = saved;
      }
    } catch (const std::exception& e) {  // the corpus or the reference itself failed
      case_failed = true;
      j = {{"case", "s" + std::to_string(args.seed) + "-i" + std::to_string(index)},
           {"index", index},
           {"failed", true},
           {"error", e.what()}};
    }
    std::lock_guard<std::mutex> lock(mutex);
    lines[static_cast<size_t>(k)] = j.dump();
    ++done;
    failed += case_failed;
    if (args.out.empty()) std::cout << lines[static_cast<size_t>(k)] << std::endl;
    note("[stress] " + std::to_string(done) + "/" + std::to_string(args.count) + " " + j.value("case", "") +
         (case_failed ? " FAILED" + (saved.empty() ? std::string() : " (mesh: " + saved + ")") : " ok"));
  }
  if (!args.out.empty())
    write_file_atomically(args.out, [&](std::ostream& out) {
      for (const std::string& line : lines) out << line << '\n';
    });
  note("stress: " + std::to_string(args.count - failed) + " of " + std::to_string(args.count) +
       " meshes passed every check");
  return kExitOk;
}

const bool registered = register_command(
    {{"stress"},
     "Stress run: generated failure-prone meshes through every geodesic method, canonical form and ICP, "
     "against exact geodesics (JSON lines)",
     [](CLI::App& app) {
       app.add_option("--count", args.count, "meshes to make and test")
           ->capture_default_str()
           ->check(integer_in(1, 1000000));
       app.add_option("--seed", args.seed, "corpus seed: case i of seed s is always the same mesh")
           ->capture_default_str();
       app.add_option("--first", args.first, "index of the first case (with --mesh-out: the case written)")
           ->capture_default_str()
           ->check(integer_at_least(0));
       app.add_option("--min-vertices", args.min_vertices, "smallest base remesh (log-uniform sizes)")
           ->capture_default_str()
           ->check(integer_in(50, 10000000));
       app.add_option("--max-vertices", args.max_vertices, "largest base remesh")
           ->capture_default_str()
           ->check(integer_in(50, 10000000));
       app.add_option("--tosca", args.tosca, "a folder of TOSCA .off shapes to draw bases from too");
       app.add_option(
              "--geodesic-methods", args.geodesic_methods,
              "geodesic methods, comma-separated (heat-direct: ours without intrinsic Delaunay flips)")
           ->capture_default_str();
       app.add_option("--sources", args.sources, "source vertices per mesh")
           ->capture_default_str()
           ->check(integer_in(1, 1000));
       app.add_option("--exact-max", args.exact_max, "reference: exact geodesics up to this many vertices, "
                                                     "fast marching above")
           ->capture_default_str()
           ->check(integer_at_least(0));
       app.add_option("--canon-max", args.canon_max, "canonical forms only on meshes up to this size")
           ->capture_default_str()
           ->check(integer_at_least(0));
       app.add_option("--methods", args.methods,
                      "canonical-form methods, comma-separated; default: every registered method");
       app.add_flag("--no-canon", args.no_canon, "skip the canonical forms");
       app.add_flag("--no-icp", args.no_icp, "skip ICP");
       app.add_option("--save-failures", args.save_failures, "write each failing mesh here as CASE.off");
       app.add_option("-o,--output", args.out,
                      "write the JSON lines to this file (.jsonl) instead of stdout");
       add_renamed(app, "--out", "-o/--output", true,
                   "an output file is -o in every command, --out a folder");
       app.add_option("--mesh-out", args.mesh_out, "only write the mesh of case --first to this file");
     },
     run});

}  // namespace
}  // namespace cmd_stress
}  // namespace cshapes::cli
