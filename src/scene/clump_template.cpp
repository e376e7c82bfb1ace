#include "scene/clump_template.h"

#include <stdexcept>
#include <vector>

#include "dem/io/csv.h"

namespace scene {

dem::ClumpShape read_clump_template(const std::string& path) {
    std::vector<dem::ClumpMember> members;
    for (const auto& r : dem::read_numeric_csv(path, 4)) members.push_back({{r[0], r[1], r[2]}, r[3]});
    try {
        return dem::make_clump_shape(members);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
}

}  // namespace scene
