#include "tests/test_support.h"

#include "cshapes/support/error.h"

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "cshapes/data/articulated.h"
#include "cshapes/data/dataset.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/mesh/remesh.h"

namespace cshapes::test {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

namespace fs = std::filesystem;

std::string data_dir() {
  if (const char* env = std::getenv("CSHAPES_DATA"); env && *env && fs::is_directory(env)) return env;
  fs::path p = fs::path(CSHAPES_SOURCE_DIR) / ".." / "shared" / "data";
  if (fs::is_directory(p)) return fs::canonical(p).string();
  return "";
}

std::string tosca5k(const std::string& name) { return data_dir() + "/tosca5k/" + name + ".off"; }

std::string scratch_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  fs::path p = fs::temp_directory_path() /
               ("cshapes-test-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

namespace {
std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

CliResult run_cli(const std::string& arguments) {
  std::string dir = scratch_dir("cli");
  std::string out = dir + "/stdout", err = dir + "/stderr";
  // $CSHAPES_CLI runs the tests against another build (e.g. to see a new test fail on an older one), as the
  // Python tests' fixture does.
  const char* env = std::getenv("CSHAPES_CLI");
  const std::string cli = env && *env ? env : CSHAPES_CLI;
  std::string command = "'" + cli + "' " + arguments + " >'" + out + "' 2>'" + err + "'";
  int status = std::system(command.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  fs::remove_all(dir);
  return r;
}

double mean_relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact, double min_distance) {
  double sum = 0;
  int count = 0;
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (exact[i] > min_distance) {
      sum += std::abs(d[i] - exact[i]) / exact[i];
      ++count;
    }
  EXPECT_GT(count, 0);
  return count ? sum / count : 0.0;
}

double signed_volume(const Mesh& m) {
  double v = 0;
  for (Index f = 0; f < m.num_faces(); ++f)
    v += m.V.row(m.F(f, 0)).dot(m.V.row(m.F(f, 1)).cross(m.V.row(m.F(f, 2)))) / 6;
  return v;
}

Mesh bent_sausage(double end_gap_angle) {
  constexpr double kPi = 3.14159265358979323846;
  Mesh m = icosphere(4);
  const double bend_radius = 3.0, half_length = bend_radius * (kPi - end_gap_angle / 2), radius = 1.0;
  for (Index i = 0; i < m.num_vertices(); ++i) {
    const double theta = m.V(i, 0) * half_length / bend_radius;
    const double rho = bend_radius + radius * m.V(i, 1);
    // (x, y, z) -> (θ, ρ, -z): the swap of x and y reverses orientation, the sign of z restores it.
    m.V.row(i) << rho * std::cos(theta), rho * std::sin(theta), -radius * m.V(i, 2);
  }
  // Isotropic triangles, so that edge-graph distances are close to surface geodesics.
  RemeshOptions o;
  o.target_vertices = 2000;
  return remesh(m, o).mesh;
}

Mesh obtuse_grid(int nx, int ny) {
  Mesh m;
  const double hx = 1.0 / (nx - 1), hy = 0.3 * hx;
  m.V.resize(nx * ny, 3);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) m.V.row(j * nx + i) << (i + 0.5 * (j % 2)) * hx, j * hy, 0.0;
  std::vector<Eigen::Vector3i> tris;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      int a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      if (j % 2 == 0) {
        tris.emplace_back(a, b, c);
        tris.emplace_back(b, d, c);
      } else {
        tris.emplace_back(a, d, c);
        tris.emplace_back(a, b, d);
      }
    }
  m.F.resize(tris.size(), 3);
  for (size_t f = 0; f < tris.size(); ++f) m.F.row(f) = tris[f].transpose();
  return m;
}

void write_text(const std::string& path, const std::string& text) {
  fs::path p(path);
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  std::ofstream(path) << text;
}

std::string generated_dataset(const std::string& dir, int classes, int poses, long vertices) {
  ArticulatedDatasetOptions o;
  o.classes = classes;
  o.poses = poses;
  o.noisy = 0;
  o.rest.target_vertices = vertices;
  std::vector<DatasetEntry> entries;
  for (const ArticulatedShape& s : make_articulated_dataset(o)) {
    DatasetEntry e;
    e.path = dir + "/" + s.name + ".off";
    e.name = s.name;
    e.class_name = s.class_name;
    e.pose = s.pose;
    write_off_fixed(e.path, s.mesh);
    entries.push_back(e);
  }
  write_manifest(dir + "/manifest.csv", entries);
  return dir + "/manifest.csv";
}

std::vector<nlohmann::json> left_out_failures(const nlohmann::json& report) {
  std::vector<nlohmann::json> left_out;
  for (const nlohmann::json& f : report["failures"]) {
    if (f["left_out"].get<bool>())
      left_out.push_back(f);
    else
      EXPECT_NE(f["reason"].get<std::string>().find("not converged"), std::string::npos) << f.dump(2);
  }
  return left_out;
}

}  // namespace cshapes::test
