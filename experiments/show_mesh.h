// A picture of a mesh, of its canonical form, or of both side by side (`cshapes show`, cshapes.show()), drawn
// by experiments/plots/show_figure.py with the paper figures' renderer (render_mesh.py's draw_mesh) through
// run_figure_script (experiments/figures.h).
//
// The meshes are read by the library's reader (every format it reads: OFF, PLY, OBJ, STL, XYZ, ...) and
// handed to the script as temporary binary PLY files, so the script reads one format only. Each panel is
// titled: a form by the method that computed it when that is known (a PLY written by `cshapes canon` records
// it; a CanonicalForm in Python carries it), otherwise by its file's name; the caller may give any title
// instead.
//
// Both panels colour a vertex alike, by its place on the input mesh: its coordinates along the input's three
// principal axes as red, green and blue (scaled by the largest extent, so a thin axis shifts the colour
// little), so that the viewer sees which part of the form is which part of the body. Vertices a canonical
// form dropped (PLY rows with valid = 0 and NaN coordinates) and the faces that use them are not drawn.
// A panel is 3.5 in wide, a column of a two-column paper, with 8 pt titles: the pair fills the page's width.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"
#include "cshapes/support/figure_format.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

struct ShowOptions {
  std::string title;  // a line above the picture; "" for none (each panel is titled on its own)
  // One of show_views(): "pca" looks along the least spread, the longest extent horizontal; "x", "y", "z"
  // along that axis (shapes with a meaningful orientation).
  std::string view = "pca";
};

// One panel of the picture: a mesh in memory and its title.
struct ShowPanel {
  // V: one row per vertex; a form's rows may be non-finite (vertices a method dropped: not drawn). F: the
  // faces; empty for a form drawn with its mesh's faces, or for a point cloud.
  Mesh mesh;
  std::string title;  // the panel's title ("" for none)
  std::string file;   // the file it was read from, named in messages and never written over; "" in memory
};

// The values ShowOptions::view takes ("pca", "x", "y", "z"): the renderer's own (render_mesh.py --view).
const std::vector<std::string>& show_views();
// The picture formats show_panels writes, by extension: figure_format_names(), {"png", "pdf", "svg"}.
const std::vector<std::string>& show_picture_extensions();

// The options a user sets, each declared once (support/option_declaration.h): `cshapes show`'s flags and
// show()'s keywords.
namespace show_options {
inline const OptionDeclaration kTitle{"title", "--title", "a line above the picture"};
inline const OptionDeclaration kView{
    "view", "--view",
    "pca: look along the direction of least spread, the longest extent horizontal; x, y, z: along that axis",
    std::nullopt, show_views()};
}  // namespace show_options

// The method recorded in a mesh file's PLY comments ("coulomb" from the line "comment method coulomb" that
// `cshapes canon` writes); "" when it has none (any other file).
std::string recorded_method(const std::vector<std::string>& comments);
// A form's default title: "Coulomb canonical form" for a registered method's name (its title), "NAME
// canonical form" for another name, "canonical form" for "".
std::string form_panel_title(const std::string& method);

// A mesh file as a panel, read by the library's reader: every vertex row of the file (rows a canonical form
// dropped, valid = 0, come back as NaN rows in their place, with the faces on them left out), so that a form
// lines up row by row with its mesh. Titled by the file's name; a form (`form`) by its recorded method when
// it has one (form_panel_title). Throws cshapes::Error naming the file when it cannot be read.
ShowPanel read_show_panel(const std::string& path, bool form = false);

// The picture's path when `format` is asked for: `picture` itself when its extension is that format's, or
// when no format is asked for; picture + ".EXT" when it has no extension that is a picture format's ("fig" ->
// "fig.svg"). Throws cshapes::Error naming both when its extension is another picture format's.
std::string picture_path(const std::string& picture, std::optional<FigureFormat> format);

// Draws `mesh`, and beside it `form` unless it is null (a canonical form of the mesh: as many vertex rows;
// empty faces: the mesh's), into `picture` (.png, .pdf or .svg). Checked before anything is drawn, each a
// cshapes::Error naming the files: the picture is none of the panels' files (check_output_not_input), has a
// known extension and a writable folder (check_output_path), the view is known, and the vertex counts agree.
// The picture is written to a temporary file beside it and renamed into place, so an old picture stays whole
// when drawing fails. Throws cshapes::Error saying why when it cannot draw (no Python with matplotlib, the
// script failed: its own message).
void show_panels(const ShowPanel& mesh, const ShowPanel* form, const std::string& picture,
                 const ShowOptions& options = {});

// show_panels for two files (`form` "" for the mesh alone), each read by read_show_panel.
void show_mesh_files(const std::string& mesh, const std::string& form, const std::string& picture,
                     const ShowOptions& options = {});

// show_panels for meshes in memory, titled "mesh" and "canonical form".
void show_meshes(const Mesh& mesh, const Mesh* form, const std::string& picture,
                 const ShowOptions& options = {});

}  // namespace cshapes
