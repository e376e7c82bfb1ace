#include "vpp/analysis/analysis.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string_view>

#include "dem/io/csv.h"

namespace vpp {

std::vector<CycleResult> analyze_cycles(const LoopSeries& s, double radius) {
    const std::size_t n = s.displacement.size();
    if (s.force.size() != n || s.cycle.size() != n || (!s.time.empty() && s.time.size() != n))
        throw std::invalid_argument("analyze_cycles: displacement, force, cycle (and time) differ in length");
    if (!(radius > 0) || !std::isfinite(radius))
        throw std::invalid_argument("analyze_cycles: radius must be positive");
    const double area = std::numbers::pi * radius * radius;

    std::map<int, std::vector<std::size_t>> groups;  // cycle -> sample indices in record order
    for (std::size_t i = 0; i < n; ++i)
        if (s.cycle[i] > 0) groups[s.cycle[i]].push_back(i);

    std::vector<CycleResult> out;
    for (const auto& [cycle, idx] : groups) {
        const std::size_t m = idx.size();
        if (m < 3) continue;
        double e = 0, fmax = s.force[idx[0]], fmin = fmax;
        double dmax = s.displacement[idx[0]], dmin = dmax, step = 0;
        for (std::size_t k = 0; k < m; ++k) {
            const std::size_t a = idx[k], b = idx[(k + 1) % m];
            e += 0.5 * (s.force[a] + s.force[b]) * (s.displacement[b] - s.displacement[a]);
            fmax = std::max(fmax, s.force[a]);
            fmin = std::min(fmin, s.force[a]);
            dmax = std::max(dmax, s.displacement[a]);
            dmin = std::min(dmin, s.displacement[a]);
            if (k + 1 < m) step = std::max(step, std::abs(s.displacement[b] - s.displacement[a]));
        }
        const double gap = std::abs(s.displacement[idx[m - 1]] - s.displacement[idx[0]]);
        CycleResult r;
        r.cycle = cycle;
        r.dissipated_energy = e;
        r.W = e / area;
        r.peak_force = fmax;
        r.min_force = fmin;
        r.samples = int(m);
        r.complete = gap <= std::max(0.1 * (dmax - dmin), 1.5 * step);
        out.push_back(r);
    }
    return out;
}

std::vector<int> split_cycles(const std::vector<double>& d) {
    const std::size_t n = d.size();
    std::vector<int> cyc(n, 0);
    if (n == 0) return cyc;
    const auto [mn, mx] = std::minmax_element(d.begin(), d.end());
    const double range = *mx - *mn;
    if (!(range > 0) || !std::isfinite(range)) return cyc;
    const double lo = *mn + 0.1 * range, hi = *mn + 0.9 * range;

    std::vector<std::size_t> bounds;
    if (d[0] <= lo) bounds.push_back(0);
    bool armed = false;  // been at d >= hi since the last return
    std::size_t i = 0;
    while (i < n) {
        if (d[i] >= hi) {
            armed = true;
            ++i;
        } else if (armed && d[i] <= lo) {
            std::size_t end = i;
            while (end < n && d[end] < hi) ++end;
            std::size_t best = i;
            for (std::size_t k = i + 1; k < end; ++k)
                if (d[k] < d[best]) best = k;
            bounds.push_back(best);
            armed = false;
            i = end;
        } else {
            ++i;
        }
    }
    for (std::size_t k = 0; k + 1 < bounds.size(); ++k)
        for (std::size_t j = bounds[k]; j < bounds[k + 1]; ++j) cyc[j] = int(k + 1);
    if (bounds.size() >= 2) cyc[bounds.back()] = int(bounds.size() - 1);
    return cyc;
}

namespace {

std::string_view trim(std::string_view v) {
    const auto b = v.find_first_not_of(" \t\r");
    if (b == std::string_view::npos) return {};
    const auto e = v.find_last_not_of(" \t\r");
    v = v.substr(b, e - b + 1);
    if (v.size() >= 2 && v.front() == '"' && v.back() == '"') v = v.substr(1, v.size() - 2);
    return v;
}

std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> cells;
    std::size_t start = 0;
    for (;;) {
        const auto p = line.find(',', start);
        cells.push_back(trim(line.substr(start, p == std::string_view::npos ? p : p - start)));
        if (p == std::string_view::npos) break;
        start = p + 1;
    }
    return cells;
}

}  // namespace

