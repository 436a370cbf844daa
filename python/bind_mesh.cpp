// cshapes.read_mesh, write_mesh, mesh_info, geodesics, add_topological_noise, generate: meshes in and out of
// the library (mesh/io.h, pipeline/mesh_report.h, pipeline/mesh_geodesics.h, data/topological_noise.h,
// data/articulated.h, data/synthetic.h).
#include <pybind11/stl.h>

#include "cshapes/data/articulated.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/mesh_geodesics.h"
#include "cshapes/pipeline/mesh_report.h"
#include "cshapes/support/error.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/kwargs.h"
#include "python/progress.h"
#include "python/declared_options.h"

namespace cshapes::python {

namespace {

py::tuple mesh_tuple(const Mesh& mesh) {
  return py::make_tuple(to_numpy(mesh.V), to_numpy(mesh.F));
}

py::object read_mesh_py(const py::object& path_in, bool fields) {
  const std::string path = to_path(path_in, "path");
  MeshFile file;
  {
    Computing computing;
    file = read_mesh_file(path);
  }
  if (!fields) return mesh_tuple(file.mesh);
  py::dict scalars;
  for (const VertexScalar& s : file.scalars) scalars[s.name.c_str()] = to_numpy(s.values);
  if (file.colors.rows() > 0) {
    py::array_t<unsigned char> colors({static_cast<py::ssize_t>(file.colors.rows()), py::ssize_t{3}});
    auto w = colors.mutable_unchecked<2>();
    for (Index i = 0; i < file.colors.rows(); ++i)
      for (int c = 0; c < 3; ++c) w(i, c) = file.colors(i, c);
    scalars["colors"] = colors;
  }
  return py::make_tuple(to_numpy(file.mesh.V), to_numpy(file.mesh.F), scalars);
}

void write_mesh_py(const py::object& path_in, const py::object& V, const py::object& F, bool binary,
                   const py::kwargs& fields) {
  const std::string path = to_path(path_in, "path");
  Mesh mesh{to_points(V, "V", /*allow_nonfinite=*/true), to_faces(F, "F")};
  WriteOptions options;
  options.binary = binary;
  for (auto item : fields) {
    const std::string name = item.first.cast<std::string>();
    Eigen::VectorXd values = to_vector(item.second, name);
    CSHAPES_REQUIRE(values.size() == mesh.num_vertices(), name, ": ", values.size(), " values for ",
                    mesh.num_vertices(), " vertices");
    options.scalars.push_back({name, std::move(values)});
  }
  CSHAPES_REQUIRE(options.scalars.empty() || file_extension(path) == "ply", path,
                  ": per-vertex fields are written to .ply only");
  Computing computing;
  write_mesh(path, mesh, options);
}

py::object mesh_info_py(const py::object& V, const py::object& F) {
  const Mesh mesh = to_mesh(V, F);
  nlohmann::json j;
  {
    Computing computing;
    j = describe_mesh(mesh);
  }
  return to_python(j);
}

py::object geodesics_py(const py::object& V, const py::object& F, const py::object& sources,
                        const std::string& method, const py::object& heat_mode, bool strict,
                        const py::object& progress_in) {
  const Mesh mesh = to_mesh(V, F);
  MeshGeodesicsOptions options;
  options.geodesics.method = parse_geodesic_method(method);
  // As `cshapes geodesics --heat-mode`: given with another method, it would be ignored.
  if (!heat_mode.is_none()) {
    const bool heat = options.geodesics.method == GeodesicMethod::Heat ||
                      options.geodesics.method == GeodesicMethod::HeatCgal;
    CSHAPES_REQUIRE(heat, "geodesics(): heat_mode applies to method 'heat' or 'heat-cgal' only, not '", method,
                    "'");
    options.geodesics.heat_mode = parse_cgal_heat_mode(py::str(heat_mode).cast<std::string>());
  }
  options.strict = strict;
  const PythonProgress progress(progress_in, "geodesics");
  options.geodesics.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
  std::vector<int> rows;
  // One index: an int, a numpy integer or a 0-d array; a numpy array of indices is a sequence of them (numpy
  // arrays have __index__ too, which raised TypeError for np.array([0, 5])).
  const bool array = py::isinstance<py::array>(sources);
  const bool one = !sources.is_none() && (array ? py::array(sources.cast<py::array>()).ndim() == 0
                                                : py::hasattr(sources, "__index__"));
  if (one) {
    const py::object index = sources.attr("__index__")();
    const Index n = mesh.num_vertices();
    long long value = -1;
    try {
      value = index.cast<long long>();
    } catch (const py::cast_error&) {  // beyond 64 bits (2**63 gave "Unable to cast Python instance")
    }
    CSHAPES_REQUIRE(value >= 0 && value < n, "geodesics(): sources: ", py::str(index).cast<std::string>(),
                    " is not a vertex index (expected 0..", n - 1, ")");
    rows.push_back(static_cast<int>(value));
  } else if (!sources.is_none()) {
    for (const Eigen::VectorXd::Scalar s : to_vector(sources, "sources")) {
      CSHAPES_REQUIRE(s == std::floor(s), "sources: expected vertex indices, got ", s);
      rows.push_back(static_cast<int>(s));
    }
    CSHAPES_REQUIRE(!rows.empty(),
                    "geodesics(): sources: an empty list; give vertex indices, or None for all pairs");
  }
  MeshGeodesics prepared;
  Eigen::MatrixXd D_rows;
  DistanceMatrix D;
  progress.run([&] {
    prepared = prepare_mesh_geodesics(mesh, options);
    if (sources.is_none())
      D = geodesic_all_pairs(mesh, prepared, options);
    else
      D_rows = geodesic_rows(mesh, prepared, rows, options);
  });
  if (prepared.repaired.changed())
    warn("cshapes.geodesics: " + prepared.repaired.text +
         "; distances are given at the input's vertices (NaN where a vertex was dropped)");
  if (!prepared.warning.empty()) warn("cshapes.geodesics: " + prepared.warning);
  if (sources.is_none()) return to_numpy(D);
  if (one) return to_numpy(Eigen::VectorXd(D_rows.row(0).transpose()));
  return to_numpy(D_rows);
}

py::object add_topological_noise_py(const py::object& V, const py::object& F, const py::kwargs& kwargs) {
  const Mesh mesh = to_mesh(V, F);
  Kwargs k(kwargs, "add_topological_noise");
  TopologicalNoiseOptions o;
  o.glue_count = k.int32(noise_options::kGlue, o.glue_count);
  o.seed =
      static_cast<std::uint64_t>(k.integer(noise_options::kSeed.keyword, static_cast<long long>(o.seed), 0));
  o.max_gap = k.number(noise_options::kMaxGap, o.max_gap);
  o.gap_edge_lengths = k.number(noise_options::kGapEdges, o.gap_edge_lengths);
  o.min_ratio = k.number(noise_options::kMinRatio, o.min_ratio);
  o.min_geodesic_fraction = k.number(noise_options::kMinFraction, o.min_geodesic_fraction);
  o.min_separation_fraction = k.number(noise_options::kSeparation, o.min_separation_fraction);
  o.relax_steps = k.int32(noise_options::kRelax, o.relax_steps);
  o.geodesic.method =
      parse_geodesic_method(k.text(noise_options::kGeodesics.keyword, to_string(o.geodesic.method)));
  const bool info = k.flag("return_info", false);
  const PythonProgress progress(k.object("progress"), "add_topological_noise");
  o.geodesic.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
  k.done();
  const TopologicalNoiseResult r = progress.run([&] { return glue_topological_noise(mesh, o); });
  if (!info) return mesh_tuple(r.mesh);
  return py::make_tuple(to_numpy(r.mesh.V), to_numpy(r.mesh.F), to_python(topological_noise_json(r)));
}

py::object generate_py(const std::string& kind, const py::kwargs& kwargs) {
  Kwargs k(kwargs, "generate");
  if (kind == "swissroll") {
    SwissRollOptions o;
    const long n = k.int32("vertices", 561, generate_limits::kVertices);
    k.done();
    std::tie(o.nu, o.nv) = swiss_roll_grid(n);
    return mesh_tuple(swiss_roll(o));
  }
  if (kind == "icosphere") {
    const int subdivisions = k.int32("subdivisions", 3);
    const double radius = k.number("radius", 1.0, number_limit("radius", 0, kNoLimit, /*minimum_open=*/true));
    k.done();
    CSHAPES_REQUIRE(subdivisions >= 0 && subdivisions <= 8,
                    "generate('icosphere'): subdivisions: expected 0..8, got ", subdivisions);
    return mesh_tuple(icosphere(subdivisions, radius));
  }
  if (kind == "articulated") {
    ArticulatedOptions o;
    const std::string class_name = k.text("class_", "biped");
    o.poses = k.int32("poses", o.poses, generate_limits::kPoses);
    o.seed = static_cast<std::uint64_t>(k.integer("seed", 0, 0));
    o.rest.target_vertices =
        k.int32("vertices", static_cast<int>(o.rest.target_vertices), generate_limits::kVertices);
    o.amplitude = k.number("amplitude", o.amplitude, generate_limits::kAmplitude);
    k.done();
    o.progress = stop_on_python_signals();  // Ctrl-C (python/interrupt.h)
    ArticulatedClass c;
    {
      Computing computing;
      c = generate_articulated(class_name, o);
    }
    py::list poses;
    for (const Mesh& pose : c.poses) poses.append(mesh_tuple(pose));
    return poses;
  }
  if (kind == "hand") {
    const auto seed = static_cast<std::uint64_t>(k.integer("seed", 0, 0));
    const int glues = k.int32("glue", 3, generate_limits::kGlue);
    k.done();
    GluedHand h;
    {
      Computing computing;
      h = generate_glued_hand(seed, glues);
    }
    py::dict d;
    d["separated"] = mesh_tuple(h.separated);
    d["glued"] = mesh_tuple(h.glued);
    d["glued_pairs"] = h.glued_pairs;
    return d;
  }
  if (kind == "dataset") {
    ArticulatedDatasetOptions o;
    o.classes = k.int32("classes", o.classes, generate_limits::kClasses);
    o.poses = k.int32("poses", o.poses, generate_limits::kPoses);
    o.noisy = k.int32("noisy", o.noisy, generate_limits::kNoisy);
    o.glue_count = k.int32("glue", o.glue_count, generate_limits::kGlue);
    o.seed = static_cast<std::uint64_t>(k.integer("seed", 0, 0));
    o.rest.target_vertices =
        k.int32("vertices", static_cast<int>(o.rest.target_vertices), generate_limits::kVertices);
    const PythonProgress progress(k.object("progress"), "generate");
    k.done();
    o.progress = progress.fn();  // reports and Ctrl-C (python/progress.h)
    const std::vector<ArticulatedShape> shapes = progress.run([&] { return make_articulated_dataset(o); });
    py::list out;
    for (const ArticulatedShape& s : shapes) {
      py::dict d;
      d["name"] = s.name;
      d["class"] = s.class_name;
      d["pose"] = s.pose;
      d["noisy"] = s.noisy;
      d["V"] = to_numpy(s.mesh.V);
      d["F"] = to_numpy(s.mesh.F);
      d["glued_pairs"] = s.glued_pairs;
      out.append(d);
    }
    return out;
  }
  fail("generate(): unknown kind '", kind, "'; known: swissroll, icosphere, articulated, hand, dataset");
}

}  // namespace

void bind_mesh(py::module_& m) {
  declare_keywords("geodesics",
                   {&geodesic_options::kMethod, &geodesic_options::kHeatMode, &kStrictGeodesicsOption});
  declare_keywords("add_topological_noise", noise_options::kAll);
  // One-line docstrings: cshapes/_api.py documents the Python functions (signature, numpy sections).
  m.def("read_mesh", &read_mesh_py, py::arg("path"), py::kw_only(), py::arg("fields") = false,
        "Reads a mesh or point cloud: see help(cshapes.read_mesh).");
  m.def("write_mesh", &write_mesh_py, py::arg("path"), py::arg("V"), py::arg("F"), py::kw_only(),
        py::arg("binary") = false, "Writes a mesh: see help(cshapes.write_mesh).");
  m.def("mesh_info", &mesh_info_py, py::arg("V"), py::arg("F"),
        "Counts, topology, size and defects of a mesh: see help(cshapes.mesh_info).");
  m.def("geodesics", &geodesics_py, py::arg("V"), py::arg("F"), py::arg("sources") = py::none(),
        py::kw_only(), py::arg("method") = "heat", py::arg("heat_mode") = py::none(),
        py::arg("strict") = false, py::arg("progress") = py::none(),
        "Geodesic distances on a triangle mesh: see help(cshapes.geodesics).");
  m.def("add_topological_noise", &add_topological_noise_py, py::arg("V"), py::arg("F"),
        "Topological noise the paper's way: see help(cshapes.add_topological_noise).");
  m.def("generate", &generate_py, py::arg("kind"), "Shapes made here: see help(cshapes.generate).");
}

}  // namespace cshapes::python
