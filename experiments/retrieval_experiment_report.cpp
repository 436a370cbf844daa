// report.md of `cshapes experiment retrieval` (write_retrieval_report, experiments/retrieval_experiment.h).
#include <cmath>
#include <sstream>

#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/retrieval_experiment.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes {

std::string retrieval_measures_cells(const RetrievalScores& s) {
  return " | " + fixed(s.nn, 3) + " | " + fixed(s.ft, 3) + " | " + fixed(s.st, 3) + " | " + fixed(s.e, 3) +
         " | " + fixed(s.dcg, 3) + " | " + fixed(s.ap, 3) + " |";
}

const char* const kRetrievalMeasuresHeader = " | NN | FT | ST | E | DCG | mAP |";
const char* const kRetrievalMeasuresRule = "---:|---:|---:|---:|---:|---:|";

std::string retrieval_distance_title(const std::string& kind) {
  return kind == "hausdorff" ? "Hausdorff (the paper's)"
         : kind == "chamfer" ? "Chamfer"
         : kind == "rmse"    ? "RMSE"
                             : kind;
}

namespace {

void overall_section(std::ostream& out, const RetrievalExperimentResult& r) {
  out << "## Overall\n\nEvery shape a query against all the others; micro averages over the queries.\n\n"
      << "| method | distance | shapes" << kRetrievalMeasuresHeader << "\n|---|---|---:|"
      << kRetrievalMeasuresRule << '\n';
  for (const RetrievalMethodResult& m : r.methods)
    for (const std::string& kind : retrieval_distances()) {
      auto it = m.by_distance.find(kind);
      if (it == m.by_distance.end()) continue;
      out << "| " << canonical_form_method_title(m.method) << " | " << retrieval_distance_title(kind) << " | "
          << m.names.size() << retrieval_measures_cells(it->second.result.mean) << '\n';
    }
  out << '\n';
}

// Per method: each class's measures under the paper's distance, then each class's mAP under every distance
// and method side by side.
void per_class_section(std::ostream& out, const RetrievalExperimentResult& r) {
  out << "## Per class\n\nMeasures of each class's queries under the Hausdorff distance (macro view: a class "
         "that is hard for a method shows here, however large the others).\n\n";
  for (const RetrievalMethodResult& m : r.methods) {
    auto it = m.by_distance.find("hausdorff");
    if (it == m.by_distance.end()) continue;
    const RetrievalReport& rep = it->second;
    out << "### " << canonical_form_method_title(m.method) << "\n\n| class | queries"
        << kRetrievalMeasuresHeader << "\n|---|---:|" << kRetrievalMeasuresRule << '\n';
    for (size_t c = 0; c < rep.class_names.size(); ++c) {
      out << "| " << rep.class_names[c] << " | " << rep.result.class_queries[c];
      if (rep.result.class_queries[c] > 0)
        out << retrieval_measures_cells(rep.result.class_mean[c]) << '\n';
      else
        out << " | — | — | — | — | — | — |\n";
    }
    out << "| **all** | " << rep.result.queries.size() << retrieval_measures_cells(rep.result.mean) << "\n\n";
  }
  out << "### mAP per class, every method and distance\n\n| class |";
  std::string rule = "|---|";
  for (const RetrievalMethodResult& m : r.methods)
    for (const std::string& kind : retrieval_distances()) {
      out << ' ' << canonical_form_method_title(m.method) << ", " << kind << " |";
      rule += "---:|";
    }
  out << '\n' << rule << '\n';
  for (const std::string& cls : r.class_names) {
    out << "| " << cls << " |";
    for (const RetrievalMethodResult& m : r.methods)
      for (const std::string& kind : retrieval_distances()) {
        auto it = m.by_distance.find(kind);
        std::string cell = "—";
        if (it != m.by_distance.end()) {
          const RetrievalReport& rep = it->second;
          for (size_t c = 0; c < rep.class_names.size(); ++c)
            if (rep.class_names[c] == cls && rep.result.class_queries[c] > 0)
              cell = fixed(rep.result.class_mean[c].ap, 3);
        }
        out << ' ' << cell << " |";
      }
    out << '\n';
  }
  out << '\n';
}

void confusion_section(std::ostream& out, const RetrievalExperimentResult& r) {
  out << "## Confusion (nearest neighbour, Hausdorff)\n\nRow: the query's class; column: the class of its "
         "nearest neighbour (every shape a query). A perfect method has only the diagonal.\n\n";
  for (const RetrievalMethodResult& m : r.methods) {
    auto it = m.by_distance.find("hausdorff");
    if (it == m.by_distance.end()) continue;
    const RetrievalReport& rep = it->second;
    const nlohmann::json counts = confusion_json(rep.result.confusion);  // whole, or shares of tied nearest
    out << "### " << canonical_form_method_title(m.method) << "\n\n| query \\ nearest |";
    for (const std::string& c : rep.class_names) out << ' ' << c << " |";
    out << "\n|---|";
    for (size_t c = 0; c < rep.class_names.size(); ++c) out << "---:|";
    out << '\n';
    for (size_t a = 0; a < rep.class_names.size(); ++a) {
      out << "| " << rep.class_names[a] << " |";
      for (size_t b = 0; b < rep.class_names.size(); ++b) {
        const std::string n = counts[a][b].dump();
        out << ' ' << (a == b ? "**" + n + "**" : n) << " |";
      }
      out << '\n';
    }
    out << '\n';
  }
}

// Two-stage mode: what was aligned, the recall of the candidates and, with a reference, the measures beside
// the exact run's.
void two_stage_section(std::ostream& out, const RetrievalExperimentResult& r) {
  const RetrievalExperimentOptions& o = r.options;
  if (o.two_stage_k <= 0) return;
  out << "## Two-stage retrieval\n\nICP aligned only each shape's " << o.two_stage_k
      << " nearest candidates by a cheap descriptor of its form (moments and the D2 distribution, "
         "matching/shape_descriptor.h); every other pair ranks after them, in descriptor order. recall@K: "
         "the share of each shape's true "
      << o.two_stage_k
      << " nearest (Hausdorff, the exact run's matrix) that its candidates held; 1 means every query's "
         "first K results are the exact run's.";
  if (o.two_stage_reference.empty())
    out << " No exact run was given (--two-stage-reference), so no recall and no exact measures.";
  else
    out << " Exact run: `" << o.two_stage_reference << "`.";
  out << "\n\n| method | pairs aligned | of all pairs | recall@K | mAP | mAP exact | NN | NN exact |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const RetrievalMethodResult& m : r.methods) {
    const long n = static_cast<long>(m.names.size()), all = n * (n - 1) / 2;
    const RetrievalScores& s = m.by_distance.at("hausdorff").result.mean;
    const auto exact = m.exact.find("hausdorff");
    const bool have = exact != m.exact.end();
    out << "| " << canonical_form_method_title(m.method) << " | " << m.pairs_aligned << " | "
        << percent(all > 0 ? static_cast<double>(m.pairs_aligned) / static_cast<double>(all) : NAN, 1)
        << " | " << (m.recall >= 0 ? fixed(m.recall, 3) : std::string("—")) << " | " << fixed(s.ap, 3) << " | "
        << (have ? fixed(exact->second.ap, 3) : std::string("—")) << " | " << fixed(s.nn, 3) << " | "
        << (have ? fixed(exact->second.nn, 3) : std::string("—")) << " |\n";
  }
  out << "\nMeasures under the Hausdorff distance (the paper's); the other distances' are in retrieval.json "
         "(\"two_stage\").\n\n";
}

