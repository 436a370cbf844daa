// The extension behind `import cshapes` (python/__init__.py loads it as cshapes._cshapes): the library from
// Python, numpy in and numpy out. A skin over the same library calls as the CLI (pipeline/, eval/, matching/,
// canon/ and the rooms below): no pipeline logic of its own. Errors raise ValueError (cshapes::Error) or OSError
// (cshapes::FileError) with the CLI's messages.
#include "cshapes/support/build_info.h"
#include "cshapes/support/error.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/simd.h"
#include "cshapes/support/threads.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/declared_options.h"

namespace py = pybind11;

PYBIND11_MODULE(_cshapes, m) {
  m.doc() = R"(cshapes: Coulomb shapes and MDS canonical forms, ICP shape distances and retrieval measures.

Arrays: V (n, 3) float64 coordinates, F (m, 3) int32/int64 vertex indices, D (n, n) distances; any real
dtype and any strides are accepted (copied once into the library's layout). Keyword options carry the
CLI's names (--tear-fraction -> tear_fraction) and defaults. Long computations release the GIL.)";
  m.attr("__version__") = CSHAPES_VERSION;
  m.attr("GOMP_SPINCOUNT") = cshapes::kGompSpinCount;  // what cshapes/__init__.py sets before loading libgomp
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const cshapes::Cancelled&) {
      // Ctrl-C (python/interrupt.h): Python's handler runs now (KeyboardInterrupt, or the user's own).
      if (PyErr_CheckSignals() == 0) PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const cshapes::FileError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const cshapes::Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.def(
      "set_num_threads",
      [](int n) {
        if (n < 0)
          throw py::value_error("set_num_threads(): expected an integer >= 0, got " + std::to_string(n));
        cshapes::python::set_threads(n);
      },
      py::arg("n"),
      "OpenMP threads of every later call, from any Python thread; 0: the default (OMP_NUM_THREADS or all "
      "cores).");
  m.def("get_num_threads", &cshapes::python::threads, "OpenMP threads later calls use.");
  m.def(
      "build_info",
      [] {
        py::dict out;
        out["version"] = cshapes::version();
        out["build"] = cshapes::build_description();
        out["simd"] = cshapes::to_string(cshapes::simd_target());
        py::list supported;
        for (cshapes::SimdTarget t : cshapes::supported_simd_targets())
          supported.append(cshapes::to_string(t));
        out["simd_supported"] = supported;
        return out;
      },
      "What this module is: {'version', 'build', 'simd' (the instruction set its kernels run with: the best "
      "this CPU supports, or the environment variable CSHAPES_SIMD=baseline|avx2|avx512 read at the first "
      "call), 'simd_supported'}.");
  cshapes::python::bind_mesh(m);
  cshapes::python::bind_canon(m);
  cshapes::python::bind_matching(m);
  cshapes::python::bind_eval(m);
  cshapes::python::bind_experiments(m);
  cshapes::python::bind_option_declarations(m);
}
