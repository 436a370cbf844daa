// Cache keys built from the options' own field lists (support/option_fields.h): every options struct that
// enters a key lists each of its members exactly once, and every listed field reaches the key of the options
// that hold it — CanonicalFormOptions (canonical_form_key, per registered method), TopologicalNoiseOptions
// (glued_mesh_key) and IcpOptions (to_key_string) — while the fields marked kNoEffect do not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "cshapes/data/cache.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/noise_experiment.h"
#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/experiments/pose_invariance.h"
#include "cshapes/experiments/retrieval_experiment.h"
#include "cshapes/experiments/topkids_experiment.h"
#include "cshapes/matching/icp.h"
#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/glued_meshes.h"
#include "cshapes/pipeline/method_options.h"
#include "cshapes/support/option_fields.h"
#include "tests/test_support.h"

namespace cshapes {
namespace options_key_test {

// ---- (a) A field list names every member: counted by aggregate initialisation ----

// Converts to any member type, so T{AnyMember{}, ...} compiles with as many initialisers as T has members and
// no more (a nested options struct takes one whole: the conversion makes brace elision unnecessary).
struct AnyMember {
  template <class T>
  operator T() const;  // declared only: used in unevaluated contexts
};

template <class T, class... Initialisers>
constexpr auto accepts(int) -> decltype(T{std::declval<Initialisers>()...}, true) {
  return true;
}
template <class T, class... Initialisers>
constexpr bool accepts(long) {
  return false;
}

// The number of members of the aggregate T.
template <class T, class... Initialisers>
constexpr size_t member_count() {
  if constexpr (sizeof...(Initialisers) > 64) {
    return 0;  // not an aggregate we can count; the test fails on it
  } else if constexpr (accepts<T, Initialisers..., AnyMember>(0)) {
    return member_count<T, Initialisers..., AnyMember>();
  } else {
    return sizeof...(Initialisers);
  }
}

// What a field list says of one object: each listed field's name, where it lies in the object and its size.
struct ListedField {
  std::string name;
  size_t offset = 0, size = 0;
};
template <class T>
std::vector<ListedField> listed_fields(T& object) {
  std::vector<ListedField> fields;
  const auto* base = reinterpret_cast<const char*>(&object);
  T::for_each_field(object, [&](const char* name, auto& field, auto...) {
    fields.push_back(
        {name, static_cast<size_t>(reinterpret_cast<const char*>(&field) - base), sizeof(field)});
  });
  return fields;
}

// T's list names as many fields as T has members, each a different member of T (distinct names, disjoint
// storage inside the object): so every member is listed exactly once.
template <class T>
void expect_every_member_listed(const char* type) {
  static_assert(std::is_aggregate_v<T>, "an options struct stays an aggregate (its members are counted)");
  static_assert(has_field_list<T>::value, "an options struct that enters a cache key lists its fields");
  T object;
  const std::vector<ListedField> fields = listed_fields(object);
  EXPECT_EQ(fields.size(), member_count<T>()) << type << ": its for_each_field lists " << fields.size()
                                              << " fields for " << member_count<T>() << " members";
  std::set<std::string> names;
  for (const ListedField& f : fields)
    EXPECT_TRUE(names.insert(f.name).second) << type << ": " << f.name << " twice";
  for (size_t a = 0; a < fields.size(); ++a) {
    EXPECT_LE(fields[a].offset + fields[a].size, sizeof(T))
        << type << "." << fields[a].name << " is no member";
    for (size_t b = a + 1; b < fields.size(); ++b)
      EXPECT_TRUE(fields[a].offset + fields[a].size <= fields[b].offset ||
                  fields[b].offset + fields[b].size <= fields[a].offset)
          << type << ": " << fields[a].name << " and " << fields[b].name << " are the same storage";
  }
}

TEST(OptionsKey, EveryMemberIsListed) {
  expect_every_member_listed<CoulombCanonOptions>("CoulombCanonOptions");
  expect_every_member_listed<MetricProjectionOptions>("MetricProjectionOptions");
  expect_every_member_listed<CoulombOptions>("CoulombOptions");
  expect_every_member_listed<SmacofOptions>("SmacofOptions");
  expect_every_member_listed<ClassicalMdsOptions>("ClassicalMdsOptions");
  expect_every_member_listed<MdsSolverOptions>("MdsSolverOptions");
  expect_every_member_listed<LandmarkGeodesicsOptions>("LandmarkGeodesicsOptions");
  expect_every_member_listed<GeodesicOptions>("GeodesicOptions");
  expect_every_member_listed<KnnGraphOptions>("KnnGraphOptions");
  expect_every_member_listed<TopologicalNoiseOptions>("TopologicalNoiseOptions");
  expect_every_member_listed<IcpOptions>("IcpOptions");
  expect_every_member_listed<CanonicalFormOptions>("CanonicalFormOptions");
  expect_every_member_listed<ResampleOptions>("ResampleOptions");
}

// The counting itself: a struct with a member its list leaves out is caught.
struct TwoListedOfThree {
  int a = 0;
  double b = 0;
  std::string c;
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("a", o.a);
    visit("b", o.b);
  }
};
TEST(OptionsKey, AnUnlistedMemberIsCounted) {
  static_assert(member_count<TwoListedOfThree>() == 3);
  static_assert(member_count<KnnGraphOptions>() == 1);
  TwoListedOfThree object;
  EXPECT_EQ(listed_fields(object).size(), 2u);
}

// ---- (b) Every listed field reaches its key ----

// One field the walk below reached: its path ("coulomb.projection.steps"), its top-level name, and whether
// its mark says it changes the result.
struct Leaf {
  std::string path, top;
  bool changes_result = true;
  bool file_content = false;
};

// Visits the leaves of a field list (nested option structs are walked into) in order, calling
// at(leaf, field) for each.
template <class Options, class At>
void for_each_leaf(Options& options, At&& at, const std::string& prefix = "", const std::string& top = "") {
  Options::for_each_field(options, [&](const char* name, auto& field, auto... effect) {
    using Field = std::decay_t<decltype(field)>;
    const std::string path = prefix + name;
    const std::string top_name = top.empty() ? std::string(name) : top;
    if constexpr (has_field_list<Field>::value) {
      for_each_leaf(field, at, path + ".", top_name);
    } else {
      at(Leaf{path, top_name, changes_result<decltype(effect)...>, is_file_content<decltype(effect)...>},
         field);
    }
  });
}

template <class T>
struct is_vector : std::false_type {};
template <class T, class A>
struct is_vector<std::vector<T, A>> : std::true_type {};

// Another value of the same type: numbers moved, a bool flipped, an enum to another valid value, a string
// changed, a vector's element changed (same size), a callback set.
template <class Field>
void perturb(Field& field) {
  if constexpr (std::is_same_v<Field, bool>) {
    field = !field;
  } else if constexpr (std::is_integral_v<Field>) {
    field = static_cast<Field>(field + 1);
  } else if constexpr (std::is_floating_point_v<Field>) {
    field = std::isfinite(field) ? field + 0.5 + std::abs(field) : 1.0;
  } else if constexpr (std::is_enum_v<Field>) {
    // Every option enum has at least two values, numbered from 0: 0 and 1 are both valid.
    const Field other = static_cast<Field>(static_cast<int>(field) == 0 ? 1 : 0);
    EXPECT_NE(to_string(other), to_string(field));
    field = other;
  } else if constexpr (std::is_same_v<Field, std::string>) {
    field += "-changed";
  } else if constexpr (is_vector<Field>::value) {
    ASSERT_FALSE(field.empty()) << "give the vector values first (populate)";
    perturb(field[field.size() / 2]);
  } else if constexpr (std::is_base_of_v<Eigen::EigenBase<Field>, Field>) {
    ASSERT_GT(field.size(), 0) << "give the vector values first (populate)";
    field[field.size() / 2] += 0.25;
  } else if constexpr (std::is_same_v<Field, std::map<std::string, std::string>>) {
    field["perturbed"] += "1";  // CanonicalFormOptions::extra: another entry, or another value of it
  } else {
    field = [](auto&&...) {};  // a callback (kNoEffect)
  }
}

// Values for what is empty by default, so a change "in value, same size" exists: vectors get values (SMACOF's
// weights 300 of them, so their key is the SHA-256 branch), a kFileContent path a file.
struct Populate {
  std::string file;
  template <class Field>
  void operator()(const Leaf& leaf, Field& field) const {
    if constexpr (is_vector<Field>::value) {
      if (field.empty()) field = {3, 30, 300};
    } else if constexpr (std::is_base_of_v<Eigen::EigenBase<Field>, Field>) {
      if (field.size() == 0) field = Eigen::VectorXd::LinSpaced(300, 0.5, 2.0);
    } else if constexpr (std::is_same_v<Field, std::string>) {
      if (leaf.file_content) field = file;
    }
  }
};

// Perturbs each leaf of `base` in turn and checks key(perturbed) against key(base): different exactly when
// expect_change(leaf). A kFileContent leaf is pointed at a file of other content (changes the key) and at a
// copy of its file under another name (does not). Returns the leaves it visited.
template <class Options, class Key, class ExpectChange>
std::vector<std::string> expect_keys_follow_fields(const Options& base, const Key& key,
                                                   const ExpectChange& expect_change, const std::string& what,
                                                   const std::string& dir) {
  const std::string base_key = key(base);
  std::vector<std::string> visited;
  Options walk = base;
  size_t count = 0;
  for_each_leaf(walk, [&](const Leaf&, auto&) { ++count; });
  for (size_t k = 0; k < count; ++k) {
    Options changed = base;
    size_t index = 0;
    Leaf which;
    for_each_leaf(changed, [&](const Leaf& leaf, auto& field) {
      if (index++ != k) return;
      which = leaf;
      using Field = std::decay_t<decltype(field)>;
      if constexpr (std::is_same_v<Field, std::string>) {
        if (leaf.file_content) {
          // The same content under another name: the same key.
          const std::string copy = dir + "/copy-of-" + std::to_string(k) + ".bin";
          test::write_text(copy, "the distances");
          field = copy;
          EXPECT_EQ(key(changed), base_key) << what << ": " << leaf.path << " renamed, same content";
          test::write_text(dir + "/other.bin", "other distances");
          field = dir + "/other.bin";
          return;
        }
        if (leaf.path == "method") {
          for (const std::string& m : canonical_form_methods())
            if (m != field) {
              field = m;
              return;
            }
        }
      }
      perturb(field);
    });
    visited.push_back(which.path);
    const bool changed_key = key(changed) != base_key;
    EXPECT_EQ(changed_key, expect_change(which))
        << what << ": changing " << which.path
        << (expect_change(which) ? " leaves the key unchanged (a stale cache entry would be served)"
                                 : " changes the key, yet it is marked as not changing the result");
  }
  return visited;
}

TEST(OptionsKey, EveryFieldReachesTheCanonicalFormKey) {
  const std::string dir = test::scratch_dir("options_key");
  test::write_text(dir + "/D.bin", "the distances");
  for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
    CanonicalFormOptions base;
    base.method = method.name;
    for_each_leaf(base, Populate{dir + "/D.bin"});
    // The fields a method reads are fields.
    std::set<std::string> tops;
    for_each_leaf(base, [&](const Leaf& leaf, auto&) { tops.insert(leaf.top); });
    for (const std::string& name : method.reads)
      EXPECT_TRUE(tops.count(name)) << method.name << ": reads names no field: " << name;
    const auto reads = [&](const Leaf& leaf) {
      return leaf.changes_result && method_reads_field(method, leaf.top);
    };
    const std::vector<std::string> visited = expect_keys_follow_fields(
        base, [](const CanonicalFormOptions& o) { return canonical_form_key(o); }, reads,
        "canonical_form_key(" + method.name + ")", dir);
    // The walk reached the nested structs' fields (SMACOF's weights among them).
    EXPECT_TRUE(std::count(visited.begin(), visited.end(), "smacof.vertex_weights"));
    EXPECT_TRUE(std::count(visited.begin(), visited.end(), "coulomb.projection.steps"));
    EXPECT_TRUE(std::count(visited.begin(), visited.end(), "geodesics.heat_time_factor"));
  }
}

