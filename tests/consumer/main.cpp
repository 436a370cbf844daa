// Uses the installed library: a generated sphere's Coulomb canonical form and its quality, printed.
#include <iostream>

#include "core/synthetic.h"
#include "pipeline/canonical_forms.h"

int main() {
  const cshapes::Mesh sphere = cshapes::icosphere(2);
  cshapes::CanonicalFormOptions options;
  options.method = "coulomb";
  const cshapes::CanonicalForm form = cshapes::canonical_form(sphere, options);
  std::cout << "vertices " << form.X.rows() << " iterations " << form.iterations << "\n";
  return form.X.rows() == sphere.num_vertices() && form.X.allFinite() ? 0 : 1;
}
