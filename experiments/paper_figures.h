// The data behind Figures 2, 3 and 5 and Table 1 of the paper, for `cshapes experiment paper`
// (experiments/paper_experiment.h); what they measure goes into the PaperReport (experiments/paper_report.h).
#pragma once

#include "cshapes/data/cache.h"
#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/experiments/paper_report.h"

namespace cshapes {

// Figure 2 (the hand, separated and glued, by every method, and their ICP alignment), Figure 3 (one shape
// after 300 … 10,000 paper-scheme iterations) and Figure 5 (energy and violation per iteration for 1, 10
// and 100 projection steps): meshes under out/figures/, convergence.csv, and report.figure_grids.
void write_figure_data(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& misc_cache,
                       const DiskCache& form_cache);

// Table 1 on the swiss roll (561 vertices), a cat (3,505) and a michael (22,738) — remeshed from the data's
// "cat"/"michael" classes when present, else from its first and second classes; table1.csv.
void measure_table1(const PaperExperimentOptions& o, PaperReport& report, const DiskCache& misc_cache);

}  // namespace cshapes