// Which methods read an option, from the methods' own option lists (pipeline/canonical_form_methods.h): the
// answers the CLI's refusals and Python's give (tests/cli_errors_test.cpp holds the CLI's messages,
// tests/python/test_method_keywords.py Python's, from a table written out independently).
TEST(OptionsReadBy, TheRegistryNamesTheMethodsThatReadAnOption) {
  using Names = std::vector<std::string>;
  EXPECT_EQ(canonical_form_methods_reading("geodesics"), (Names{"cmds", "smacof", "spectral-mds"}));
  EXPECT_EQ(canonical_form_methods_reading("distances"), (Names{"cmds", "smacof"}));
  EXPECT_EQ(canonical_form_methods_reading("mds_solver"), (Names{"cmds", "smacof"}));
  // SMACOF's fold repair, not classical MDS's.
  EXPECT_EQ(canonical_form_methods_reading("fold_overstretch"), (Names{"smacof"}));
  EXPECT_EQ(canonical_form_methods_reading("eigenpairs"), (Names{"lbo", "diffusion"}));
  EXPECT_EQ(canonical_form_methods_reading("laplacian"), (Names{"lbo", "diffusion", "spectral-mds"}));
  EXPECT_EQ(canonical_form_methods_reading("scheme"), (Names{"coulomb"}));
  EXPECT_EQ(canonical_form_methods_reading("init"), (Names{"smacof"}));
  EXPECT_EQ(canonical_form_methods_where([](const CanonicalFormMethod& m) { return m.has_history; }),
            (Names{"coulomb", "smacof"}));
  for (const CanonicalFormMethod& m : canonical_form_method_registry())
    EXPECT_TRUE(method_reads_field(m, "knn")) << m.name;  // every method: a point cloud's graph
  EXPECT_TRUE(method_reads_field(canonical_form_method("spectral-mds"), "spectral_mds"));
  EXPECT_FALSE(method_reads_field(canonical_form_method("spectral-mds"), "lbo"));
  EXPECT_FALSE(method_reads_field(canonical_form_method("coulomb"), "geodesics"));
  // As the CLI's messages say them: "--geodesics applies to --method cmds, smacof or spectral-mds only".
  EXPECT_EQ(either_of(canonical_form_methods_reading("geodesics")), "cmds, smacof or spectral-mds");
  EXPECT_EQ(either_of(canonical_form_methods_reading("mds_solver"), "'"), "'cmds' or 'smacof'");
  EXPECT_EQ(either_of({"coulomb"}), "coulomb");
}

