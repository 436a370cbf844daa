// The parts of `cshapes experiment paper` beyond retrieval: the data of Figures 2, 3 and 5, Table 1, and
// report.md (each claim of the paper beside our measurement). Used by experiments/paper_experiment.cpp.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/experiments/timing_table.h"

namespace cshapes {

// report.md in folder, from the report alone (each claim of the paper beside what was measured).
void write_paper_report(const PaperReport& report, const std::string& folder);

// A method's name as the paper writes it (its registered title, pipeline/canonical_form_methods.h).
std::string method_title(const std::string& method);

}  // namespace cshapes
