// Methods from outside (pipeline/outside_methods.h): the command and forms doors give what the program or the
// folder holds, the form contract refuses each kind of broken form by name, the cache key follows the door,
// and an experiment with a broken outside method leaves those shapes out for it alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cshapes/data/cache.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/support/error.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace cshapes {
namespace {

CanonicalFormOptions options_for(const std::string& method, const std::string& name = "ball.off") {
  CanonicalFormOptions o;
  o.method = method;
  o.name = name;
  return o;
}

OutsideDoor command(const std::string& text) {
  OutsideDoor door;
  door.kind = OutsideDoor::Kind::Command;
  door.text = text;
  return door;
}

TEST(OutsideMethods, ACommandDoorGivesTheFormItsProgramWrites) {
  const Mesh ball = icosphere(2);
  OutsideMethod m("ident", command("cp {mesh} {form.off}"));
  const CanonicalForm form = canonical_form(ball, options_for("ident"));
  ASSERT_EQ(form.X.rows(), ball.num_vertices());
  EXPECT_EQ((form.X - ball.V).cwiseAbs().maxCoeff(), 0.0);  // OFF is written to the last digit
  EXPECT_EQ(form.details.value("door", ""), "command");
  EXPECT_GT(form.details.value("peak_memory_bytes", 0.0), 0.0);
  ASSERT_TRUE(form.quality.has_value());
  EXPECT_TRUE(form.quality->ok);
  // The name is known while registered, and only then.
  EXPECT_NE(find_canonical_form_method("ident"), nullptr);
}

TEST(OutsideMethods, TheNameIsGoneAfterTheRunAndABuiltInNameIsRefused) {
  { OutsideMethod m("gone", command("cp {mesh} {form.off}")); }
  EXPECT_EQ(find_canonical_form_method("gone"), nullptr);
  EXPECT_NE(test::error_of([] { OutsideMethod m("lbo", command("cp {mesh} {form.off}")); }).find("cshapes's own"),
            std::string::npos);
  EXPECT_NE(test::error_of([] { parse_outside_method("x=sh:true"); }).find("cmd:COMMAND or forms:DIR"), std::string::npos);
  EXPECT_NE(test::error_of([] { parse_outside_method("x=cmd:true {mesh}"); }).find("no {form}"), std::string::npos);
  EXPECT_NE(test::error_of([] { parse_outside_method("a b=cmd:cp {mesh} {form}"); }).find("letters, digits"),
            std::string::npos);
}

// Each way an outside program can fail, as its shape's error: the reason by name, the program's last lines.
TEST(OutsideMethods, EachBrokenFormOrProgramIsRefusedByNameWithTheReason) {
  const Mesh ball = icosphere(1);
  const std::string n = std::to_string(ball.num_vertices());
  OutsideMethodSettings quick;
  quick.timeout_seconds = 0.5;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"awk 'NR==1{print \"nan 0 0\"; exit}' {mesh} > {form.xyz}; tail -n +3 {mesh} | head -n " +
           std::to_string(ball.num_vertices() - 1) + " >> {form.xyz}",
       "cannot be read"},
      {"tail -n +3 {mesh} | head -n 5 > {form.xyz}", "the form has 5 rows, expected one per vertex"},
      {"echo about to crash >&2; kill -SEGV $$", "signal 11"},
      {"echo boom >&2; exit 2", "exited with status 2; its last lines:\n    boom"},
      {"sleep 30", "ran past its limit of 0.5 s"},
      {"true {mesh}", "wrote no form"},
      {"for i in $(seq " + n + "); do echo 1 2 3; done > {form.xyz}", "collapsed"},
  };
  int k = 0;
  for (const auto& [text, expected] : cases) {
    const std::string name = "broken" + std::to_string(k++);
    OutsideMethod m(name, command(text.find("{mesh}") == std::string::npos ? text + " # {mesh} {form}" : text),
                    quick);
    const std::string message = test::error_of([&] { canonical_form(ball, options_for(name)); });
    EXPECT_NE(message.find("ball.off: method " + name), std::string::npos) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << text << "\n" << message;
  }
}