// Each option a method lists sets a field the method reads: its value reaches the method's cache key (an
// option that set nothing the method reads would be accepted and ignored), and its default is the library's.
TEST(MethodOptions, EachOptionReachesTheKeyOfEveryMethodThatListsIt) {
  for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
    for (const MethodOption& option : method.options) {
      CanonicalFormOptions base;
      base.method = method.name;
      CanonicalFormOptions changed = base;
      const OptionValue fallback = option_default(option);
      OptionValue other;
      switch (option.type) {
        case MethodOption::Type::Integer: {
          const long long v = std::get<long long>(fallback);
          other = v + 1 <= option.limit->maximum ? v + 1 : v - 1;
          break;
        }
        case MethodOption::Type::Number: {
          const double v = std::get<double>(fallback);
          other = v * 1.5 + 0.01 <= option.limit->maximum ? v * 1.5 + 0.01 : v / 2;
          break;
        }
        case MethodOption::Type::Choice:
          other = option.choices.front() == std::get<std::string>(fallback) ? option.choices.back()
                                                                            : option.choices.front();
          break;
        case MethodOption::Type::Path: {
          const std::string file = test::scratch_dir("method_options") + "/D.bin";
          test::write_text(file, "the distances");
          other = file;
          break;
        }
      }
      option.set(changed, other);
      EXPECT_EQ(option_text(option.get(changed)), option_text(other)) << option.name << " reads back";
      EXPECT_NE(canonical_form_key(changed), canonical_form_key(base))
          << method.name << " lists " << option.name << ", whose value does not reach its key";
      if (option.type == MethodOption::Type::Choice) {
        EXPECT_TRUE(std::count(option.choices.begin(), option.choices.end(), option_text(fallback)))
            << option.name << ": its default is not one of its choices";
      }
      if (const long long* i = std::get_if<long long>(&fallback)) {
        EXPECT_TRUE(option.limit->holds(static_cast<double>(*i)))
            << option.name << ": default outside its limit";
      }
      if (const double* x = std::get_if<double>(&fallback)) {
        EXPECT_TRUE(option.limit->holds(*x)) << option.name << ": default outside its limit";
      }
    }
  }
}

