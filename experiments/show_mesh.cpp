#include "cshapes/experiments/show_mesh.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/experiments/figures.h"

namespace cshapes {

namespace fs = std::filesystem;

namespace {

// A name no other process or thread uses at the same time: "-PID-N".
std::string unique_suffix() {
  static std::atomic<long> counter{0};
  return "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

// The vertex rows of a mesh file: the vertices read and the rows left out (NaN, valid = 0) together, which
// is what a canonical form shares with its input.
Index vertex_rows(const std::string& path) {
  const MeshFile file = read_mesh_file(path);
  return file.mesh.num_vertices() + file.invalid_vertices;
}

void draw(const std::string& mesh, const std::string& form, const std::string& picture,
          const std::vector<std::string>& labels, const ShowOptions& options) {
  // The script draws into a temporary file beside the picture (with its extension: matplotlib writes by it),
  // renamed into place once drawn; a symbolic link is written through, as write_file_atomically does.
  std::error_code ec;
  const fs::path target = fs::is_symlink(picture, ec) ? fs::weakly_canonical(picture, ec) : fs::path(picture);
  const fs::path temporary = target.parent_path() / ("." + target.stem().string() + ".tmp" + unique_suffix() +
                                                     target.extension().string());
  // Options as --name=value and the files after "--": a title, a label or a file name may start with '-'.
  std::vector<std::string> args = {"--output=" + temporary.string(), "--view=" + options.view};
  for (const std::string& label : labels) args.push_back("--label=" + label);
  if (!options.title.empty()) args.push_back("--title=" + options.title);
  args.insert(args.end(), {"--", mesh});
  if (!form.empty()) args.push_back(form);
  const FigureRun run = run_figure_script("show_figure.py", args, temporary.string());
  if (!run.drawn) {
    fs::remove(temporary, ec);
    fail(picture, ": not drawn: ", run.problem);
  }
  fs::rename(temporary, target, ec);
  if (ec) {
    fs::remove(temporary, ec);
    fail_write(picture, ": cannot rename the temporary file into place: ", ec.message());
  }
}

void check_view(const std::string& view) {
  const std::vector<std::string>& views = show_views();
  if (std::find(views.begin(), views.end(), view) == views.end()) {
    std::string known;
    for (const std::string& v : views) known += (known.empty() ? "" : ", ") + v;
    fail("view: expected one of ", known, ", got '", view, "'");
  }
}

}  // namespace

const std::vector<std::string>& show_views() {
  static const std::vector<std::string> views = {"pca", "x", "y", "z"};
  return views;
}

const std::vector<std::string>& show_picture_extensions() {
  static const std::vector<std::string> extensions = {"png", "pdf"};
  return extensions;
}

void show_mesh_files(const std::string& mesh, const std::string& form, const std::string& picture,
                     const ShowOptions& options) {
  check_view(options.view);
  check_output_not_input(picture, {mesh, form}, "the picture");
  check_output_path(picture, show_picture_extensions());
  const Index mesh_rows = vertex_rows(mesh);
  if (!form.empty()) {
    const Index form_rows = vertex_rows(form);
    if (form_rows != mesh_rows)
      fail("the form ", form, " has ", form_rows, " vertices but the mesh ", mesh, " has ", mesh_rows,
           ": a canonical form keeps its mesh's vertices, one row each (cshapes canon MESH -o FORM)");
  }
  std::vector<std::string> labels = {fs::path(mesh).filename().string()};
  if (!form.empty()) labels.push_back(fs::path(form).filename().string());
  draw(mesh, form, picture, labels, options);
}

void show_meshes(const Mesh& mesh, const Mesh* form, const std::string& picture, const ShowOptions& options) {
  check_view(options.view);
  check_output_path(picture, show_picture_extensions());
  check_mesh_arrays(mesh, "mesh");
  if (form && form->V.rows() != mesh.V.rows())
    fail("the form has ", form->V.rows(), " vertices but the mesh has ", mesh.V.rows(),
         ": a canonical form keeps its mesh's vertices, one row each");
  if (form && form->F.rows() > 0 && (form->F.minCoeff() < 0 || form->F.maxCoeff() >= form->V.rows()))
    fail("the form's faces use vertex indices outside 0..", form->V.rows() - 1);
  std::error_code ec;
  const fs::path folder = fs::temp_directory_path() / ("cshapes-show" + unique_suffix());
  fs::create_directories(folder);
  try {
    const std::string mesh_file = (folder / "mesh.ply").string(), form_file = (folder / "form.ply").string();
    write_mesh(mesh_file, mesh, WriteOptions{{}, {}, true});
    std::vector<std::string> labels = {"mesh"};
    if (form) {
      // Rows a method dropped are non-finite: written as the PLY a canonical form is (valid = 0).
      Mesh drawn{form->V, form->F.rows() > 0 ? form->F : mesh.F};
      Eigen::VectorXd valid(drawn.V.rows());
      for (Index i = 0; i < drawn.V.rows(); ++i) valid[i] = drawn.V.row(i).allFinite() ? 1.0 : 0.0;
      WriteOptions written;
      written.binary = true;
      if (valid.minCoeff() == 0) {
        written.scalars.push_back({"valid", valid});
        drawn.V = (valid.array() > 0).replicate(1, 3).select(drawn.V, std::nan(""));
      }
      write_mesh(form_file, drawn, written);
      labels.push_back("canonical form");
    }
    draw(mesh_file, form ? form_file : "", picture, labels, options);
  } catch (...) {
    fs::remove_all(folder, ec);
    throw;
  }
  fs::remove_all(folder, ec);
}

}  // namespace cshapes
