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
#include "cshapes/pipeline/canonical_form_methods.h"

namespace cshapes {

namespace fs = std::filesystem;

namespace {

// A name no other process or thread uses at the same time: "-PID-N".
std::string unique_suffix() {
  static std::atomic<long> counter{0};
  return "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
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

// " FILE" for a panel read from a file, "" for one in memory: messages name the files.
std::string named(const ShowPanel& panel) {
  return panel.file.empty() ? "" : " " + panel.file;
}

// A panel's mesh as the script can draw it: some finite row, faces within the rows.
void check_panel(const ShowPanel& panel, const std::string& what) {
  const Mesh& m = panel.mesh;
  const std::string name = what + named(panel);
  CSHAPES_REQUIRE(m.V.rows() > 0, name, ": no vertex to draw");
  bool any_finite = false;
  for (Index i = 0; i < m.V.rows() && !any_finite; ++i) any_finite = m.V.row(i).allFinite();
  CSHAPES_REQUIRE(any_finite, name, ": no vertex to draw (every row is NaN: dropped)");
  if (m.F.rows() > 0 && (m.F.minCoeff() < 0 || m.F.maxCoeff() >= m.V.rows()))
    fail(name, ": faces use vertex indices outside 0..", m.V.rows() - 1);
}

// Writes a panel's mesh as binary PLY for the script; rows that are not finite (dropped) are written as a
// canonical form writes them, NaN with valid = 0, and the faces on them are left for the script to skip.
void write_panel(const std::string& path, const Mesh& mesh) {
  WriteOptions written;
  written.binary = true;
  Eigen::VectorXd valid(mesh.V.rows());
  for (Index i = 0; i < mesh.V.rows(); ++i) valid[i] = mesh.V.row(i).allFinite() ? 1.0 : 0.0;
  if (valid.minCoeff() == 0) {
    written.scalars.push_back({"valid", valid});
    Mesh drawn = mesh;
    drawn.V = (valid.array() > 0).replicate(1, 3).select(mesh.V, std::nan(""));
    write_mesh(path, drawn, written);
  } else {
    write_mesh(path, mesh, written);
  }
}

}  // namespace

const std::vector<std::string>& show_views() {
  static const std::vector<std::string> views = {"pca", "x", "y", "z"};
  return views;
}

const std::vector<std::string>& show_picture_extensions() {
  return figure_format_names();
}

std::string recorded_method(const std::vector<std::string>& comments) {
  for (const std::string& comment : comments)
    if (comment.rfind("method ", 0) == 0) {
      const size_t start = comment.find_first_not_of(' ', 7);
      if (start != std::string::npos) return comment.substr(start);
    }
  return "";
}

std::string form_panel_title(const std::string& method) {
  return method.empty() ? "canonical form" : canonical_form_method_title(method) + " canonical form";
}

ShowPanel read_show_panel(const std::string& path, bool form) {
  const MeshFile file = read_mesh_file(path);
  ShowPanel panel;
  panel.file = path;
  const std::string method = form ? recorded_method(file.comments) : "";
  panel.title = method.empty() ? fs::path(path).filename().string() : form_panel_title(method);
  if (file.file_vertex.empty()) {
    panel.mesh = file.mesh;
    return panel;
  }
  // The rows the reader left out come back as NaN rows in their place: a form lines up with its mesh.
  const Index rows = file.mesh.num_vertices() + file.invalid_vertices;
  panel.mesh.V = Points::Constant(rows, 3, std::nan(""));
  for (Index k = 0; k < file.mesh.num_vertices(); ++k)
    panel.mesh.V.row(file.file_vertex[static_cast<size_t>(k)]) = file.mesh.V.row(k);
  panel.mesh.F = file.mesh.F;
  for (Index f = 0; f < panel.mesh.F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      panel.mesh.F(f, c) = static_cast<int>(file.file_vertex[static_cast<size_t>(panel.mesh.F(f, c))]);
  return panel;
}

std::string picture_path(const std::string& picture, std::optional<FigureFormat> format) {
  if (!format) return picture;
  const std::string extension = file_extension(picture);
  const std::vector<std::string>& formats = figure_format_names();
  if (extension == to_string(*format)) return picture;
  if (std::find(formats.begin(), formats.end(), extension) == formats.end())
    return picture + "." + to_string(*format);
  fail(picture, ": a .", extension, " picture, but the figure format asked for is ", to_string(*format),
       " (give the picture that extension, or none)");
}

void show_panels(const ShowPanel& mesh, const ShowPanel* form, const std::string& picture,
                 const ShowOptions& options) {
  check_view(options.view);
  std::vector<std::string> files;
  for (const ShowPanel* panel : {&mesh, form})
    if (panel && !panel->file.empty()) files.push_back(panel->file);
  if (!files.empty()) check_output_not_input(picture, files, "the picture");
  check_output_path(picture, show_picture_extensions());
  check_panel(mesh, "the mesh");
  if (form) {
    check_panel(*form, "the form");
    if (form->mesh.V.rows() != mesh.mesh.V.rows())
      fail("the form", named(*form), " has ", form->mesh.V.rows(), " vertices but the mesh", named(mesh),
           " has ", mesh.mesh.V.rows(), ": a canonical form keeps its mesh's vertices, one row each",
           form->file.empty() ? "" : " (cshapes canon MESH -o FORM)");
  }
  std::error_code ec;
  const fs::path folder = fs::temp_directory_path() / ("cshapes-show" + unique_suffix());
  fs::create_directories(folder);
  try {
    const std::string mesh_file = (folder / "mesh.ply").string(), form_file = (folder / "form.ply").string();
    write_panel(mesh_file, mesh.mesh);
    std::vector<std::string> titles = {mesh.title};
    if (form) {
      write_panel(form_file, Mesh{form->mesh.V, form->mesh.F.rows() > 0 ? form->mesh.F : mesh.mesh.F});
      titles.push_back(form->title);
    }
    draw(mesh_file, form ? form_file : "", picture, titles, options);
  } catch (...) {
    fs::remove_all(folder, ec);
    throw;
  }
  fs::remove_all(folder, ec);
}

void show_mesh_files(const std::string& mesh, const std::string& form, const std::string& picture,
                     const ShowOptions& options) {
  check_view(options.view);
  check_output_not_input(picture, {mesh, form}, "the picture");
  check_output_path(picture, show_picture_extensions());
  const ShowPanel mesh_panel = read_show_panel(mesh);
  if (form.empty()) return show_panels(mesh_panel, nullptr, picture, options);
  const ShowPanel form_panel = read_show_panel(form, true);
  show_panels(mesh_panel, &form_panel, picture, options);
}

void show_meshes(const Mesh& mesh, const Mesh* form, const std::string& picture, const ShowOptions& options) {
  const ShowPanel mesh_panel{mesh, "mesh", ""};
  if (!form) return show_panels(mesh_panel, nullptr, picture, options);
  const ShowPanel form_panel{*form, form_panel_title(""), ""};
  show_panels(mesh_panel, &form_panel, picture, options);
}

}  // namespace cshapes