// The fields a method does not list in `reads` do not change its form: each changed in turn (every leaf under
// it), the form of a small sphere stays the same, bit for bit. A field a method read without listing it would
// change its form here, and its cache would serve stale forms.
TEST(MethodOptions, AFieldAMethodDoesNotListLeavesItsFormUnchanged) {
  const Mesh mesh = icosphere(2);  // 162 vertices
  for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
    CanonicalFormOptions base;
    base.method = method.name;
    base.coulomb.max_iterations = 30;  // small runs: each form is computed once per field
    base.smacof.max_iterations = 10;
    base.spectral_mds.laplacian.eigenpairs = 12;
    base.spectral_mds.sources = 40;
    const Points reference = canonical_form(mesh, base).X;
    std::set<std::string> tops;
    for_each_leaf(base, [&](const Leaf& leaf, auto&) {
      if (leaf.changes_result && !method_reads_field(method, leaf.top)) tops.insert(leaf.top);
    });
    for (const std::string& top : tops) {
      CanonicalFormOptions changed = base;
      for_each_leaf(changed, [&](const Leaf& leaf, auto& field) {
        if (leaf.top != top) return;
        Populate{}(leaf, field);
        perturb(field);
      });
      const Points X = canonical_form(mesh, changed).X;
      EXPECT_TRUE(X.cwiseEqual(reference).all())
          << method.name << ": changing " << top << " changed its form";
    }
  }
}

