// A picture of a mesh, of its canonical form, or of both side by side (`cshapes show`, cshapes.show()), drawn
// by experiments/plots/show_figure.py with the paper figures' renderer (render_mesh.py's draw_mesh) through
// run_figure_script (experiments/figures.h).
//
// Both panels colour a vertex alike, by its place on the input mesh: its coordinates along the input's three
// principal axes as red, green and blue (scaled by the largest extent, so a thin axis shifts the colour
// little), so that the viewer sees which part of the form is which part of the body. Vertices a canonical
// form dropped (PLY rows with valid = 0 and NaN coordinates) and the faces that use them are not drawn.
#pragma once

#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct ShowOptions {
  std::string title;  // a line above the picture; "" for none (each panel is titled on its own)
  // One of show_views(): "pca" looks along the least spread, the longest extent horizontal; "x", "y", "z"
  // along that axis (shapes with a meaningful orientation).
  std::string view = "pca";
};

// The values ShowOptions::view takes ("pca", "x", "y", "z"): the renderer's own (render_mesh.py --view).
const std::vector<std::string>& show_views();
// The picture formats show_mesh_files writes, by extension: {"png", "pdf"}.
const std::vector<std::string>& show_picture_extensions();

// Draws the mesh file `mesh`, and beside it the mesh file `form` unless it is "" (a canonical form of `mesh`,
// as `cshapes canon` writes it: as many vertex rows as `mesh`, NaN rows allowed where valid = 0), into
// `picture` (.png or .pdf). Checked before anything is drawn, each a cshapes::Error naming the files: the
// picture is none of the inputs (check_output_not_input), has a known extension and a writable folder
// (check_output_path), both meshes read, and the vertex counts agree. The picture is written to a temporary
// file beside it and renamed into place, so an old picture stays whole when drawing fails. Throws
// cshapes::Error saying why when it cannot draw (no Python with matplotlib, the script failed).
void show_mesh_files(const std::string& mesh, const std::string& form, const std::string& picture,
                     const ShowOptions& options = {});

// The same for meshes in memory: `form` may be null (the mesh alone); form->V has as many rows as mesh.V and
// may hold non-finite rows (vertices a method dropped, not drawn); form->F empty: the mesh's faces. Written
// to temporary PLY files first; the panels are titled "mesh" and "canonical form".
void show_meshes(const Mesh& mesh, const Mesh* form, const std::string& picture,
                 const ShowOptions& options = {});

}  // namespace cshapes