void cost_section(std::ostream& out, const RetrievalExperimentResult& r) {
  out << "## Cost\n\nMeasured under whatever else ran on the machine; cached items cost nothing on a "
         "rerun.\n\n"
         "| method | forms computed | forms cached | seconds per form (median) | peak memory per form (MB) | "
         "pairs computed | pairs cached | seconds |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const RetrievalMethodResult& m : r.methods)
    out << "| " << canonical_form_method_title(m.method) << " | " << m.forms_computed << " | "
        << m.forms_cached << " | " << fixed(m.form_seconds_median, 2) << " | "
        << (m.form_peak_bytes_max < 0 ? std::string("—") : fixed(m.form_peak_bytes_max / 1e6, 0)) << " | "
        << m.pairs_computed << " | " << m.pairs_cached << " | " << fixed(m.seconds, 1) << " |\n";
  out << "Seconds per form: as computed (a cached form keeps the time of the run that computed it). Peak "
         "memory: of the program a method from outside runs per shape (its largest); — for the library's "
         "methods, which run inside cshapes.\n\n";
  if (r.profile.empty()) return;
  out << "### Where the time went\n\nPer stage: wall and CPU seconds (this process's threads and the programs "
         "it ran: methods from outside, the figures' Python), the cores kept busy on average (CPU / wall) and "
         "the share of the machine's "
      << r.cores
      << " cores left idle. Forms: reading the files and the canonical forms (cached ones are read); pairs: "
         "ICP and the distances of every pair; measures: the matrices' files and the measures. Also in "
         "retrieval.json's \"profile\".\n\n"
      << stage_times_markdown(r.profile, r.cores) << '\n';
}

}  // namespace