TEST(OptionsKey, EveryFieldReachesTheGluedMeshKey) {
  const Mesh mesh = icosphere(1);
  TopologicalNoiseOptions base;
  for_each_leaf(base, Populate{});
  const std::vector<std::string> visited = expect_keys_follow_fields(
      base, [&](const TopologicalNoiseOptions& o) { return glued_mesh_key(mesh, o); },
      [](const Leaf& leaf) { return leaf.changes_result; }, "glued_mesh_key", test::scratch_dir("glue_key"));
  EXPECT_TRUE(std::count(visited.begin(), visited.end(), "geodesic.method"));
}

TEST(OptionsKey, EveryFieldReachesTheIcpKey) {
  IcpOptions base;
  for_each_leaf(base, Populate{});
  expect_keys_follow_fields(
      base, [](const IcpOptions& o) { return to_key_string(o); },
      [](const Leaf& leaf) { return leaf.changes_result; }, "to_key_string(IcpOptions)",
      test::scratch_dir("icp_key"));
}

// The case the count-only key missed: SMACOF weights of the same count, other values.
TEST(OptionsKey, SmacofWeightsEnterByValue) {
  CanonicalFormOptions a;
  a.method = "smacof";
  a.smacof.vertex_weights = Eigen::VectorXd::Ones(5000);
  CanonicalFormOptions b = a;
  b.smacof.vertex_weights[4321] = 1.0 + 1e-15;
  EXPECT_NE(canonical_form_key(a), canonical_form_key(b));
  EXPECT_LT(canonical_form_key(a).size(), 4000u);  // long vectors enter as their count and a SHA-256
}

