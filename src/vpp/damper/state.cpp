// The damper run's state (damper/state.h): its archive in the checkpoint's app blob, the older
// key/value text it reads too, and the tables forces.csv and energy.csv it holds.
#include "vpp/damper/state.h"

#include <charconv>
#include <istream>
#include <sstream>
#include <stdexcept>

#include "dem/io/archive.h"
#include "dem/io/checkpoint.h"
#include "vpp/analysis/records.h"

namespace vpp::damper_detail {

EnergyRow energy_row(const dem::EnergyLedger& L, double time) {
    EnergyRow r;
    dem::energy_csv_row(L, time, r.v);
    return r;
}

// The state's fields in the run-state archive (dem/io/archive.h), the format of the World's own
// sections: one section "RUNS"; S is `const RunState` when saving.
template <class A, class S> void RunState::fields(A& a, S& r) {
    a.section("RUNS", [&](A& s) {
        int32_t stage = int32_t(r.stage);
        int64_t window_n = r.window_n;
        uint64_t grains = r.grains;
        s.pod(stage);
        s.pod(r.stage_t0);
        s.pod(r.cap_d0);
        s.pod(r.cycle_t0);
        s.pod(r.window_grains);
        s.pod(r.window_foil);
        s.pod(window_n);
        s.numbers(r.geometry);
        s.numbers(r.settings);
        s.pod(grains);
        s.numbers(r.report);
        s.strings(r.warnings);
        s.vec(r.samples);
        s.vec(r.energy);
        s.pod(r.gas_amount);
        s.pod(r.gas_volume);
        s.pod(r.gas_work);
        s.vec(r.air);
        if constexpr (A::kLoading) {
            // Stage(stage) outside the enum would index past stage_name()'s table.
            if (stage < int32_t(Stage::Fill) || stage > int32_t(Stage::Done))
                throw std::runtime_error("damper state entry 'stage' holds " + std::to_string(stage) +
                                         ", not a stage (0 fill ... 5 done)");
            r.stage = Stage(stage);
            r.window_n = long(window_n);
            r.grains = std::size_t(grains);
        }
    });
}

std::string RunState::save() const {
    dem::io::Writer w;
    fields(w, *this);
    return w.buf;
}

std::string RunState::save_as_sample() const {
    RunState s = *this;
    s.settings.clear();
    return s.save();
}

namespace {

// One number of the state blob. std::from_chars, not operator>>: the blob holds what operator<<
// wrote, "nan" and "inf" included (the report of a run that went wrong), which >> does not read
// back; it stopped the reading there, and the rest of the state was silently left out.
template <class T> T statenumber(std::istream& is, const std::string& entry, const std::string& path) {
    std::string tok;
    T v{};
    if (is >> tok) {
        const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (r.ec == std::errc() && r.ptr == tok.data() + tok.size()) return v;
    }
    throw std::runtime_error("checkpoint '" + path + "': damper state entry '" + entry + "' holds " +
                             (tok.empty() ? std::string("nothing") : "'" + tok + "'") + " where a number belongs");
}

}  // namespace

RunState RunState::load(const std::string& blob, const std::string& path) {
    if (blob.size() >= 4 && blob.compare(0, 4, "RUNS") == 0) {
        RunState r;
        dem::io::Reader in(blob.data(), blob.size(), path);
        try {
            fields(in, r);
        } catch (const std::runtime_error& e) {
            const std::string what = e.what();
            if (what.starts_with("checkpoint '")) throw;
            throw std::runtime_error("checkpoint '" + path + "': " + what);
        }
        if (!in.done()) dem::io::corrupt(path, "unexpected data after the damper state");
        return r;
    }
    return load_text(blob, path);
}

RunState RunState::load_text(const std::string& text, const std::string& path) {
    RunState r;
    std::istringstream is(text);
    std::string key;
    int stage = 0;
    auto real = [&](const std::string& entry) { return statenumber<double>(is, entry, path); };
    auto name = [&](const std::string& entry) {
        std::string k;
        if (!(is >> k)) throw std::runtime_error("checkpoint '" + path + "': damper state entry '" + entry + "' has no name");
        return k;
    };
    while (is >> key) {
        if (key == "stage") stage = statenumber<int>(is, key, path);
        else if (key == "stage_t0") r.stage_t0 = real(key);
        else if (key == "cap_d0") r.cap_d0 = real(key);
        else if (key == "cycle_t0") r.cycle_t0 = real(key);
        else if (key == "window") {
            r.window_grains = real(key);
            r.window_foil = real(key);
            r.window_n = statenumber<long>(is, key, path);
        } else if (key == "geometry") {
            const std::string k = name(key);
            r.geometry[k] = real(key + " " + k);
        } else if (key == "setting") {
            const std::string k = name(key);
            r.settings[k] = real(key + " " + k);
        } else if (key == "grains") {
            r.grains = statenumber<std::size_t>(is, key, path);
        } else if (key == "report") {
            const std::string k = name(key);
            r.report[k] = real(key + " " + k);
        } else if (key == "warning") {
            std::string w;
            std::getline(is, w);
            r.warnings.push_back(w.empty() ? w : w.substr(1));  // the space after the key
        } else if (key == "sample") {
            Sample s;
            s.time = real(key);
            s.displacement = real(key);
            s.grains = real(key);
            s.foil = real(key);
            r.samples.push_back(s);
        } else if (key == "energy") {
            EnergyRow e;
            for (double& v : e.v) v = real(key);
            r.energy.push_back(e);
        } else if (key == "gas") {
            r.gas_amount = real(key);
            r.gas_volume = real(key);
            r.gas_work = real(key);
        } else if (key == "air") {
            AirSample a;
            a.enclosed = real(key);
            a.gas = real(key);
            a.p_inside = real(key);
            a.dp = real(key);
            a.lid_area = real(key);
            a.gas_work = real(key);
            r.air.push_back(a);
        } else throw std::runtime_error("checkpoint '" + path + "': unknown damper state entry '" + key + "'");
    }
    // Stage(stage) outside the enum would index past stage_name()'s table.
    if (stage < int(Stage::Fill) || stage > int(Stage::Done))
        throw std::runtime_error("checkpoint '" + path + "': damper state entry 'stage' holds " + std::to_string(stage) +
                                 ", not a stage (0 fill ... 5 done)");
    r.stage = Stage(stage);
    return r;
}

bool air_complete(const RunState& st) { return !st.air.empty() && st.air.size() == st.samples.size(); }

ForcesTable energy_table(const RunState& state) {
    ForcesTable t;
    if (state.energy.empty()) return t;
    const bool air = air_complete(state) && state.air.size() == state.energy.size();
    // The columns of dem::energy_csv_header(), and the gas's work with the air record.
    t.columns = dem::energy_column_names();
    if (air) t.columns.push_back("gas_work");
    t.rows.reserve(state.energy.size());
    for (std::size_t k = 0; k < state.energy.size(); ++k) {
        std::vector<double> row(state.energy[k].v, state.energy[k].v + kEnergyRowSize);
        if (air) row.push_back(state.air[k].gas_work);
        t.rows.push_back(std::move(row));
    }
    return t;
}

ForcesTable forces_table(const RunState& state, int samples_per_cycle) {
    ForcesTable t;
    const bool air = air_complete(state);
    t.columns = sample_column_names(air);
    // The air (docs/damper.md, "The air inside"): force_lid is what dp adds to the testing
    // machine's force on the lid (the atmosphere pushes the lid in: -dp times its area,
    // compression positive); force_machine_zeroed is the machine's force, grains + foil + lid,
    // zeroed at the first sample as force_zeroed is. With a constant dp the two zeroed columns agree.
    const int S = samples_per_cycle;
    const double f0 = state.samples.empty() ? 0.0 : state.samples[0].grains + state.samples[0].foil;
    const double m0 = air ? f0 - state.air[0].dp * state.air[0].lid_area : 0.0;
    t.rows.reserve(state.samples.size());
    for (std::size_t k = 0; k < state.samples.size(); ++k) {
        const Sample& s = state.samples[k];
        const double total = s.grains + s.foil;
        std::vector<double> row = {s.time - state.cycle_t0, s.displacement, total, s.grains, s.foil, total - f0,
                                   double(k / S + 1)};
        if (air) {
            const AirSample& a = state.air[k];
            const double lid = -a.dp * a.lid_area;
            row.insert(row.end(), {a.enclosed, a.gas, a.p_inside, a.dp, lid, total + lid - m0});
        }
        t.rows.push_back(std::move(row));
    }
    return t;
}

}  // namespace vpp::damper_detail
