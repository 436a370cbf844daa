// experiments/show_mesh.h and `cshapes show`: a generated biped and its `cshapes canon` form drawn side by
// side into a PNG; a form of another vertex count, a picture that is an input and an unknown picture format
// refused before anything is written; a form's dropped vertices (NaN rows, valid = 0) left out of the
// drawing. The drawing needs a Python with matplotlib: without one, the tests that draw are skipped.
#include "cshapes/experiments/show_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/experiments/figures.h"
#include "tests/test_support.h"

namespace cshapes {
namespace show_mesh_test {

namespace fs = std::filesystem;

constexpr int kDataError = 1;  // README's exit codes: an input that is invalid
constexpr int kUsage = 2;      // an output path that cannot be written

std::string q(const std::string& path) {
  return "'" + path + "'";
}

struct Biped {
  std::string dir, mesh, form;
};
// A generated biped (about 600 vertices) and its classical-MDS form, both by the CLI.
Biped biped(const std::string& tag) {
  Biped b;
  b.dir = test::scratch_dir(tag);
  const std::string generate = "-q generate articulated --class biped --poses 1 --vertices 600 --seed 3 --out ";
  const test::CliResult generated = test::run_cli(generate + q(b.dir));
  EXPECT_EQ(generated.exit_code, 0) << generated.err;
  b.mesh = b.dir + "/biped0.off";
  b.form = b.dir + "/form.ply";
  const test::CliResult canon =
      test::run_cli("-q canon " + q(b.mesh) + " -o " + q(b.form) + " --method cmds");
  EXPECT_EQ(canon.exit_code, 0) << canon.err;
  return b;
}

// The width and height of a PNG file, from its IHDR chunk; {0, 0} when the file is no PNG.
std::pair<long, long> png_size(const std::string& path) {
  const std::string bytes = read_file(path);
  if (bytes.size() < 24 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 || bytes.compare(12, 4, "IHDR") != 0)
    return {0, 0};
  const auto big_endian = [&](std::size_t at) {
    long value = 0;
    for (std::size_t k = 0; k < 4; ++k) value = value * 256 + static_cast<unsigned char>(bytes[at + k]);
    return value;
  };
  return {big_endian(16), big_endian(20)};
}

bool can_draw() {
  return !find_python("matplotlib, numpy").empty();
}

TEST(ShowMesh, TheMeshAndItsFormSideBySideMakeAWidePng) {
  if (!can_draw()) GTEST_SKIP() << "no Python with matplotlib and numpy";
  const Biped b = biped("show-pair");
  const std::string picture = b.dir + "/pair.png";
  const test::CliResult r =
      test::run_cli("-q show " + q(b.mesh) + " " + q(b.form) + " -o " + q(picture) + " --title 'a biped'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto [width, height] = png_size(picture);
  EXPECT_GE(height, 200);
  EXPECT_LE(height, 4000);
  EXPECT_GE(width, 2 * height - 50) << "two panels side by side";
  const auto [alone_width, alone_height] = [&] {
    const test::CliResult one = test::run_cli("-q show " + q(b.mesh) + " -o " + q(b.dir + "/one.png"));
    EXPECT_EQ(one.exit_code, 0) << one.err;
    return png_size(b.dir + "/one.png");
  }();
  EXPECT_EQ(alone_height, height);
  EXPECT_LT(alone_width, width) << "one panel";
  for (const fs::directory_entry& entry : fs::directory_iterator(b.dir))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "left behind: " << entry.path();
  fs::remove_all(b.dir);
}

TEST(ShowMesh, AFormsDroppedVerticesAreLeftOut) {
  if (!can_draw()) GTEST_SKIP() << "no Python with matplotlib and numpy";
  const Biped b = biped("show-dropped");
  Mesh form = read_mesh(b.form);
  Eigen::VectorXd valid = Eigen::VectorXd::Ones(form.num_vertices());
  for (Index i = 0; i < 40; ++i) {
    valid[3 * i] = 0;
    form.V.row(3 * i).setConstant(std::nan(""));
  }
  WriteOptions options;
  options.scalars.push_back({"valid", valid});
  const std::string dropped = b.dir + "/dropped.ply";
  write_mesh(dropped, form, options);
  const std::string picture = b.dir + "/dropped.png";
  EXPECT_NO_THROW(show_mesh_files(b.mesh, dropped, picture));
  EXPECT_GT(png_size(picture).first, 0);
  // In memory the same: non-finite rows are the dropped ones.
  const std::string from_arrays = b.dir + "/arrays.pdf";
  EXPECT_NO_THROW(show_meshes(read_mesh(b.mesh), &form, from_arrays));
  EXPECT_EQ(read_file(from_arrays).rfind("%PDF", 0), 0u);
  fs::remove_all(b.dir);
}

TEST(ShowMesh, AFormOfAnotherVertexCountIsRefusedNamingBothFiles) {
  const Biped b = biped("show-mismatch");
  const std::string other = b.dir + "/roll.off";
  ASSERT_EQ(test::run_cli("-q generate swissroll -o " + q(other)).exit_code, 0);
  const std::string picture = b.dir + "/mismatch.png";
  const test::CliResult r = test::run_cli("-q show " + q(b.mesh) + " " + q(other) + " -o " + q(picture));
  EXPECT_EQ(r.exit_code, kDataError) << r.err;
  EXPECT_EQ(r.err.rfind("cshapes show: error: ", 0), 0u) << r.err;
  for (const std::string& named :
       {b.mesh, other, std::string("561"), std::to_string(read_mesh(b.mesh).num_vertices())})
    EXPECT_NE(r.err.find(named), std::string::npos) << named << " not in: " << r.err;
  EXPECT_FALSE(fs::exists(picture));
  EXPECT_THROW(show_mesh_files(b.mesh, other, picture), Error);
  EXPECT_FALSE(fs::exists(picture));
  fs::remove_all(b.dir);
}

TEST(ShowMesh, APictureThatIsAnInputOrOfAnotherFormatIsRefused) {
  const Biped b = biped("show-refusals");
  const std::string mesh_bytes = read_file(b.mesh), form_bytes = read_file(b.form);
  for (const std::string& output : {b.mesh, b.form, b.dir + "/./biped0.off"}) {
    const test::CliResult r = test::run_cli("-q show " + q(b.mesh) + " " + q(b.form) + " -o " + q(output));
    EXPECT_EQ(r.exit_code, kUsage) << r.err;
    EXPECT_NE(r.err.find("is the input"), std::string::npos) << r.err;
  }
  EXPECT_EQ(read_file(b.mesh), mesh_bytes);
  EXPECT_EQ(read_file(b.form), form_bytes);
  const test::CliResult jpeg = test::run_cli("-q show " + q(b.mesh) + " -o " + q(b.dir + "/p.jpg"));
  EXPECT_EQ(jpeg.exit_code, kUsage) << jpeg.err;
  EXPECT_NE(jpeg.err.find(".png"), std::string::npos) << jpeg.err;
  EXPECT_FALSE(fs::exists(b.dir + "/p.jpg"));
  EXPECT_THROW(show_mesh_files(b.mesh, "", b.mesh), Error);
  EXPECT_THROW(show_mesh_files(b.mesh, "", b.dir + "/p.png", ShowOptions{"", "sideways"}), Error);
  fs::remove_all(b.dir);
}

// Issue 60: every format the library reads (the script only ever sees PLY), a form titled by the method its
// file records, a form dropped rows back in their place, and the picture's format from --figure-format.
TEST(ShowMesh, PanelsFromAnyFormatTitledByTheirMethod) {
  const Biped b = biped("show-panels");
  const std::string obj = b.dir + "/biped0.obj";
  ASSERT_EQ(test::run_cli("-q convert " + q(b.mesh) + " " + q(obj)).exit_code, 0);
  const ShowPanel mesh = read_show_panel(obj);
  EXPECT_EQ(mesh.title, "biped0.obj");
  EXPECT_EQ(mesh.file, obj);
  EXPECT_EQ(mesh.mesh.V.rows(), read_mesh(b.mesh).num_vertices());
  const ShowPanel form = read_show_panel(b.form, true);
  EXPECT_EQ(form.title, "classical MDS canonical form");  // `cshapes canon` records "method cmds"
  EXPECT_EQ(read_show_panel(b.form).title, "form.ply");   // as a mesh: its file
  EXPECT_EQ(recorded_method({"cshapes", "method coulomb"}), "coulomb");
  EXPECT_EQ(recorded_method({"cshapes"}), "");
  EXPECT_EQ(form_panel_title("mine"), "mine canonical form");
  // A form's dropped rows come back in place, NaN, so that it lines up with its mesh.
  Mesh dropped = read_mesh(b.form);
  Eigen::VectorXd valid = Eigen::VectorXd::Ones(dropped.num_vertices());
  valid[5] = 0;
  dropped.V.row(5).setConstant(std::nan(""));
  WriteOptions written;
  written.scalars.push_back({"valid", valid});
  write_mesh(b.dir + "/dropped.ply", dropped, written);
  const ShowPanel back = read_show_panel(b.dir + "/dropped.ply", true);
  ASSERT_EQ(back.mesh.V.rows(), dropped.V.rows());
  EXPECT_FALSE(back.mesh.V.row(5).allFinite());
  EXPECT_EQ(back.mesh.V.row(6), dropped.V.row(6));
  EXPECT_EQ(picture_path("p.png", std::nullopt), "p.png");
  EXPECT_EQ(picture_path("p.svg", FigureFormat::svg), "p.svg");
  EXPECT_EQ(picture_path("p", FigureFormat::pdf), "p.pdf");
  EXPECT_THROW(picture_path("p.png", FigureFormat::svg), Error);
  if (can_draw()) {
    const test::CliResult r =
        test::run_cli("-q show " + q(obj) + " " + q(b.form) + " -o " + q(b.dir + "/p.svg"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string svg = read_file(b.dir + "/p.svg");
    EXPECT_NE(svg.find("classical MDS canonical form"), std::string::npos);
    EXPECT_NE(svg.find("biped0.obj"), std::string::npos);
  }
  fs::remove_all(b.dir);
}

TEST(ShowMesh, WithoutItsScriptItFailsSayingWhyAndKeepsTheOldPicture) {
  const Biped b = biped("show-no-script");
  const std::string empty = b.dir + "/no-plots";
  fs::create_directories(empty);
  const std::string picture = b.dir + "/old.png";
  test::write_text(picture, "old");
  setenv("CSHAPES_PLOTS", empty.c_str(), 1);
  const test::CliResult r = test::run_cli("-q show " + q(b.mesh) + " -o " + q(picture));
  unsetenv("CSHAPES_PLOTS");
  EXPECT_EQ(r.exit_code, kDataError) << r.err;
  EXPECT_NE(r.err.find("show_figure.py"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(picture), "old");
  fs::remove_all(b.dir);
}

}  // namespace show_mesh_test
}  // namespace cshapes