void write_retrieval_report(const RetrievalExperimentResult& r, const std::string& folder) {
  std::ostringstream out;
  const RetrievalExperimentOptions& o = r.options;
  out << "# Retrieval experiment\n\n"
      << build_sentence() << "\n\n"
      << "Collection: `" << o.data << "`: " << r.shapes << " shapes in " << r.class_names.size()
      << " classes (";
  for (size_t c = 0; c < r.class_names.size(); ++c)
    out << (c ? ", " : "") << r.class_names[c] << " " << r.class_sizes[c];
  out << "). Inputs' digest (SHA-256 over each shape's name, class and file SHA-256; retrieval.json's "
         "\"inputs\", which `cshapes compare` checks): `"
      << r.inputs.digest << "`. Methods: ";
  for (size_t k = 0; k < r.methods.size(); ++k)
    out << (k ? ", " : "") << canonical_form_method_title(r.methods[k].method);
  out << ". Distances between canonical forms after ICP: Hausdorff (the paper's), Chamfer, RMSE. "
      << "Run time " << fixed(r.seconds, 1) << " s.\n\n"
      << "Conventions (eval/retrieval.h, the Princeton Shape Benchmark's psbTable): the query is excluded "
         "from its results; NN is the nearest result's class; FT and ST the share of the class (C − 1 "
         "shapes) among the first C − 1 and 2(C − 1) results; E the E-measure of the first "
      << o.retrieval.e_measure_depth
      << " results; DCG normalised by its ideal; mAP the mean average precision. Classes of fewer than "
      << o.retrieval.min_class_size << " shapes give no queries.\n\n";
  if (r.resampled) out << "## Resampling\n\n" << resampling_markdown(r.resampling) << '\n';
  overall_section(out, r);
  two_stage_section(out, r);
  per_class_section(out, r);
  confusion_section(out, r);
  out << "## Figures\n\n";
  if (r.figures.empty()) out << "Not drawn: " << r.figures_note << "\n\n";
  for (const std::string& f : r.figures) out << figure_markdown(f, f) << "\n\n";
  out << shape_failures_markdown(r.failures);
  cost_section(out, r);
  out << "## Files\n\n"
         "- `classes.cla`: the collection's classes (Princeton .cla), in its order\n"
         "- `METHOD/classes.cla`: the shapes of METHOD's matrices, in their order\n"
         "- `METHOD/DISTANCE.csv`: the distance matrix with shape names (`cshapes evaluate` reads it)\n"
         "- `METHOD/DISTANCE.txt`: the same as plain text, one row per line (SHREC's evaluation code)\n"
         "- `METHOD/DISTANCE.matrix`: the same as 32-bit floats (the PSB's psbTable and psbPRCurve)\n"
         "- `METHOD/DISTANCE/`: metrics.json, pr.csv, queries.csv, matrix.csv, confusion.csv\n"
         "- `retrieval.json`: every measure above\n";
  if (r.resampled) out << "- `resampled/`: the remeshed shapes, their manifest.csv and resample.csv\n";
  ExperimentFolder(folder).write_text("report.md", out.str());
}

}  // namespace cshapes
