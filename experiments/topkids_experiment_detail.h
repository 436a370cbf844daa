// Internal to the TOPKIDS experiment's files: experiments/topkids_experiment.cpp (inputs, forms, scoring, the
// run) and topkids_experiment_files.cpp (the data files, the figure and report.md, from a
// TopkidsExperimentResult).
#pragma once

#include "cshapes/experiments/topkids_experiment.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes::topkids_detail {

// The method name of the inputs' own row (the poses aligned directly, no canonical form).
inline constexpr const char* kInputs = "inputs";

// topkids.csv (a row per pose and method), topkids_curves.csv and topkids.json.
void write_data_files(const ExperimentFolder& folder, const TopkidsExperimentResult& r,
                      const TopkidsExperimentOptions& o);

}  // namespace cshapes::topkids_detail
