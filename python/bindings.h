// The Python module's parts: each bind_* adds one layer's functions to the module (python/module.cpp).
#pragma once

#include <pybind11/pybind11.h>

#include "cshapes/matching/icp.h"
#include "python/kwargs.h"

namespace cshapes::python {

void bind_mesh(pybind11::module_& m);      // read_mesh, write_mesh, mesh_info, geodesics, noise, generate
void bind_canon(pybind11::module_& m);     // coulomb, canonical_form, classical_mds, smacof
void bind_matching(pybind11::module_& m);  // icp, shape_distance
void bind_eval(pybind11::module_& m);      // distance_matrix, retrieval_measures
void bind_experiments(pybind11::module_& m);  // experiment_paper, experiment_retrieval, show

// The ICP keywords of `cshapes align` (no_reflections, one_way, axis_swaps, trim, tolerance).
IcpOptions read_icp_options(Kwargs& k);

}  // namespace cshapes::python
