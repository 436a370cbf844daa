// Princeton Shape Benchmark classification files (.cla), the class lists of the PSB and the SHREC tracks
// (Shilane et al. 2004; shape.cs.princeton.edu/benchmark/documentation/classification_format.html):
//
//   PSB 1
//   numClasses numModels
//
//   className parentClassName numModelsInClass
//   modelId
//   …
//
// Tokens are separated by any whitespace (blank lines between classes are customary, not required); a parent
// of "0" is the root, any other parent must be a class defined earlier; class names are unique; a class may
// hold no models (an inner node of the hierarchy). Model ids are tokens without whitespace (PSB: integers).
// numModels is the count of model ids listed, each id at most once.
//
// As a dataset (data/dataset.h, read_dataset("FILE.cla")): each model id names a mesh file in the .cla's
// folder, the first of ID.off ID.ply ID.obj ID.stl ID.vert, then mID.off … mID.vert (the PSB's "m812"
// naming) that exists; the shape's class is its class in the file (leaves and inner classes alike), its pose
// its rank in the class, the file order is kept.
#pragma once

#include <string>
#include <vector>

namespace cshapes {

struct ClassificationClass {
  std::string name;
  std::string parent = "0";         // "0": the root
  std::vector<std::string> models;  // model ids, in file order
  std::vector<int> model_lines;     // read from a file: the line of each model id (for messages)
};

struct Classification {
  std::vector<ClassificationClass> classes;
  // Model ids of every class, in file order.
  std::vector<std::string> models() const;
};

// Reads a .cla file. Throws cshapes::Error naming the file, the line and what was expected (a bad header, a
// count that does not match, a missing or repeated class or model, an undefined parent).
Classification read_classification(const std::string& path);
// Parses .cla text; `where` names it in errors.
Classification parse_classification(const std::string& text, const std::string& where);
// Writes the file ("PSB 1", counts, a blank line before each class). Atomic. Throws for names with
// whitespace, a repeated class or model, or a parent not defined before its class.
void write_classification(const std::string& path, const Classification& classification);

// The class of every model: one class per distinct name of `classes` (order of first appearance), parent
// "0", the models in input order within their class. ids[i] has class classes[i].
Classification classification_from_labels(const std::vector<std::string>& ids,
                                          const std::vector<std::string>& classes);

// The mesh file of model `id` in `folder` by the rule above; "" when none exists.
std::string classification_model_file(const std::string& folder, const std::string& id);

}  // namespace cshapes
