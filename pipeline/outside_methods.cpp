#include "cshapes/pipeline/outside_methods.h"

#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include <Eigen/Eigenvalues>

#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/support/process_run.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/sha256.h"
#include "cshapes/support/threads.h"
#include "cshapes/support/timing.h"

namespace fs = std::filesystem;

namespace cshapes {

struct OutsideMethod::State {
  std::string name;
  OutsideDoor door;
  OutsideMethodSettings settings;
  std::mutex mutex;  // guards missing (forms of shapes computed on several threads)
  struct Missing {
    std::string shape;
    Mesh mesh;
  };
  std::vector<Missing> missing;  // forms door: shapes the folder had no form for, in the order asked
  // Command door: results of run_commands_ahead, by ahead_key, each taken by the pass's call for its mesh.
  struct Ahead {
    std::optional<CanonicalForm> form;
    std::string error;  // the failure's message when there is no form
  };
  std::map<std::string, Ahead> ahead;
};

namespace {

std::mutex& logs_mutex() {
  static std::mutex m;
  return m;
}
std::string& logs_folder() {
  static std::string folder;
  return folder;
}

// The live outside methods' states by name (for forms-needed and reports).
std::mutex& states_mutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, std::weak_ptr<OutsideMethod::State>>& states() {
  static std::map<std::string, std::weak_ptr<OutsideMethod::State>> s;
  return s;
}
std::shared_ptr<OutsideMethod::State> state_of(const std::string& name) {
  std::lock_guard<std::mutex> lock(states_mutex());
  auto it = states().find(name);
  return it == states().end() ? nullptr : it->second.lock();
}

const std::vector<std::string> kFormExtensions = {".ply", ".off", ".obj", ".xyz", ".npy"};

// The shape's name: the stem of the mesh's path ("cat0" for "data/cat0.off").
std::string shape_name(const std::string& path) {
  const std::string stem = fs::path(path).stem().string();
  return stem.empty() ? path : stem;
}

// A file name made of the shape's name (letters, digits, '-', '_', '.' kept; anything else '_').
std::string file_safe(const std::string& name) {
  std::string out = name;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  return out.empty() ? "_" : out;
}

std::string shell_quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The last `count` non-empty lines of a text, each indented, for an error message.
std::string last_lines(const std::string& text, size_t count) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  if (lines.empty()) return "";
  std::string out;
  for (size_t k = lines.size() > count ? lines.size() - count : 0; k < lines.size(); ++k)
    out += "\n    " + lines[k];
  return out;
}

// The form contract (pipeline/outside_methods.h), checked before the form is used. point_set: any number of
// points will do (CanonicalFormOptions::point_set).
void check_form(const Points& X, const Mesh& mesh, const std::string& where, bool point_set) {
  if (point_set)
    CSHAPES_REQUIRE(X.rows() >= 4, where, ": the form has ", X.rows(), " rows, expected at least 4 points");
  else
    CSHAPES_REQUIRE(X.rows() == mesh.num_vertices(), where, ": the form has ", X.rows(),
                    " rows, expected one per vertex of the mesh given (", mesh.num_vertices(),
                    "), in the mesh's vertex order");
  for (Index i = 0; i < X.rows(); ++i)
    for (int c = 0; c < 3; ++c)
      CSHAPES_REQUIRE(std::isfinite(X(i, c)), where, ": row ", i, " of the form is not finite (", X(i, 0), ' ',
                      X(i, 1), ' ', X(i, 2), "); every coordinate must be a finite number");
  // Spans a plane: the second singular value of the centred points is not negligible beside the first.
  const Eigen::RowVector3d centre = X.colwise().mean();
  const Eigen::Matrix3d C = (X.rowwise() - centre).transpose() * (X.rowwise() - centre);
  const Eigen::Vector3d s = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues().cwiseMax(0);
  CSHAPES_REQUIRE(s(2) > 0 && s(1) > 1e-20 * s(2), where, ": the form is collapsed (its ", X.rows(),
                  s(2) > 0 ? " points lie on a line" : " points coincide",
                  "); a canonical form must span at least a plane");
}

CanonicalForm form_of(Points X, const std::string& door, double seconds) {
  CanonicalForm form;
  form.X = std::move(X);
  form.valid = Eigen::VectorXd::Ones(form.X.rows());
  form.solve_seconds = seconds;
  form.details["door"] = door;
  return form;
}

// One run of a command door's program on one mesh.
CanonicalForm run_program(const OutsideMethod::State& st, const Mesh& mesh, const CanonicalFormOptions& options) {
  const std::string shape = shape_name(options.name);
  const std::string where = options.name + ": method " + st.name;
  std::string command = st.door.text;
  // The temporary folder the program works in: the mesh and the form, removed afterwards.
  std::string pattern = (fs::temp_directory_path() / "cshapes-form-XXXXXX").string();
  CSHAPES_REQUIRE(mkdtemp(pattern.data()), "cannot create a temporary folder in ",
                  fs::temp_directory_path().string(), ": ", std::strerror(errno));
  const fs::path tmp = pattern;
  struct Remove {
    fs::path p;
    ~Remove() {
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  } remove{tmp};
  const bool ply_mesh = command.find("{mesh.ply}") != std::string::npos;
  const std::string mesh_path = (tmp / (ply_mesh ? "mesh.ply" : "mesh.off")).string();
  std::string form_path = (tmp / "form.xyz").string();
  for (const std::string ext : {"npy", "ply", "off", "obj", "xyz"})
    if (command.find("{form." + ext + "}") != std::string::npos) form_path = (tmp / ("form." + ext)).string();
  auto replace_all = [&command](const std::string& from, const std::string& to) {
    for (size_t at = command.find(from); at != std::string::npos; at = command.find(from, at + to.size()))
      command.replace(at, from.size(), to);
  };
  for (const std::string key : {"{mesh}", "{mesh.ply}", "{mesh.off}"}) replace_all(key, shell_quoted(mesh_path));
  for (const std::string key : {"{form}", "{form.npy}", "{form.ply}", "{form.off}", "{form.obj}", "{form.xyz}"})
    replace_all(key, shell_quoted(form_path));
  replace_all("{name}", shell_quoted(shape));
  WriteOptions wo;
  wo.binary = ply_mesh;
  write_mesh(mesh_path, mesh, wo);

  const std::string out_path = (tmp / "stdout.txt").string(), err_path = (tmp / "stderr.txt").string();
  const ProcessRun run = run_process(command, out_path, err_path, st.settings.timeout_seconds, options.progress,
                                     st.name, where);
  const int status = run.status;
  const bool timed_out = run.timed_out;
  const struct rusage& usage = run.usage;
  const double seconds = run.seconds;
  const std::string out_text = file_text(out_path), err_text = file_text(err_path);
  {
    std::string logs;
    {
      std::lock_guard<std::mutex> lock(logs_mutex());
      logs = logs_folder();
    }
    if (!logs.empty()) {
      const fs::path folder = fs::path(logs) / st.name;
      fs::create_directories(folder);
      write_file_atomically((folder / (file_safe(shape) + ".out")).string(),
                            [&](std::ostream& o) { o << out_text; });
      write_file_atomically((folder / (file_safe(shape) + ".err")).string(),
                            [&](std::ostream& o) { o << err_text; });
    }
  }
  const std::string tail = last_lines(err_text.empty() ? out_text : err_text, 5);
  const std::string said = tail.empty() ? " (it printed nothing)" : "; its last lines:" + tail;
  if (timed_out)
    fail(where, ": the command ran past its limit of ", st.settings.timeout_seconds,
         " s (--method-timeout) and was stopped", said);
  if (WIFSIGNALED(status))
    fail(where, ": the command was killed by signal ", WTERMSIG(status), " (", strsignal(WTERMSIG(status)), ")",
         said);
  const int code = WEXITSTATUS(status);
  if (code > 128 && code <= 128 + 64)  // a shell reports its child's signal as 128 + the signal
    fail(where, ": the command exited with status ", code, " (128 + signal ", code - 128, ": ",
         strsignal(code - 128), ")", said);
  if (code != 0) fail(where, ": the command exited with status ", code, code == 127 ? " (command not found?)" : "", said);
  CSHAPES_REQUIRE(fs::exists(form_path), where, ": the command exited with status 0 but wrote no form at {form}",
                  said);
  Points X;
  try {
    X = read_form_file(form_path);
  } catch (const Error& error) {
    std::string message = error.what();  // the temporary path means nothing once it is gone: {form}
    for (size_t at = message.find(form_path); at != std::string::npos; at = message.find(form_path))
      message.replace(at, form_path.size(), "{form}");
    fail(where, ": the form the command wrote cannot be read: ", message);
  }
  check_form(X, mesh, where, options.point_set);
  CanonicalForm form = form_of(std::move(X), "command", seconds);
  form.details["peak_memory_bytes"] = static_cast<double>(usage.ru_maxrss) * 1024.0;
  return form;
}

// What identifies one call of a command door's program: the mesh's content and the name it runs under.
std::string ahead_key(const Mesh& mesh, const std::string& name) {
  std::string bytes = name + '\n';
  bytes.append(reinterpret_cast<const char*>(mesh.V.data()), sizeof(double) * static_cast<size_t>(mesh.V.size()));
  bytes.append(reinterpret_cast<const char*>(mesh.F.data()),
               sizeof(mesh.F(0, 0)) * static_cast<size_t>(mesh.F.size()));
  return sha256_hex(bytes);
}

// The command door's compute: the result run_commands_ahead left for this mesh, else one run now.
CanonicalForm run_command(OutsideMethod::State& st, const Mesh& mesh, const CanonicalFormOptions& options) {
  {
    std::lock_guard<std::mutex> lock(st.mutex);
    if (!st.ahead.empty()) {
      auto it = st.ahead.find(ahead_key(mesh, options.name));
      if (it != st.ahead.end()) {
        OutsideMethod::State::Ahead ahead = std::move(it->second);
        st.ahead.erase(it);
        if (!ahead.form) throw Error(ahead.error);
        return std::move(*ahead.form);
      }
    }
  }
  return run_program(st, mesh, options);
}

CanonicalForm read_from_folder(OutsideMethod::State& st, const Mesh& mesh, const CanonicalFormOptions& options) {
  const std::string shape = shape_name(options.name);
  const std::string where = options.name + ": method " + st.name;
  const auto start = WallClock::now();
  for (const std::string& ext : kFormExtensions) {
    const fs::path path = fs::path(st.door.text) / (shape + ext);
    if (!fs::is_regular_file(path)) continue;
    Points X = read_form_file(path.string());
    check_form(X, mesh, where + " (" + path.string() + ")", options.point_set);
    return form_of(std::move(X), "forms", seconds_since(start));
  }
  {
    std::lock_guard<std::mutex> lock(st.mutex);
    const bool listed = std::any_of(st.missing.begin(), st.missing.end(),
                                    [&](const OutsideMethod::State::Missing& m) { return m.shape == shape; });
    if (!listed) st.missing.push_back({shape, mesh});
  }
  fail(where, ": no form '", shape, ".{ply,off,obj,xyz,npy}' in ", st.door.text,
       " (an experiment lists such shapes in OUT/forms-needed/", st.name, ".csv, with their meshes)");
}

CanonicalForm call_function(const OutsideMethod::State& st, const Mesh& mesh, const CanonicalFormOptions& options) {
  const std::string where = options.name + ": method " + st.name;
  const auto start = WallClock::now();
  Points X = st.door.function(mesh, options.name);
  const double seconds = seconds_since(start);
  check_form(X, mesh, where, options.point_set);
  return form_of(std::move(X), "python", seconds);
}

bool valid_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
  });
}

