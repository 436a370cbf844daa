// The parts of `cshapes experiment paper` beyond retrieval: the data of Figures 2, 3 and 5, Table 1, and
// report.md (each claim of the paper beside our measurement). Used by experiments/paper_experiment.cpp.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/cache.h"
#include "eval/timing.h"
#include "experiments/paper_experiment.h"

namespace cshapes {

// What the experiment measured, gathered for report.md.
struct PaperReport {
  const PaperExperimentOptions* options = nullptr;
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
  std::map<std::string, Retrieval> retrieval;
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

// Figure 2 (the hand, separated and glued, by every method, and their ICP alignment), Figure 3 (one shape
// after 300 … 10,000 paper-scheme iterations) and Figure 5 (energy and violation per iteration for 1, 10
// and 100 projection steps): meshes under out/figures/, convergence.csv, and report.figure_grids.
void write_figure_data(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& misc_cache,
                       const DiskCache& form_cache);

// Table 1 on the swiss roll (561 vertices), a cat (3,505) and a michael (22,738) — remeshed from the data's
// "cat"/"michael" classes when present, else from its first and second classes; table1.csv.
void measure_table1(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& misc_cache);

// report.md.
void write_report(const PaperExperimentOptions& o, const PaperReport& report);

}  // namespace cshapes
