#include "vpp/study/study_progress.h"

#include <algorithm>
#include <cstdio>

#include "scene/progress.h"

namespace vpp {

StudyProgress::StudyProgress(std::string command, std::size_t total, int jobs, double every)
    : command_(std::move(command)), total_(total), jobs_(std::max(1, jobs)), every_(every) {}

void StudyProgress::started(std::size_t i, const std::string& name, double now) {
    std::lock_guard<std::mutex> lk(mu_);
    Running& r = running_[i];
    r = Running{};
    r.name = name;
    r.start = r.stage_start = now;
}

void StudyProgress::stage(std::size_t i, const std::string& stage, uint64_t done, uint64_t total, double now) {
    std::lock_guard<std::mutex> lk(mu_);
    const auto it = running_.find(i);
    if (it == running_.end()) return;
    Running& r = it->second;
    if (stage != r.stage) {  // a new stage: its rate counts from here (a resumed stage starts above 0)
        r.stage = stage;
        r.stage_start = now;
        r.stage_first = done;
    }
    r.done = done;
    r.total = total;
    r.at = now;
}

void StudyProgress::finished(std::size_t i, bool ran, double now) {
    std::lock_guard<std::mutex> lk(mu_);
    const auto it = running_.find(i);
    if (ran && it != running_.end()) {
        ran_seconds_ += now - it->second.start;
        ++ran_;
    }
    if (it != running_.end()) running_.erase(it);
    ++done_;
}

double StudyProgress::case_left(const Running& r, double now) const {
    if (r.stage == "cycle" && r.done > r.stage_first && r.at > r.stage_start) {
        const double rate = double(r.done - r.stage_first) / (r.at - r.stage_start);  // [steps/s]
        return std::max(0.0, double(r.total - std::min(r.done, r.total)) / rate - (now - r.at));
    }
    if (ran_ > 0) return std::max(0.0, ran_seconds_ / double(ran_) - (now - r.start));
    return -1;
}

double StudyProgress::time_left(double now) const {
    std::lock_guard<std::mutex> lk(mu_);
    return left(now);
}

std::string StudyProgress::line(double now) const {
    std::lock_guard<std::mutex> lk(mu_);
    return compose(now);
}

double StudyProgress::left(double now) const {
    double longest = 0, sum = 0, per_case = ran_ > 0 ? ran_seconds_ / double(ran_) : -1;
    for (const auto& [i, r] : running_) {
        const double left = case_left(r, now);
        if (left < 0) return -1;
        longest = std::max(longest, left);
        sum += left;
        if (per_case < 0 && r.stage == "cycle") per_case = now - r.start + left;
    }
    const std::size_t pending = total_ - std::min(total_, done_ + running_.size());
    if (pending > 0) {
        if (per_case < 0) return -1;
        sum += double(pending) * per_case;
    }
    return std::max(longest, sum / double(jobs_));
}

std::string StudyProgress::compose(double now) const {
    std::string out = command_ + ": " + std::to_string(done_) + " of " + std::to_string(total_) + " cases done";
    if (!running_.empty()) {
        out += ", running:";
        bool first = true;
        for (const auto& [i, r] : running_) {
            char pct[32] = "";
            if (r.total > 0) std::snprintf(pct, sizeof pct, " %.0f%%", 100.0 * double(std::min(r.done, r.total)) / double(r.total));
            out += (first ? " " : ", ") + r.name + " (" + (r.stage.empty() ? std::string("starting") : r.stage + pct) + ")";
            first = false;
        }
    }
    const double s = left(now);
    out += s < 0 ? "; time left: known once a case cycles or ends"
                 : "; about " + scene::Progress::format_duration(s) + " left";
    return out;
}

std::string StudyProgress::due(double now) {
    std::lock_guard<std::mutex> lk(mu_);
    if (now - last_ < every_) return "";
    last_ = now;
    return compose(now);
}

}  // namespace vpp