// What identifies a command's code: the command and the content of each file it names (a script).
std::string command_key(const std::string& command) {
  std::string key = "command=" + command;
  std::istringstream words(command);
  for (std::string word; words >> word;) {
    word.erase(std::remove(word.begin(), word.end(), '\''), word.end());
    word.erase(std::remove(word.begin(), word.end(), '"'), word.end());
    std::error_code ec;
    if (word.find('{') == std::string::npos && fs::is_regular_file(word, ec))
      key += ";file:" + word + "=" + sha256_hex(file_text(word));
  }
  return key;
}

}  // namespace

std::string door_name(OutsideDoor::Kind kind) {
  switch (kind) {
    case OutsideDoor::Kind::Command:
      return "command";
    case OutsideDoor::Kind::Forms:
      return "forms";
    case OutsideDoor::Kind::Function:
      return "python";
  }
  return "";
}


std::vector<std::string> split_method_items(const std::string& text, const std::string& context) {
  std::vector<std::string> items;
  std::string item;
  for (size_t k = 0; k <= text.size(); ++k) {
    if (k + 1 < text.size() && text[k] == '\\' && text[k + 1] == ',') {
      item += ',';
      ++k;
    } else if (k == text.size() || text[k] == ',') {
      CSHAPES_REQUIRE(!item.empty(), context, ": empty item in '", text, "'");
      items.push_back(item);
      item.clear();
    } else {
      item += text[k];
    }
  }
  return items;
}

