// resample_dataset (pipeline/resampled_dataset.h) remeshing several shapes at once: the same files, manifest,
// resample.csv, cache entries and counts as one shape after the other, for any thread count; a stop said by
// the note callback, and a shape that fails, end the run with nothing of the folder's index written.
// (The measures of each remesh and the cache's reuse: tests/retrieval_experiment_test.cpp.)
#include "cshapes/pipeline/resampled_dataset.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <thread>

#include "cshapes/data/synthetic.h"
#include "cshapes/mesh/io.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/support/threads.h"
#include "tests/test_support.h"

namespace cshapes {
namespace resampled_dataset_test {

namespace fs = std::filesystem;

// Closed and open meshes of 42 to 960 vertices (remeshed up and down to 150, the largest simplified first),
// a second file with the largest torus's bytes (the two largest files: on two threads at once, unless only
// the first of a content is remeshed), a point cloud (kept as it is) and a file no reader takes.
std::string mixed_collection(const std::string& dir) {
  const std::string data = dir + "/data";
  for (int k = 0; k < 3; ++k) {
    write_mesh(data + "/sphere" + std::to_string(k) + ".off", icosphere(k + 1, 1.0 + 0.2 * k));
    write_mesh(data + "/torus" + std::to_string(k) + ".off",
               torus(12 + 14 * k, 8 + 8 * k, 1.0 + 0.1 * k, 0.3 + 0.05 * k));
  }
  write_mesh(data + "/sheet0.off", grid(20, 15, 1.5, 1.0));
  write_mesh(data + "/sheet1.off", grid(12, 9, 1.0, 0.8));
  fs::copy_file(data + "/torus2.off", data + "/copy0.off");
  test::write_text(data + "/cloud0.off", "OFF\n5 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n");
  test::write_text(data + "/broken0.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n");
  return data;
}

// Remeshable shapes only (each gives a "[k/N]" note): tori of 96 to 646 vertices.
std::string tori(const std::string& dir, int count) {
  for (int k = 0; k < count; ++k)
    write_mesh(dir + "/data/torus" + std::to_string(k) + ".off", torus(12 + 2 * k, 8 + k, 1.0, 0.3));
  return dir + "/data";
}

// Every file under `folder`, by its path relative to it, with its bytes.
std::map<std::string, std::string> files_under(const std::string& folder) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(folder))
    if (e.is_regular_file()) files[fs::relative(e.path(), folder).string()] = read_file(e.path().string());
  return files;
}

// The cache entries written (a writer's temporary files are no entries).
size_t cache_entries(const std::string& cache) {
  if (!fs::exists(cache)) return 0;
  size_t count = 0;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(cache))
    if (e.is_regular_file() && e.path().string().find(".tmp.") == std::string::npos) ++count;
  return count;
}

// One run with `threads` OpenMP threads (no front end's request: refresh_threads keeps the count), its
// notes and the threads that said them.
struct NotedRun {
  ResampledDataset result;
  std::vector<std::string> notes;
  std::set<std::thread::id> note_threads;
};

NotedRun resample_with(int threads, const std::string& data, const ResampleOptions& options,
                       const std::string& folder, const std::string& cache) {
  set_thread_request(-1);
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  NotedRun run;
  std::mutex notes;
  const NoteFn note = [&](const std::string& line) {
    std::lock_guard<std::mutex> lock(notes);
    run.notes.push_back(line);
    run.note_threads.insert(std::this_thread::get_id());
  };
  try {
    run.result = resample_dataset(data, options, folder, DiskCache(cache), nullptr, note);
  } catch (...) {
    omp_set_num_threads(before);
    throw;
  }
  omp_set_num_threads(before);
  return run;
}

// The notes without their "[k/N]" (k follows the order in which shapes finish), sorted.
std::vector<std::string> notes_in_any_order(std::vector<std::string> notes) {
  const std::regex count(R"(\[\d+/\d+\] )");
  for (std::string& line : notes) line = std::regex_replace(line, count, "");
  std::sort(notes.begin(), notes.end());
  return notes;
}