// The text itself: names, 17 digits, enums by name, quoted strings, vectors by value.
TEST(OptionsKey, TextNamesEveryValue) {
  KnnGraphOptions knn;
  knn.k = 12;
  EXPECT_EQ(options_key(knn), "k=12");
  GeodesicOptions g;
  g.method = GeodesicMethod::FastMarching;
  g.heat_time_factor = 0.1;
  EXPECT_EQ(options_key(g),
            "method=fmm;heat_mode=" + to_string(g.heat_mode) + ";heat_time_factor=0.10000000000000001");
  CanonicalFormOptions o;
  o.method = "coulomb";
  o.name = "a\"b";  // kNoEffect: not in the key
  const std::string key = canonical_form_key(o);
  EXPECT_EQ(key.rfind("method=\"coulomb\";coulomb.scheme=", 0), 0u) << key;
  EXPECT_EQ(key.find("geodesics."), std::string::npos) << "coulomb does not read the geodesics: " << key;
  EXPECT_NE(key.find(";knn.k=8"), std::string::npos) << key;
  IcpOptions icp;
  EXPECT_NE(to_key_string(icp).find(";pyramid=100,1000,;"), std::string::npos);
}

// A method whose arithmetic changed (results_version > 1: Coulomb) keys its cached forms, and everything
// keyed by its options (Fig. 3's snapshots), apart from those cached before, so they are computed again; a
// method at version 1 keeps the key it always had, so its cached forms are still served.
TEST(OptionsKey, AMethodsResultsVersionSeparatesItsCachedForms) {
  const Mesh mesh = icosphere(1);
  for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
    CanonicalFormOptions o;
    o.method = method.name;
    const std::string options_only =
        options_key(o, [&method](const char* field) { return method_reads_field(method, field); });
    const std::string before_versions =
        cache_key({"canonical-form-v2", mesh_content_key(mesh), options_only});
    if (method.results_version > 1) {
      EXPECT_EQ(canonical_form_key(o), options_only + ";results-v" + std::to_string(method.results_version));
      EXPECT_NE(canonical_form_cache_key(mesh, o), before_versions) << method.name;
    } else {
      EXPECT_EQ(canonical_form_key(o), options_only) << method.name;
      EXPECT_EQ(canonical_form_cache_key(mesh, o), before_versions) << method.name;
    }
  }
  EXPECT_EQ(canonical_form_method("coulomb").results_version, 4);
}

// The experiments start from the library's experiment defaults (heat geodesics), whoever calls them: the CLI
// no longer sets them, so a C++ or Python caller gets the CLI's numbers. Compared field by field, by key.
// A single canonical_form() call (`canon`, Python's canonical_form) starts from the same options: the same
// method gives the same form from every command (issue 36: `canon` used fast marching, the rest heat).
TEST(OptionsKey, ExperimentsStartFromTheLibraryDefaults) {
  const CanonicalFormOptions defaults = experiment_canonical_form_options();
  const CanonicalFormOptions single_call;  // canonical_form() alone
  const PaperExperimentOptions paper;
  const NoiseExperimentOptions noise;
  const TopkidsExperimentOptions topkids;
  const PoseInvarianceOptions pose;
  const RetrievalExperimentOptions retrieval;
  EXPECT_EQ(options_key(retrieval.canon), options_key(defaults));
  EXPECT_EQ(retrieval.methods, canonical_form_methods());
  EXPECT_EQ(defaults.geodesics.method, GeodesicMethod::Heat);
  EXPECT_EQ(options_key(defaults), options_key(single_call));
  EXPECT_EQ(single_call.geodesics.method, GeodesicMethod::Heat);
  EXPECT_EQ(options_key(paper.canon), options_key(defaults));
  EXPECT_EQ(options_key(noise.canon), options_key(defaults));
  EXPECT_EQ(options_key(topkids.canon), options_key(defaults));
  EXPECT_EQ(options_key(pose.canon), options_key(defaults));
  EXPECT_EQ(paper.methods, canonical_form_methods());
}