bool is_outside_method_item(const std::string& item) {
  const size_t eq = item.find('=');
  return eq != std::string::npos;
}

std::pair<std::string, OutsideDoor> parse_outside_method(const std::string& item) {
  const size_t eq = item.find('=');
  CSHAPES_REQUIRE(eq != std::string::npos, "'", item, "' is not NAME=cmd:COMMAND or NAME=forms:DIR");
  const std::string name = item.substr(0, eq), rest = item.substr(eq + 1);
  CSHAPES_REQUIRE(valid_name(name), "'", item, "': a method's name is letters, digits, '-' and '_' (it names ",
                  "files and columns), got '", name, "'");
  OutsideDoor door;
  if (rest.rfind("cmd:", 0) == 0) {
    door.kind = OutsideDoor::Kind::Command;
    door.text = rest.substr(4);
    CSHAPES_REQUIRE(door.text.find_first_not_of(" \t") != std::string::npos, "'", item,
                    "': the command is empty");
    CSHAPES_REQUIRE(door.text.find("{form") != std::string::npos, "'", item,
                    "': the command has no {form} (the path where it must write the form)");
    CSHAPES_REQUIRE(door.text.find("{mesh") != std::string::npos, "'", item,
                    "': the command has no {mesh} (the path of the mesh it is given)");
  } else if (rest.rfind("forms:", 0) == 0) {
    door.kind = OutsideDoor::Kind::Forms;
    door.text = rest.substr(6);
    CSHAPES_REQUIRE(!door.text.empty() && fs::is_directory(door.text), "'", item, "': '", door.text,
                    "' is not a folder (the forms, DIR/SHAPE.{ply,off,obj,xyz,npy})");
  } else {
    fail("'", item, "': the door is cmd:COMMAND or forms:DIR, got '", rest.substr(0, rest.find(':')), "'");
  }
  return {name, door};
}

