// A toy canonical-form method, declared and registered from this one file: what adding a method to cshapes
// takes (pipeline/canonical_form_methods.h). Its form is the mesh centred, scaled by toy_scale and mirrored
// across the plane of toy_mirror. Nothing else in the tree names it: linked into cshapes_toy (the CLI) and a
// Python module of its own (build/toy_python), it has its option group in `cshapes_toy canon --help`, its
// keywords in canonical_form(method='toy'), its entries in the stub scripts/make_stub.py writes for that module,
// its cache key, and the refusal of its options by the other methods (tests/toy_method/toy_method_test.cpp,
// tests/toy_method/check_toy_python.py).
#include "cshapes/pipeline/canonical_form_methods.h"

namespace cshapes {
namespace {

// Its options, kept in CanonicalFormOptions::extra (option_in_extra): a method from outside the library has no
// field of its own there.
const MethodOption& toy_scale() {
  static const MethodOption option = [] {
    MethodOption o = option_of("toy_scale", MethodOption::Type::Number, "the form is the centred mesh times this");
    o.limit = number_limit("toy-scale", 0, 1000, /*minimum_open=*/true);
    return option_in_extra(o, OptionValue(2.0));
  }();
  return option;
}

const MethodOption& toy_mirror() {
  static const MethodOption option = [] {
    MethodOption o = option_of("toy_mirror", MethodOption::Type::Choice,
                               "mirror the form across the plane normal to this axis");
    o.choices = {"none", "x", "y", "z"};
    return option_in_extra(o, OptionValue(std::string("none")));
  }();
  return option;
}

CanonicalForm toy_compute(const Mesh& mesh, const CanonicalFormOptions& options, const GivenDistances&) {
  CanonicalForm form;
  const Eigen::RowVector3d centre = mesh.V.colwise().mean();
  form.X = (mesh.V.rowwise() - centre) * extra_number(options, toy_scale());
  const std::string axis = extra_text(options, toy_mirror());
  if (axis != "none") form.X.col(axis[0] - 'x') *= -1.0;
  return form;
}

CanonicalFormMethod toy_method() {
  CanonicalFormMethod m;
  m.name = "toy";
  m.title = "toy";
  m.summary = "the mesh centred, scaled and mirrored (a test of method registration)";
  m.requirements = MeshRequirements::edge_graph();
  m.repair_purpose = "the toy method";
  m.options = {toy_scale(), toy_mirror()};
  m.reads = {"extra"};
  m.compute = toy_compute;
  return m;
}

const bool registered = register_canonical_form_method(toy_method());

}  // namespace
}  // namespace cshapes