// --coulomb-preset paper sets the paper's algorithm (§2 as written), first: an option given beside it, before
// or after it on the command line, changes one setting; the same settings given one by one give the same form.
TEST(MethodOptions, ThePaperPresetSetsThePapersAlgorithmAndSingleSettingsChangeIt) {
  const auto all = all_method_options();
  const auto preset = std::find_if(all.begin(), all.end(), [](const MethodOption* o) {
    return o->name == "coulomb_preset";
  });
  ASSERT_NE(preset, all.end());
  CanonicalFormOptions o;
  EXPECT_EQ(option_text((*preset)->get(o)), "default");
  (*preset)->set(o, std::string("paper"));
  EXPECT_EQ(option_text((*preset)->get(o)), "paper");
  EXPECT_EQ(o.coulomb.start, CoulombStart::Input);
  EXPECT_EQ(o.coulomb.scheme, CoulombScheme::Paper);
  EXPECT_EQ(o.coulomb.step_rule, CoulombStepRule::MaxEdge);
  EXPECT_EQ(o.coulomb.step_gradient, StepGradient::Max);
  EXPECT_EQ(o.coulomb.step_factor, 0.1);
  EXPECT_EQ(o.coulomb.flatten, 0.0);
  EXPECT_EQ(o.coulomb.bridge_detour, 0.0);
  EXPECT_EQ(o.coulomb.projection.norm, ProjectionNorm::L2);
  EXPECT_EQ(o.coulomb.tear_times, 1);
  EXPECT_EQ(o.coulomb.tear_after, 100);
  EXPECT_EQ(o.coulomb.multiresolution.above_resolution, 0);
  EXPECT_EQ(o.coulomb.move_limit, 0.0);
  (*preset)->set(o, std::string("default"));
  EXPECT_EQ(canonical_form_key(o), canonical_form_key(CanonicalFormOptions{}));

  const std::string dir = test::scratch_dir("coulomb_preset");
  write_mesh(dir + "/shape.off", capsule());
  auto form = [&](const std::string& options, const std::string& out) {
    const test::CliResult r = test::run_cli("-q --threads 1 canon " + dir + "/shape.off -o " + dir + "/" + out +
                                            " " + options);
    EXPECT_EQ(r.exit_code, 0) << options << "\n" << r.err;
    std::ifstream in(dir + "/" + out, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  const std::string one_by_one =
      "--coulomb-start input --flatten 0 --scheme paper --step-rule max-edge --step-gradient max --tear-after 100 "
      "--tear-times 1 --tear-guard vertex --coulomb-multiresolution-above 0 --move-limit 0 "
      "--projection-steps 3";
  const std::string preset_then_one = form("--coulomb-preset paper --projection-steps 3", "a.ply");
  EXPECT_EQ(form("--projection-steps 3 --coulomb-preset paper", "b.ply"), preset_then_one);
  EXPECT_EQ(form(one_by_one, "c.ply"), preset_then_one);
  EXPECT_NE(form("--coulomb-preset paper", "d.ply"), preset_then_one);
}

}  // namespace options_key_test
}  // namespace cshapes
