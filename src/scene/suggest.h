// "Did you mean ...?" for a mistyped command word.
#pragma once

#include <string>
#include <vector>

namespace scene {

// Edit distance (insertions, deletions, substitutions and swaps of two neighbours, each 1)
// between a and b.
int edit_distance(const std::string& a, const std::string& b);

// The candidate closest to `word` by edit_distance, or "" when even the closest needs more
// than max(1, size of the word / 3) edits (then it is not a typo of it but another word).
// Ties go to the first candidate in the list.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace scene
