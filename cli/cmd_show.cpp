// cshapes show MESH [FORM] -o PICTURE.png [--title TEXT] [--label TEXT]... [--view pca|x|y|z]
// [--figure-format png|pdf|svg]: a picture of a mesh, or of a mesh and its canonical form side by side with
// the same colour per vertex (experiments/show_mesh.h).
#include <iostream>
#include <optional>

#include "cli/command.h"
#include "cshapes/experiments/show_mesh.h"

namespace cshapes::cli {
namespace cmd_show {
namespace {

struct ShowArgs {
  std::string mesh, form, output;
  std::vector<std::string> labels;
  FigureFormat figure_format = FigureFormat::png;
  ShowOptions options;
  bool json = false;
} args;

int run() {
  if (args.labels.size() > (args.form.empty() ? 1u : 2u))
    usage_fail("--label: ", args.labels.size(), " titles for ", args.form.empty() ? "1 panel" : "2 panels",
               " (one --label per panel: the mesh's, then the form's)");
  std::optional<FigureFormat> format;
  if (option_given("--figure-format")) format = args.figure_format;
  std::string picture;
  try {
    picture = picture_path(args.output, format);
  } catch (const Error& e) {
    throw UsageError(std::string("-o: ") + e.what());
  }
  require_output_not_input(picture, {args.mesh, args.form}, "-o");
  require_output_path(picture, show_picture_extensions());
  ShowPanel mesh = read_show_panel(args.mesh);
  std::optional<ShowPanel> form;
  if (!args.form.empty()) form = read_show_panel(args.form, true);
  if (!args.labels.empty()) mesh.title = args.labels[0];
  if (args.labels.size() > 1) form->title = args.labels[1];
  show_panels(mesh, form ? &*form : nullptr, picture, args.options);
  note("wrote " + picture);
  if (args.json) {
    nlohmann::json panels = nlohmann::json::array();
    panels.push_back({{"file", args.mesh}, {"title", mesh.title}});
    if (form) panels.push_back({{"file", args.form}, {"title", form->title}});
    std::cout << nlohmann::json{{"picture", picture}, {"view", args.options.view}, {"panels", panels}}.dump(2)
              << std::endl;
  }
  return kExitOk;
}

const bool registered = register_command(
    {{"show"},
     "Draw a mesh, or a mesh and its canonical form side by side with the same colour per vertex (PNG, PDF "
     "or SVG; needs a Python with matplotlib)",
     [](CLI::App& app) {
       app.add_option("MESH", args.mesh, "the mesh, in any format cshapes reads")->required();
       app.add_option("FORM", args.form,
                      "its canonical form (as `cshapes canon` writes it: one vertex row per vertex of MESH; "
                      "dropped vertices, valid = 0, are not drawn)");
       app.add_option(
              "-o,--output", args.output,
              "the picture, .png, .pdf or .svg (without an extension: --figure-format's); each vertex "
              "coloured by its place on MESH (principal coordinates as red, green, blue)")
           ->required();
       add_declared(app, show_options::kTitle, args.options.title);
       app.add_option(
              "--label", args.labels,
              "a panel's title, once per panel: the mesh's, then the form's (default: the mesh's file "
              "name; the form's method when its file records it, as `cshapes canon`'s PLY does, else "
              "its file name)")
           ->allow_extra_args(false);
       add_declared(app, show_options::kView, args.options.view)->capture_default_str();
       add_figure_format_option(app, args.figure_format);
       app.add_flag("--json", args.json, "print the summary as JSON");
     },
     run});

}  // namespace
}  // namespace cmd_show
}  // namespace cshapes::cli