LoopSeries read_loop_csv(const std::string& path, const std::string& time_col,
                         const std::string& disp_col, const std::string& force_col,
                         const std::string& cycle_col) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read CSV file '" + path + "'");

    std::string line;
    std::size_t lineno = 0;
    std::vector<std::string> header;
    while (std::getline(in, line)) {
        ++lineno;
        // A UTF-8 byte order mark (spreadsheet exports write one) is no part of the first column's
        // name: kept, "time" would not be found, with a message showing no visible difference.
        if (lineno == 1 && line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);
        const std::string_view t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        for (auto c : split(line)) header.emplace_back(c);
        break;
    }
    if (header.empty()) throw std::runtime_error("CSV file '" + path + "' has no header line");

    auto find = [&](const std::string& name) -> long {
        for (std::size_t k = 0; k < header.size(); ++k)
            if (header[k] == name) return long(k);
        return -1;
    };
    auto require = [&](const std::string& name, const char* what) -> long {
        const long k = find(name);
        if (k >= 0) return k;
        std::string avail;
        for (const auto& h : header) avail += (avail.empty() ? "" : ", ") + ("'" + h + "'");
        throw std::runtime_error("CSV file '" + path + "': no " + what + " column '" + name +
                                 "' (columns: " + avail + ")");
    };
    const long ct = time_col.empty() ? -1 : require(time_col, "time");
    const long cd = require(disp_col, "displacement");
    const long cf = require(force_col, "force");
    const long cc = cycle_col.empty() ? -1 : find(cycle_col);
    const std::size_t need = std::size_t(std::max({ct, cd, cf, cc})) + 1;

    LoopSeries s;
    std::vector<double> cyc;
    while (std::getline(in, line)) {
        ++lineno;
        const std::string_view t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        const auto cells = split(line);
        const auto where = [&] { return "CSV file '" + path + "' line " + std::to_string(lineno); };
        if (cells.size() < need)
            throw std::runtime_error(where() + ": " + std::to_string(cells.size()) + " columns, need " +
                                     std::to_string(need));
        auto num = [&](long k) {
            std::string_view c = cells[std::size_t(k)];
            if (!c.empty() && c[0] == '+') c.remove_prefix(1);
            double v = 0;
            const auto r = std::from_chars(c.data(), c.data() + c.size(), v);
            if (c.empty() || r.ec != std::errc() || r.ptr != c.data() + c.size() || !std::isfinite(v))
                throw std::runtime_error(where() + ": column '" + header[std::size_t(k)] +
                                         "': not a finite number: '" + std::string(cells[std::size_t(k)]) +
                                         "'");
            return v;
        };
        const double time = ct >= 0 ? num(ct) : double(s.time.size());
        // The cycles and the loop's order follow the rows: a time running backwards is rows out
        // of order (a merged or sorted-by-another-column file), whose loops would be wrong.
        if (!s.time.empty() && time < s.time.back())
            throw std::runtime_error(where() + ": column '" + time_col + "' = " + std::string(cells[std::size_t(ct)]) +
                                     " is earlier than the row before (" + dem::csv_number(s.time.back()) +
                                     "): the rows must be in time order");
        s.time.push_back(time);
        s.displacement.push_back(num(cd));
        s.force.push_back(num(cf));
        if (cc >= 0) cyc.push_back(num(cc));
    }
    if (s.displacement.empty())
        throw std::runtime_error("CSV file '" + path + "' has a header but no data rows");
    if (cc >= 0) {
        s.cycle.reserve(cyc.size());
        for (double c : cyc) s.cycle.push_back(int(std::lround(c)));
        s.cycles_from_column = true;
    } else {
        s.cycle = split_cycles(s.displacement);
    }
    return s;
}

}  // namespace vpp