// Each run writes the same folder and cache paths (manifest.csv and the first note name them), from an empty
// cache; both are moved aside after each run. Then: the same bytes in every file of the folder and of the
// cache, the same counts and the same notes, at 1 and at 4 threads; and the 4-thread run did remesh on more
// than one thread.
TEST(ResampledDataset, SeveralShapesAtOnceGiveTheBytesOfOneAfterTheOther) {
  const std::string dir = test::scratch_dir("resampled-threads");
  const std::string data = mixed_collection(dir);
  ResampleOptions options;
  options.vertices = 150;
  options.tolerance = 0.05;
  const std::string folder = dir + "/resampled";
  std::map<int, NotedRun> runs;
  const std::string cache = dir + "/cache";
  for (int threads : {1, 4}) {
    runs[threads] = resample_with(threads, data, options, folder, cache);
    fs::rename(folder, dir + "/resampled" + std::to_string(threads));
    fs::rename(cache, dir + "/cache" + std::to_string(threads));
  }
  const ResampledDataset &one = runs[1].result, &four = runs[4].result;
  ASSERT_EQ(one.shapes.size(), 10u);  // the unreadable file has no record
  EXPECT_EQ(one.computed, 9);         // torus2 reads its copy's remesh from the cache
  EXPECT_EQ(one.cached, 1);
  EXPECT_EQ(four.computed, one.computed);
  EXPECT_EQ(four.cached, one.cached);
  for (size_t k = 0; k < one.shapes.size(); ++k) {
    EXPECT_EQ(four.shapes[k].name, one.shapes[k].name);
    EXPECT_EQ(four.shapes[k].cached, one.shapes[k].cached) << one.shapes[k].name;
  }
  const auto expected = files_under(dir + "/resampled1"), got = files_under(dir + "/resampled4");
  EXPECT_EQ(expected.size(), 11u);  // 9 remeshed files (the copy's too), manifest.csv, resample.csv
  for (const auto& [name, bytes] : expected) {
    ASSERT_TRUE(got.count(name)) << name << " missing at 4 threads";
    EXPECT_TRUE(got.at(name) == bytes) << name << " differs at 4 threads";
  }
  EXPECT_EQ(got.size(), expected.size());
  EXPECT_TRUE(files_under(dir + "/cache4") == files_under(dir + "/cache1")) << "the cache entries differ";
  EXPECT_EQ(cache_entries(dir + "/cache1"), 9u);  // the 8 remeshes (torus2's is its copy's), the cloud
  EXPECT_EQ(notes_in_any_order(runs[4].notes), notes_in_any_order(runs[1].notes));
  EXPECT_GT(runs[4].note_threads.size(), 1u) << "the shapes were not remeshed on several threads";
}

// A note callback that throws (Python's Ctrl-C, support/progress.h) stops the run: the stop reaches the
// caller, no thread starts another shape (each finished at most the one under way), and neither manifest.csv
// nor resample.csv is written.
TEST(ResampledDataset, AStopFromTheNotesEndsEveryThread) {
  const std::string dir = test::scratch_dir("resampled-stop");
  const int shapes = 12, threads = 4;
  const std::string data = tori(dir, shapes);
  ResampleOptions options;
  options.vertices = 150;
  options.tolerance = 0.05;
  set_thread_request(-1);
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  const NoteFn stop_at_first_shape = [](const std::string& line) {
    if (line.rfind("  [", 0) == 0) throw Cancelled();
  };
  EXPECT_THROW(resample_dataset(data, options, dir + "/resampled", DiskCache(dir + "/cache"), nullptr,
                                stop_at_first_shape),
               Cancelled);
  omp_set_num_threads(before);
  EXPECT_FALSE(fs::exists(dir + "/resampled/manifest.csv"));
  EXPECT_FALSE(fs::exists(dir + "/resampled/resample.csv"));
  const size_t cached = cache_entries(dir + "/cache");
  EXPECT_GE(cached, 1u);
  EXPECT_LE(cached, static_cast<size_t>(threads));
}

// A shape that fails (its file cannot be written: a folder stands at its path) ends the run with that
// failure, after the other threads stopped; the index files are not written.
TEST(ResampledDataset, AFailingShapeIsRethrownAfterTheOthersStop) {
  const std::string dir = test::scratch_dir("resampled-failure");
  const std::string data = tori(dir, 8);
  ResampleOptions options;
  options.vertices = 150;
  options.tolerance = 0.05;
  fs::create_directories(dir + "/resampled/torus3.off");
  for (int threads : {1, 4}) {
    set_thread_request(-1);
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    try {
      resample_dataset(data, options, dir + "/resampled",
                       DiskCache(dir + "/cache" + std::to_string(threads)));
      ADD_FAILURE() << "no failure at " << threads << " threads";
    } catch (const WriteError& e) {
      EXPECT_NE(std::string(e.what()).find("torus3.off"), std::string::npos) << e.what();
    }
    omp_set_num_threads(before);
    EXPECT_FALSE(fs::exists(dir + "/resampled/manifest.csv"));
    EXPECT_FALSE(fs::exists(dir + "/resampled/resample.csv"));
  }
}

}  // namespace resampled_dataset_test
}  // namespace cshapes
