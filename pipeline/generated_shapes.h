// The generated shapes of data/articulated.h written to a folder, as `cshapes generate` writes them: meshes
// as OFF with 6 fixed decimals (data/dataset.h write_off_fixed), so that the same seed gives byte-identical
// files; glued vertex pairs as JSON; a dataset with its manifest.csv. Every file is written atomically, and a
// failed write throws cshapes::WriteError naming the path.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "cshapes/data/articulated.h"

namespace cshapes {

// {"pairs": [[a, b], ...]} (0-based vertex indices), pretty-printed (2 spaces) with a final newline.
void write_glued_pairs_json(const std::string& path, const std::vector<std::pair<int, int>>& pairs);

// FOLDER/CLASS_rest.off and FOLDER/CLASS0.off, CLASS1.off, ... (one a pose; CLASS: the skeleton's class
// name). Returns {class, vertices, faces, redraws, poses: [{file, edge_change_mean, edge_change_max}]}: each
// pose's file path and its edge-length change against the rest mesh (fractions).
nlohmann::json write_articulated_class(const ArticulatedClass& shapes, const std::string& folder);

// FOLDER/hand_separated.off, FOLDER/hand_glued.off and FOLDER/hand_glued_pairs.json.
void write_glued_hand(const GluedHand& hand, const std::string& folder);

// FOLDER/NAME.off for every shape, FOLDER/NAME_glued_pairs.json for the noisy ones, and FOLDER/manifest.csv
// (file, class, pose, noisy) listing them in order. Returns one summary per shape:
// [{file (NAME.off), class, noisy, vertices, genus, edge_change_mean, edge_change_max}].
nlohmann::json write_articulated_dataset(const std::vector<ArticulatedShape>& shapes,
                                         const std::string& folder);

}  // namespace cshapes