OutsideMethod::OutsideMethod(std::string name, OutsideDoor door, OutsideMethodSettings settings)
    : name_(std::move(name)), state_(std::make_shared<State>()) {
  CSHAPES_REQUIRE(valid_name(name_), "a method's name is letters, digits, '-' and '_', got '", name_, "'");
  CSHAPES_REQUIRE(settings.timeout_seconds > 0, "--method-timeout: expected a positive number of seconds, got ",
                  settings.timeout_seconds);
  state_->name = name_;
  state_->door = std::move(door);
  state_->settings = std::move(settings);
  CanonicalFormMethod m;
  m.name = name_;
  m.title = name_;
  m.door = door_name(state_->door.kind);
  m.door_text = state_->door.text;
  m.summary = "a method from outside (" + m.door + ")";
  m.repair_purpose = "method " + name_;
  m.takes_mesh_as_given = true;
  const std::string version = ";version=" + state_->settings.version;
  std::shared_ptr<State> st = state_;
  switch (state_->door.kind) {
    case OutsideDoor::Kind::Command:
      m.key_text = command_key(st->door.text) + version;
      m.compute = [st](const Mesh& mesh, const CanonicalFormOptions& o, const GivenDistances&) {
        return run_command(*st, mesh, o);
      };
      break;
    case OutsideDoor::Kind::Forms:
      m.key_text = "folder=" + fs::absolute(st->door.text).lexically_normal().string() + version;
      m.cacheable = false;
      m.compute = [st](const Mesh& mesh, const CanonicalFormOptions& o, const GivenDistances&) {
        return read_from_folder(*st, mesh, o);
      };
      break;
    case OutsideDoor::Kind::Function:
      CSHAPES_REQUIRE(static_cast<bool>(st->door.function), "method ", name_, ": no function given");
      m.key_text = "function=" + st->door.text + ";" + st->door.function_key + version;
      m.compute = [st](const Mesh& mesh, const CanonicalFormOptions& o, const GivenDistances&) {
        return call_function(*st, mesh, o);
      };
      break;
  }
  register_outside_canonical_form_method(std::move(m));
  std::lock_guard<std::mutex> lock(states_mutex());
  states()[name_] = state_;
}

