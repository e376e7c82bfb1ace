#include "scene/build_info.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "dem/io/csv.h"

namespace scene {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFile = "build.json";

nlohmann::ordered_json stamp_json(const BuildStamp& b) {
    nlohmann::ordered_json j;
    j["commit"] = b.commit;
    j["id"] = b.id;
    return j;
}

BuildStamp this_build() { return {build_commit(), build_id()}; }

}  // namespace

std::optional<std::vector<BuildStamp>> read_build_record(const std::string& dir) {
    const fs::path p = fs::path(dir) / kFile;
    if (!fs::exists(p)) return std::nullopt;
    std::ifstream in(p);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    const auto stamp = [](const nlohmann::json& o) -> std::optional<BuildStamp> {
        if (!o.is_object() || !o.contains("commit") || !o.contains("id") || !o["commit"].is_string() || !o["id"].is_string())
            return std::nullopt;
        return BuildStamp{o["commit"].get<std::string>(), o["id"].get<std::string>()};
    };
    const auto first = stamp(j);
    if (!first) return std::nullopt;
    std::vector<BuildStamp> out{*first};
    if (j.contains("resumed_by") && j["resumed_by"].is_array())
        for (const nlohmann::json& e : j["resumed_by"])
            if (const auto s = stamp(e)) out.push_back(*s);
    return out;
}

void record_build(const std::string& dir, bool fresh) {
    std::vector<BuildStamp> builds;
    if (!fresh)
        if (const auto held = read_build_record(dir)) builds = *held;
    const BuildStamp me = this_build();
    if (!builds.empty() && builds.back().id == me.id && builds.back().commit == me.commit) return;
    builds.push_back(me);
    nlohmann::ordered_json j = stamp_json(builds.front());
    if (builds.size() > 1) {
        nlohmann::ordered_json later = nlohmann::ordered_json::array();
        for (std::size_t k = 1; k < builds.size(); ++k) later.push_back(stamp_json(builds[k]));
        j["resumed_by"] = later;
    }
    dem::write_text_atomic((fs::path(dir) / kFile).string(), j.dump(2) + "\n");
}

std::vector<BuildStamp> other_builds(const std::string& dir) {
    std::vector<BuildStamp> out;
    if (const auto held = read_build_record(dir))
        for (const BuildStamp& b : *held)
            if (b.id != build_id()) out.push_back(b);
    return out;
}

}  // namespace scene