// A command door's programs run several at a time ahead of the pass (run_commands_ahead), which then takes
// each result, the form or the failure, without running the program again.
TEST(OutsideMethods, ProgramsRunSeveralAtATimeAheadAndThePassTakesTheirResults) {
  const std::string dir = test::scratch_dir("outside_ahead");
  // Each run says it started, then waits (up to 20 s) until every one of the three has started: only runs at
  // the same time all see that, so each leaves an "overlap" mark. The shape named "bad" then fails.
  const std::string command = "d=" + dir + "; echo run >> \"$d\"/runs.{name}; touch \"$d\"/started.{name}; "
      "i=0; while [ $(ls \"$d\" | grep -c started) -lt 3 ] && [ $i -lt 200 ]; do sleep 0.1; i=$((i+1)); done; "
      "[ $i -lt 200 ] && touch \"$d\"/overlap.{name}; [ {name} = bad ] && { echo bad shape >&2; exit 7; }; "
      "cp {mesh} {form.off}";
  OutsideMethod m("ahead", OutsideDoor{OutsideDoor::Kind::Command, command, {}, ""});
  std::vector<Mesh> meshes;
  for (int k = 0; k < 3; ++k) {
    meshes.push_back(icosphere(1));
    meshes.back().V *= 1.0 + k;
  }
  const std::vector<std::string> names = {"one.off", "two.off", "bad.off"};
  std::vector<ShapeAhead> shapes;
  for (size_t k = 0; k < 3; ++k) shapes.push_back({&meshes[k], names[k]});
  run_commands_ahead(DiskCache(), shapes, options_for("ahead"), 3);
  for (const std::string shape : {"one", "two", "bad"}) {
    EXPECT_TRUE(fs::exists(dir + "/overlap." + shape)) << shape << " ran alone";
    EXPECT_TRUE(fs::exists(dir + "/runs." + shape)) << shape;
  }
  for (size_t k = 0; k < 2; ++k) {
    const CanonicalForm form = canonical_form(meshes[k], options_for("ahead", names[k]));
    EXPECT_EQ((form.X - meshes[k].V).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(form.details.value("door", ""), "command");
  }
  const std::string message = test::error_of([&] { canonical_form(meshes[2], options_for("ahead", "bad.off")); });
  EXPECT_NE(message.find("bad.off: method ahead: the command exited with status 7"), std::string::npos) << message;
  EXPECT_NE(message.find("bad shape"), std::string::npos) << message;
  // Each program ran once: the pass took the results.
  for (const std::string shape : {"one", "two", "bad"}) {
    std::ifstream runs(dir + "/runs." + shape);
    const std::string text((std::istreambuf_iterator<char>(runs)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text, "run\n") << shape;
  }
  // A mesh the pass asks for again (taken already) runs the program anew.
  canonical_form(meshes[0], options_for("ahead", "one.off"));
  std::ifstream runs(dir + "/runs.one");
  const std::string text((std::istreambuf_iterator<char>(runs)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "run\nrun\n");
}

// Where nothing needs the correspondence (retrieval, distmat: CanonicalFormOptions::point_set), a method from
// outside may give any point set; elsewhere the same form is refused, from the program or from the cache.
TEST(OutsideMethods, AnyPointSetWhereNoCorrespondenceIsNeededAndOnlyThere) {
  const Mesh ball = icosphere(2);
  OutsideMethod m("half", command("awk 'NR > 2 && NR % 2 == 0 && NF == 3' {mesh} > {form.xyz}"));
  const std::string message = test::error_of([&] { canonical_form(ball, options_for("half")); });
  EXPECT_NE(message.find("expected one per vertex of the mesh given"), std::string::npos) << message;
  CanonicalFormOptions o = options_for("half");
  o.point_set = true;
  const DiskCache cache(test::scratch_dir("outside_point_set"));
  const CanonicalForm form = cached_canonical_form(cache, ball, o);
  EXPECT_GT(form.X.rows(), 4);
  EXPECT_LT(form.X.rows(), ball.num_vertices());
  ASSERT_TRUE(form.quality.has_value());
  EXPECT_NE(form.quality->description.find("not measured: a point set of"), std::string::npos);
  // The same form from the cache: taken where a point set does, refused where rows per vertex are needed.
  bool cached = false;
  EXPECT_EQ(cached_canonical_form(cache, ball, o, &cached).X, form.X);
  EXPECT_TRUE(cached);
  const std::string refused = test::error_of([&] { cached_canonical_form(cache, ball, options_for("half")); });
  EXPECT_NE(refused.find("ball.off: method half: the cached form is a point set of"), std::string::npos) << refused;
  // Too few points are refused even where a point set does.
  OutsideMethod few("few", command("head -n 5 {mesh} | tail -n 3 > {form.xyz}"));
  CanonicalFormOptions f = options_for("few");
  f.point_set = true;
  EXPECT_NE(test::error_of([&] { canonical_form(ball, f); }).find("expected at least 4 points"), std::string::npos);
}

TEST(OutsideMethods, CommasSeparateMethodsAndAnEscapedCommaStaysInTheCommand) {
  const std::vector<std::string> items = split_method_items("lbo,p=cmd:echo a\\,b {mesh} {form},cmds", "--methods");
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[1], "p=cmd:echo a,b {mesh} {form}");
  EXPECT_NE(test::error_of([] { split_method_items("lbo,,cmds", "--methods"); }).find("--methods: empty item"),
            std::string::npos);
}

TEST(OutsideMethods, AFormsDoorReadsByShapeNameAndListsTheShapesItLacks) {
  const std::string dir = test::scratch_dir("outside-forms");
  const Mesh ball = icosphere(2);
  Mesh moved = ball;
  moved.V.col(0) *= 2;  // any form: a stretched ball
  write_mesh(dir + "/forms/ball.ply", Mesh{moved.V, {}});
  OutsideDoor door;
  door.kind = OutsideDoor::Kind::Forms;
  door.text = dir + "/forms";
  OutsideMethod m("given", door);
  const CanonicalForm form = canonical_form(ball, options_for("given", "data/ball.off"));
  EXPECT_LT((form.X - moved.V).cwiseAbs().maxCoeff(), 1e-12);
  const std::string message = test::error_of([&] { canonical_form(ball, options_for("given", "data/cube3.off")); });
  EXPECT_NE(message.find("no form 'cube3.{ply,off,obj,xyz,npy}'"), std::string::npos) << message;
  const std::vector<std::string> written = write_forms_needed({"lbo", "given"}, dir + "/out");
  ASSERT_EQ(written.size(), 2u);
  std::ifstream csv(dir + "/out/forms-needed/given.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_EQ(header, "shape,mesh,form");
  EXPECT_EQ(row.substr(0, row.find(',')), "cube3");
  EXPECT_EQ(read_mesh(dir + "/out/forms-needed/given/cube3.off").num_vertices(), ball.num_vertices());
  // Forms read from a folder are read again each time, never served from a cache.
  EXPECT_FALSE(canonical_form_method("given").cacheable);
}

TEST(OutsideMethods, TheCacheKeyFollowsTheCommandTheFilesItNamesAndTheVersion) {
  const std::string dir = test::scratch_dir("outside-key");
  const Mesh ball = icosphere(1);
  const std::string script = dir + "/method.sh";
  test::write_text(script, "cp \"$1\" \"$2\"\n");
  auto key = [&](const std::string& text, const std::string& version) {
    OutsideMethodSettings s;
    s.version = version;
    OutsideMethod m("keyed", command(text), s);
    return canonical_form_cache_key(ball, options_for("keyed"));
  };
  const std::string a = key("sh " + script + " {mesh} {form.off}", "");
  EXPECT_EQ(a, key("sh " + script + " {mesh} {form.off}", ""));
  EXPECT_NE(a, key("sh  " + script + " {mesh} {form.off}", ""));
  EXPECT_NE(a, key("sh " + script + " {mesh} {form.off}", "v2"));
  test::write_text(script, "cp \"$1\" \"$2\"  # changed\n");
  EXPECT_NE(a, key("sh " + script + " {mesh} {form.off}", ""));
}

TEST(OutsideMethods, ANpyFormIsReadInEitherOrderAndWidth) {
  const std::string dir = test::scratch_dir("outside-npy");
  auto npy = [&](const std::string& path, const std::string& descr, bool fortran, const std::vector<char>& data) {
    std::string header = "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") +
                         ", 'shape': (2, 3), }";
    while ((10 + header.size() + 1) % 64) header += ' ';
    header += '\n';
    std::ofstream out(path, std::ios::binary);
    out.write("\x93NUMPY\x01\x00", 8);
    const char len[2] = {static_cast<char>(header.size() & 0xff), static_cast<char>(header.size() >> 8)};
    out.write(len, 2);
    out << header;
    out.write(data.data(), static_cast<std::streamsize>(data.size()));
  };
  auto bytes = [](const std::vector<double>& v) {
    std::vector<char> b(v.size() * 8);
    std::memcpy(b.data(), v.data(), b.size());
    return b;
  };
  npy(dir + "/c.npy", "<f8", false, bytes({1, 2, 3, 4, 5, 6}));
  npy(dir + "/f.npy", "<f8", true, bytes({1, 4, 2, 5, 3, 6}));
  const Points c = read_form_file(dir + "/c.npy"), f = read_form_file(dir + "/f.npy");
  EXPECT_EQ(c, f);
  EXPECT_EQ(c(1, 0), 4.0);
  EXPECT_EQ(c(0, 2), 3.0);
  npy(dir + "/i.npy", "<i8", false, bytes({1, 2, 3, 4, 5, 6}));
  EXPECT_NE(test::error_of([&] { read_form_file(dir + "/i.npy"); }).find("expected little-endian float64"),
            std::string::npos);
}

// The must-show: a 20-shape run with an outside method broken on five shapes (NaN form, wrong row
// count, crash, a hang past its limit, no output): each left out by name for that method, the run completes
// with exit 3, and the built-in method's matrix is byte-identical to its run alone.
TEST(OutsideMethodsCli, ABrokenOutsideMethodLeavesItsShapesOutAndNothingElseChanges) {
  const std::string dir = test::scratch_dir("outside-broken");
  const std::string manifest = test::generated_dataset(dir + "/data", 4, 5, 300);
  // Shapes are CLASSk, k = 0..4: the first class's five poses each break one way (a NaN, too few points, a
  // crash, a hang, no output), the others are given their mesh's coordinates as their form.
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir + "/data"))
    if (e.path().extension() == ".off") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  ASSERT_EQ(names.size(), 20u);
  const std::string broken_class = names.front().substr(0, names.front().size() - 1);
  const std::string script = dir + "/broken.sh";
  test::write_text(script, "case \"$1\" in\n"
                           "  " + broken_class + "0) awk 'NR==3{print \"nan nan nan\"; exit}' \"$2\" > \"$3\" ;;\n"
                           "  " + broken_class + "1) tail -n +3 \"$2\" | head -n 3 > \"$3\" ;;\n"
                           "  " + broken_class + "2) kill -SEGV $$ ;;\n"
                           "  " + broken_class + "3) sleep 60 ;;\n"
                           "  " + broken_class + "4) exit 0 ;;\n"
                           "  *) awk 'NR==2{n=$1} NR>2 && NR<=n+2{print $1, $2, $3}' \"$2\" > \"$3\" ;;\n"
                           "esac\n");
  const test::CliResult alone = test::run_cli("-q experiment retrieval --data " + manifest + " --out " + dir +
                                              "/alone --methods lbo --no-draw");
  ASSERT_EQ(alone.exit_code, 0) << alone.err;
  const test::CliResult both = test::run_cli(
      "-q experiment retrieval --data " + manifest + " --out " + dir + "/both --no-draw --method-timeout 2 " +
      "--methods 'lbo,broken=cmd:sh " + script + " {name} {mesh} {form.xyz}'");
  EXPECT_EQ(both.exit_code, 3) << both.err;
  std::ifstream json_in(dir + "/both/retrieval.json");
  const nlohmann::json r = nlohmann::json::parse(json_in);
  std::map<std::string, std::string> reasons;
  for (const auto& f : r["failures"])
    if (f["method"] == "broken") reasons[f["name"]] = f["reason"];
  ASSERT_EQ(reasons.size(), 5u) << r["failures"].dump(2);
  EXPECT_NE(reasons[broken_class + "0"].find("cannot be read"), std::string::npos);
  // Retrieval takes any point set (CanonicalFormOptions::point_set), but not one of 3 points.
  EXPECT_NE(reasons[broken_class + "1"].find("the form has 3 rows, expected at least 4 points"), std::string::npos);
  EXPECT_NE(reasons[broken_class + "2"].find("signal 11"), std::string::npos);
  EXPECT_NE(reasons[broken_class + "3"].find("ran past its limit of 2 s"), std::string::npos);
  EXPECT_NE(reasons[broken_class + "4"].find("wrote no form"), std::string::npos);
  // The other 15 shapes are measured for the outside method; lbo's matrix is the one of its run alone.
  std::ifstream broken_csv(dir + "/both/broken/hausdorff.csv");
  std::string header;
  std::getline(broken_csv, header);
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), 14) << header;  // 15 names
  auto text = [](const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  EXPECT_EQ(text(dir + "/both/lbo/hausdorff.csv"), text(dir + "/alone/lbo/hausdorff.csv"));
  EXPECT_TRUE(fs::exists(dir + "/both/method-logs/broken/" + broken_class + "2.err"));
}

}  // namespace
}  // namespace cshapes