OutsideMethod::~OutsideMethod() {
  unregister_outside_canonical_form_method(name_);
  std::lock_guard<std::mutex> lock(states_mutex());
  auto it = states().find(name_);
  if (it != states().end() && it->second.lock() == state_) states().erase(it);
}

OutsideMethodList register_outside_methods(const std::vector<std::string>& items,
                                           const OutsideMethodSettings& settings) {
  OutsideMethodList list;
  for (const std::string& item : items) {
    if (!is_outside_method_item(item)) {
      list.names.push_back(item);
      continue;
    }
    auto [name, door] = parse_outside_method(item);
    list.registered.push_back(std::make_unique<OutsideMethod>(name, std::move(door), settings));
    list.names.push_back(name);
  }
  return list;
}

bool is_command_door_method(const std::string& method) {
  const CanonicalFormMethod* m = find_canonical_form_method(method);
  return m && m->door == door_name(OutsideDoor::Kind::Command);
}

void run_commands_ahead(const DiskCache& cache, const std::vector<ShapeAhead>& shapes,
                        const CanonicalFormOptions& options, int workers) {
  if (workers < 2 || !is_command_door_method(options.method)) return;
  const std::shared_ptr<OutsideMethod::State> st = state_of(options.method);
  if (!st) return;
  std::vector<size_t> todo;
  for (size_t i = 0; i < shapes.size(); ++i) {
    CanonicalFormOptions o = options;
    o.name = shapes[i].name;
    if (cache.enabled() && fs::exists(cache.entry_path(canonical_form_cache_key(*shapes[i].mesh, o)))) continue;
    todo.push_back(i);
  }
  if (todo.size() < 2) return;
  std::mutex progress_mutex;  // the caller's progress is polled by one thread at a time
  CanonicalFormOptions base = options;
  if (options.progress)
    base.progress = [&progress_mutex, progress = options.progress](const std::string& stage, long done, long total) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      progress(stage, done, total);
    };
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::exception_ptr stopped;  // the first stop (Ctrl-C, an output that cannot be written): rethrown
  std::mutex stopped_mutex;
  auto work = [&] {
    while (!stop) {
      const size_t k = next++;
      if (k >= todo.size()) return;
      const ShapeAhead& shape = shapes[todo[k]];
      CanonicalFormOptions o = base;
      o.name = shape.name;
      OutsideMethod::State::Ahead ahead;
      try {
        ahead.form = run_program(*st, *shape.mesh, o);
      } catch (const FileError&) {  // as shape_canonical_forms: the run stops
        std::lock_guard<std::mutex> lock(stopped_mutex);
        if (!stopped) stopped = std::current_exception();
        stop = true;
        return;
      } catch (const Error& error) {
        ahead.error = error.what();
      } catch (...) {
        std::lock_guard<std::mutex> lock(stopped_mutex);
        if (!stopped) stopped = std::current_exception();
        stop = true;
        return;
      }
      std::lock_guard<std::mutex> lock(st->mutex);
      st->ahead[ahead_key(*shape.mesh, shape.name)] = std::move(ahead);
    }
  };
  std::vector<std::thread> threads;
  const size_t count = std::min(todo.size(), static_cast<size_t>(workers));
  for (size_t t = 0; t < count; ++t) threads.emplace_back(work);
  for (std::thread& t : threads) t.join();
  if (stopped) {
    std::lock_guard<std::mutex> lock(st->mutex);
    st->ahead.clear();
    std::rethrow_exception(stopped);
  }
}

