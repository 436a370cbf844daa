// The parts of `cshapes experiment paper` beyond retrieval: the data of Figures 2, 3 and 5, Table 1, and
// report.md (each claim of the paper beside our measurement). Used by experiments/paper_experiment.cpp.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "experiments/paper_experiment.h"
#include "experiments/timing_table.h"

namespace cshapes {

// What the experiment measured, gathered for report.md.
struct PaperReport {
  PaperExperimentOptions options;  // what was run (its callbacks unused by the report)
  struct ShapeRow {
    std::string name, class_name;
    bool noisy = false, in_retrieval = true;
    Index vertices = 0;
    std::string source;                          // noisy shapes glued here: their clean pose
    std::string defects;                         // core/mesh_defects.h summary, "none" for a clean mesh
    std::map<std::string, std::string> repairs;  // per method: what was repaired ("" or absent: nothing)
  };
  std::vector<ShapeRow> shapes;
  struct Skipped {
    std::string file, reason;
  };
  std::vector<Skipped> skipped;  // files of the data that could not be used, and why
  struct Retrieval {
    double map = 0, nn = 0, ft = 0, st = 0, e = 0, dcg = 0;
    double noisy_query_nn = -1;  // nearest-neighbour rate of the noisy queries alone (−1: none)
  };
  std::map<std::string, Retrieval> retrieval;  // per method, under the paper's (Hausdorff) distance
  // Per method, then per distance kind between canonical forms after ICP (hausdorff, chamfer, rmse:
  // matching/shape_distance.h): a conclusion that depends on the choice of distance shows here.
  std::map<std::string, std::map<std::string, Retrieval>> retrieval_by_distance;
  struct MethodCost {
    std::vector<double> precompute, solve;
    std::vector<int> iterations;
  };
  std::map<std::string, MethodCost> cost;
  struct NoiseRow {
    std::string shape, method;
    double vertexwise_rms = 0;  // same vertices, best rigid fit (reflection allowed), / bbox diagonal
    double hausdorff = 0;       // after ICP, / bbox diagonal
    double icp_rmse = 0;        // after ICP, / bbox diagonal
  };
  std::vector<NoiseRow> noise;
  std::map<std::string, double> pose_variation;  // median ICP RMSE between clean poses of a class / diagonal
  std::map<std::string, std::vector<double>> correspondence_mean_error;  // per pair, / √area
  int correspondence_pairs = 0;
  std::vector<TimingRow> table1;
  std::string table1_note;
  struct Convergence {
    int projection_steps = 0;
    double final_energy = 0, final_violation = 0;
  };
  std::vector<Convergence> convergence;
  std::string figure_shape;                                // the shape of Figures 3 and 5
  nlohmann::json figure_grids = nlohmann::json::object();  // Fig. 2, 3 mesh grids for paper_figures.py
  std::map<std::string, double> stage_seconds;
  PaperExperimentSummary summary;
};

// report.md in folder, from the report alone (each claim of the paper beside what was measured).
void write_paper_report(const PaperReport& report, const std::string& folder);

// A method's name as the paper writes it (its registered title, pipeline/canonical_form_methods.h).
std::string method_title(const std::string& method);

}  // namespace cshapes
