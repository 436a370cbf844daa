// Uses the installed library: a generated sphere's Coulomb canonical form and its quality, printed.
#include <iostream>

#include <cshapes/data/synthetic.h>
#include <cshapes/pipeline/canonical_forms.h>

// The consumer's own mesh/ folder, on its include path beside the installed tree: cshapes' headers name
// theirs as cshapes/mesh/..., so neither shadows the other.
#include "mesh/mesh.h"

int main() {
  const cshapes::Mesh sphere = cshapes::icosphere(2);
  cshapes::CanonicalFormOptions options;
  options.method = "coulomb";
  const cshapes::CanonicalForm form = cshapes::canonical_form(sphere, options);
  std::cout << consumer::kGreeting << ": vertices " << form.X.rows() << " iterations " << form.iterations << "\n";
  return form.X.rows() == sphere.num_vertices() && form.X.allFinite() ? 0 : 1;
}