void run_commands_ahead(const DiskCache& cache, const std::vector<ShapeAhead>& shapes,
                        const CanonicalFormOptions& base, const std::vector<std::string>& methods) {
  for (const std::string& method : methods) {
    if (!is_command_door_method(method)) continue;
    CanonicalFormOptions options = options_per_method(base, {method}, "").front();
    options.progress = polls_of(base.progress);  // a stop ends the programs; no per-form reports
    run_commands_ahead(cache, shapes, options, refresh_threads());
  }
}

void set_outside_method_logs(const std::string& folder) {
  std::lock_guard<std::mutex> lock(logs_mutex());
  logs_folder() = folder;
}

nlohmann::json outside_methods_json(const std::vector<std::string>& methods) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& name : methods) {
    const CanonicalFormMethod* m = find_canonical_form_method(name);
    if (m && !m->door.empty()) out.push_back({{"name", name}, {"door", m->door}, {"text", m->door_text}});
  }
  return out;
}

std::string methods_command_argument(const std::vector<std::string>& methods) {
  std::string out;
  bool door = false;
  for (const std::string& name : methods) {
    const CanonicalFormMethod* m = find_canonical_form_method(name);
    std::string item = name;
    if (m && !m->door.empty()) {
      door = true;
      std::string text;
      for (char c : m->door_text) text += c == ',' ? std::string("\\,") : std::string(1, c);
      item += "=" + std::string(m->door == "command" ? "cmd" : m->door == "forms" ? "forms" : "python") + ":" + text;
    }
    out += (out.empty() ? "" : ",") + item;
  }
  return door ? shell_quoted(out) : out;
}

std::string outside_methods_markdown(const std::vector<std::string>& methods) {
  std::string md;
  for (const std::string& name : methods) {
    const CanonicalFormMethod* m = find_canonical_form_method(name);
    if (!m || m->door.empty()) continue;
    md += "- **" + name + "**: from outside, by the " + m->door + " door (" +
          (m->door == "command" ? "command" : m->door == "forms" ? "forms read from" : "function") + " `" +
          m->door_text + "`)\n";
  }
  return md;
}

std::vector<std::string> write_forms_needed(const std::vector<std::string>& methods, const std::string& out) {
  std::vector<std::string> written;
  for (const std::string& name : methods) {
    const std::shared_ptr<OutsideMethod::State> st = state_of(name);
    if (!st || st->door.kind != OutsideDoor::Kind::Forms) continue;
    std::vector<OutsideMethod::State::Missing> missing;
    {
      std::lock_guard<std::mutex> lock(st->mutex);
      missing = st->missing;
    }
    if (missing.empty()) continue;
    const fs::path folder = fs::path(out) / "forms-needed";
    fs::create_directories(folder / name);
    std::ostringstream csv;
    csv << "shape,mesh,form\n";
    for (const auto& m : missing) {
      const std::string mesh = name + "/" + file_safe(m.shape) + ".off";
      write_mesh((folder / mesh).string(), m.mesh);
      written.push_back((folder / mesh).string());
      csv << m.shape << ',' << mesh << ',' << (fs::path(st->door.text) / (m.shape + ".ply")).string() << '\n';
    }
    const std::string csv_path = (folder / (name + ".csv")).string();
    write_file_atomically(csv_path, [&](std::ostream& o) { o << csv.str(); });
    written.push_back(csv_path);
  }
  return written;
}

}  // namespace cshapes
