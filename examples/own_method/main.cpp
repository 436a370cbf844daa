// A method of your own beside the built-ins, by the C++ door: registered once (a static registrar before
// main), it is then a method like the others for every experiment, canonical_form() and the cache.
// Usage: own_method OUT_FOLDER. Writes a small generated collection and a retrieval run into OUT_FOLDER.
#include <filesystem>
#include <iostream>

#include <Eigen/Eigenvalues>
#include <cshapes/data/articulated.h>
#include <cshapes/data/dataset.h>
#include <cshapes/experiments/retrieval_experiment.h>
#include <cshapes/mesh/io.h>
#include <cshapes/pipeline/canonical_form_methods.h>

namespace {

// The method: the mesh in its principal axes (axes by decreasing variance, each sign by the third moment).
cshapes::CanonicalForm principal_axes(const cshapes::Mesh& mesh, const cshapes::CanonicalFormOptions&,
                                      const cshapes::GivenDistances&) {
  const Eigen::MatrixX3d X = mesh.V.rowwise() - mesh.V.colwise().mean();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(X.transpose() * X);
  Eigen::MatrixX3d Y = X * eigen.eigenvectors().rowwise().reverse();
  for (int c = 0; c < 3; ++c)
    if (Y.col(c).array().cube().sum() < 0) Y.col(c) *= -1;
  cshapes::CanonicalForm form;
  form.X = Y;
  return form;
}

cshapes::CanonicalFormMethod principal_axes_method() {
  cshapes::CanonicalFormMethod m;
  m.name = "principal-axes";
  m.title = "principal axes";
  m.summary = "the mesh in its principal axes (a rigid baseline)";
  m.repair_purpose = "principal axes";
  m.requirements = cshapes::MeshRequirements::edge_graph();
  m.compute = principal_axes;
  return m;
}

const bool registered = cshapes::register_canonical_form_method(principal_axes_method());

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: own_method OUT_FOLDER\n";
    return 2;
  }
  const std::string out = argv[1];
  // A small collection: 2 classes of 3 poses at 400 vertices, with its manifest.
  cshapes::ArticulatedDatasetOptions data;
  data.classes = 2;
  data.poses = 3;
  data.noisy = 0;
  data.rest.target_vertices = 400;
  std::filesystem::create_directories(out + "/data");
  std::vector<cshapes::DatasetEntry> entries;
  for (const cshapes::ArticulatedShape& s : cshapes::make_articulated_dataset(data)) {
    cshapes::DatasetEntry e;
    e.path = out + "/data/" + s.name + ".off";
    e.name = s.name;
    e.class_name = s.class_name;
    e.pose = s.pose;
    cshapes::write_mesh(e.path, s.mesh);
    entries.push_back(e);
  }
  cshapes::write_manifest(out + "/data/manifest.csv", entries);
  // The retrieval experiment with a built-in method beside it, under one protocol.
  cshapes::RetrievalExperimentOptions run;
  run.data = out + "/data/manifest.csv";
  run.out = out + "/run";
  run.methods = {"lbo", "principal-axes"};
  run.figures = false;
  const cshapes::RetrievalExperimentResult r = cshapes::retrieval_experiment(run);
  for (const cshapes::RetrievalMethodResult& m : r.methods)
    std::cout << m.method << ": mAP " << m.by_distance.at("hausdorff").result.mean.ap << "\n";
  return registered && r.methods.size() == 2 ? 0 : 1;
}
