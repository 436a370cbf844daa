// cshapes show MESH [FORM] -o PICTURE.png [--title TEXT] [--view pca|x|y|z]: a picture of a mesh, or of a
// mesh and its canonical form side by side with the same colour per vertex (experiments/show_mesh.h).
#include "cli/command.h"
#include "cshapes/experiments/show_mesh.h"

namespace cshapes::cli {
namespace cmd_show {
namespace {

struct ShowArgs {
  std::string mesh, form, output;
  ShowOptions options;
} args;

int run() {
  require_output_not_input(args.output, {args.mesh, args.form}, "-o");
  require_output_path(args.output, show_picture_extensions());
  show_mesh_files(args.mesh, args.form, args.output, args.options);
  note("wrote " + args.output);
  return kExitOk;
}

const bool registered = register_command(
    {{"show"},
     "Draw a mesh, or a mesh and its canonical form side by side with the same colour per vertex (PNG or "
     "PDF; needs a Python with matplotlib)",
     [](CLI::App& app) {
       app.add_option("MESH", args.mesh, "the mesh")->required();
       app.add_option("FORM", args.form,
                      "its canonical form (as `cshapes canon` writes it: one vertex row per vertex of MESH; "
                      "dropped vertices, valid = 0, are not drawn)");
       app.add_option("-o,--output", args.output,
                      "the picture, .png or .pdf; each vertex coloured by its place on MESH (principal "
                      "coordinates as red, green, blue)")
           ->required();
       app.add_option("--title", args.options.title, "a line above the picture");
       app.add_option(
              "--view", args.options.view,
              "pca: look along the direction of least spread, the longest extent horizontal; x, y, z: "
              "along that axis")
           ->capture_default_str()
           ->check(one_of(show_views()));
     },
     run});

}  // namespace
}  // namespace cmd_show
}  // namespace cshapes::cli
