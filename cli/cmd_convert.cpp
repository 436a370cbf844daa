// cshapes convert IN OUT: between mesh formats (by extension), keeping PLY per-vertex scalars and colours.
// A PLY's invalid vertices (NaN rows with valid = 0, as canonical forms write dropped vertices) are dropped
// with the faces on them, and said.
#include <iostream>

#include "cshapes/mesh/io.h"
#include "cli/command.h"

namespace cshapes::cli {
namespace cmd_convert {
namespace {

struct ConvertArgs {
  std::string input, output;
  bool binary = false;
  bool no_validate = false;
  bool json = false;
} args;

int run() {
  require_mesh_output_path(args.output);
  require_output_not_input(args.output, {args.input}, "OUT");
  ReadOptions read_options;
  read_options.validate = !args.no_validate;
  MeshFile file = read_mesh_file(args.input, read_options);
  WriteOptions write_options;
  write_options.binary = args.binary;
  write_options.scalars = file.scalars;
  write_options.colors = file.colors;
  // Rows a canonical form marks invalid (NaN, valid = 0) are not written: the output holds the valid part.
  warn_invalid_vertices_dropped(file, args.input);
  write_mesh(args.output, file.mesh, write_options);
  note("wrote " + args.output + " (" + std::to_string(file.mesh.num_vertices()) + " vertices, " +
       std::to_string(file.mesh.num_faces()) + " triangles)");
  if (args.json)
    std::cout << nlohmann::json{{"input", args.input},
                                {"output", args.output},
                                {"vertices", file.mesh.num_vertices()},
                                {"faces", file.mesh.num_faces()},
                                {"binary", args.binary}}
                     .dump(2)
              << std::endl;
  return 0;
}

const bool registered = register_command(
    {{"convert"},
     "Convert a mesh between formats (OFF, PLY, OBJ, STL, TOSCA .vert/.tri, XYZ in; OFF, PLY, OBJ, XYZ out)",
     [](CLI::App& app) {
       app.add_option("IN", args.input, "input mesh or point cloud (.off .ply .obj .stl .vert/.tri .xyz)")
           ->required();
       app.add_option("OUT", args.output, "output file; its extension picks the format (.off .ply .obj .xyz)")
           ->required();
       app.add_flag("--binary", args.binary, "PLY output: binary little endian instead of ASCII");
       app.add_flag("--no-validate", args.no_validate,
                    "convert meshes that fail validation (degenerate faces, non-manifold edges, ...)");
       app.add_flag("--json", args.json, "print the summary as JSON");
     },
     run});

}  // namespace
}  // namespace cmd_convert
}  // namespace cshapes::cli
