#include "scene/suggest.h"

#include <algorithm>

namespace scene {

int edit_distance(const std::string& a, const std::string& b) {
    // Optimal string alignment distance (Damerau-Levenshtein without repeated edits of a
    // substring): a swap of two neighbours, the commonest typo, costs 1 instead of 2.
    const std::size_t n = a.size(), m = b.size();
    std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
    for (std::size_t i = 0; i <= n; ++i) d[i][0] = int(i);
    for (std::size_t j = 0; j <= m; ++j) d[0][j] = int(j);
    for (std::size_t i = 1; i <= n; ++i)
        for (std::size_t j = 1; j <= m; ++j) {
            const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
    std::string best;
    int best_d = 0;
    for (const std::string& c : candidates) {
        const int d = edit_distance(word, c);
        if (best.empty() || d < best_d) {
            best = c;
            best_d = d;
        }
    }
    const int allowed = std::max(1, int(word.size()) / 3);
    return best_d <= allowed ? best : std::string();
}

}  // namespace scene
