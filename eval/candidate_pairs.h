// Two-stage retrieval: a cheap descriptor distance (matching/shape_descriptor.h) picks each query's k nearest
// candidates, ICP measures only those pairs, and the pairs left out get values that rank after every measured
// one. The exact all-pairs matrix stays the reference: candidate_recall says how many of each query's true k
// nearest the candidates contained.
//
// Conventions: matrices are N×N over the same shapes, queries are rows, a shape is never its own candidate;
// ties are broken by the lower index, so every function is deterministic.
// Cost: O(N² log k) to pick candidates, O(N²) to fill and to measure recall.
#pragma once

#include <utility>
#include <vector>

#include "cshapes/support/types.h"

namespace cshapes {

// For each row i of `distances` (N×N, e.g. descriptor distances): the k columns j ≠ i with the smallest
// values, nearest first (all N−1 when k ≥ N−1). k ≥ 1.
std::vector<std::vector<int>> nearest_candidates(const Eigen::MatrixXd& distances, int k);

// Every (i, c) of the candidate lists as a pair (min, max), each pair once, in row order: what ICP measures.
std::vector<std::pair<int, int>> candidate_pairs(const std::vector<std::vector<int>>& candidates);

// The entries of D that were not measured (NaN off the diagonal) become M·(1 + δ_ij), where M is the largest
// measured off-diagonal entry and δ = descriptor_distances (≥ 0): every unmeasured pair ranks after every
// measured one of its row, unmeasured pairs in descriptor order. D stays symmetric when δ is. Throws when no
// off-diagonal entry was measured.
void rank_unmeasured_last(Eigen::MatrixXd& D, const Eigen::MatrixXd& descriptor_distances);

// recall@k: the mean over queries i of |candidates[i] ∩ (the k nearest j ≠ i of row i of `reference`)| / k,
// with k = candidates[i].size(). 1 when the candidates always hold the true nearest.
double candidate_recall(const Eigen::MatrixXd& reference, const std::vector<std::vector<int>>& candidates);

}  // namespace cshapes
