// cshapes convert IN OUT: between mesh formats (by extension).
#include "core/io.h"
#include "experiments/command.h"

namespace cshapes::cli {
namespace {

struct ConvertArgs {
  std::string input, output;
  bool binary = false;
} args;

int run() {
  Mesh mesh = read_mesh(args.input);
  WriteOptions wo;
  wo.binary = args.binary;
  write_mesh(args.output, mesh, wo);
  note("wrote " + args.output);
  return 0;
}

const bool registered = register_command(
    {{"convert"},
     "Convert a mesh between formats (OFF, PLY, OBJ, STL, TOSCA .vert/.tri in; OFF, PLY, OBJ, XYZ out)",
     [](CLI::App& app) {
       app.add_option("IN", args.input, "input mesh")->required();
       app.add_option("OUT", args.output, "output mesh; its extension picks the format")->required();
       app.add_flag("--binary", args.binary, "PLY output: binary little endian");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
