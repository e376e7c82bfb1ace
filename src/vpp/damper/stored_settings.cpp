// What a damper's checkpoint stores of the config that made it (damper/stored_settings.h): the
// tables of keys, the comparison of a checkpoint's values with a config's, and the adopting of
// them by a run from the checkpoint.
#include "vpp/damper/stored_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <stdexcept>

#include "dem/io/checkpoint.h"
#include "dem/io/csv.h"
#include "vpp/damper/state.h"
#include "vpp/settings/choices.h"
#include "vpp/settings/settings.h"

namespace vpp {

namespace damper_detail {

namespace {

// A config value stored in the checkpoint's app state: a row of the settings table, with how to
// read it from and write it into a Config (vpp/settings/settings.h).
using StoredKey = Setting;

// Geometry of the prepared sample. A run from a checkpoint must match the keys it gives and
// takes the checkpoint's values of the others.
const std::vector<StoredKey> kGeometryKeys = geometry_settings();

// What a run applies to its prepared sample (DamperScene::apply_run_settings) and records from then
// on: a resumed run continues with these, so its record is one run's, not a splice of two.
// Not here: simulation.threads (results do not depend on it), output.vtk_interval (frames only).
const std::vector<StoredKey> kRunKeys = run_settings();

// What else acted during the preparation: recorded beside the geometry (not checked by a run
// --from a sample by hand; checked for a study's branch, DamperOptions::check_preparation).
const std::vector<StoredKey> kPreparationKeys = preparation_settings();

std::map<std::string, double> values_of(const Config& c, const auto& keys) {
    std::map<std::string, double> m;
    for (const StoredKey& k : keys) m[k.key] = k.get(c);
    return m;
}

// The quoted word of an enumerated key's stored number (vpp/settings/choices.h); nullopt for a
// number no value has.
template <class E>
std::optional<std::string> quoted_word(double v) {
    const std::optional<E> e = from_number<E>(v);
    if (!e) return std::nullopt;
    return std::string("\"") + word_of(*e) + "\"";
}

bool same_value(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b)); }

}  // namespace

std::string show_value(const std::string& key, double v) {
    // Words, not the numbers the checkpoint keeps for them (a refusal said "grains.shape = 5").
    std::optional<std::string> word;
    if (key == "grains.radius_distribution") word = quoted_word<RadiusDistribution>(v);
    if (key == "grains.shape") word = quoted_word<GrainShape>(v);
    if (key == "foil.builder") word = quoted_word<FoilBuilder>(v);
    if (key == "process.pressure_model") word = quoted_word<PressureModel>(v);
    if (key == "process.waveform") word = quoted_word<Waveform>(v);
    if (word) return *word;
    if (key == "process.direction") return v == 0.0 ? "\"compression\"" : "\"extension\"";
    if (key == "output.energy" || key == "damper.refill" || key == "foil.exact_radius") return v != 0.0 ? "true" : "false";
    if (key == "foil.bond_arm") return std::string("\"") + dem::bond_arm_name(dem::BondArm(int(v))) + "\"";
    if (key == "simulation.dt" && v == 0.0) return "\"auto\"";
    if (key == "damper.cap_friction" && v < 0.0) return "(unset: the grains' friction)";
    std::string out;
    dem::append_number(out, v);
    return out;
}

std::map<std::string, double> run_settings_of(const Config& c) { return values_of(c, kRunKeys); }

std::map<std::string, double> sample_keys_of(const Config& c) {
    std::map<std::string, double> m = values_of(c, kGeometryKeys);
    for (const auto& [k, v] : values_of(c, kPreparationKeys)) m[k] = v;
    return m;
}

namespace {

// The sample's keys as a checkpoint stores them: its geometry (an older vppdem's missing keys at
// their legacy values) and the keys that acted during its preparation (those it recorded).
std::map<std::string, double> stored_sample_keys(const RunState& ck) {
    std::map<std::string, double> keys = ck.geometry;
    for (const StoredKey& k : kGeometryKeys)
        if (!keys.count(k.key) && std::isfinite(k.legacy)) keys[k.key] = k.legacy;
    return keys;
}

// How a refusal words a stored value against the config's: "key = stored (<asks> value<note>)",
// the note after a preparation key's value.
struct Wording {
    const char* asks;
    const char* preparation_note;
};

// The keys whose values `stored` (stored_sample_keys) differ from c's, as a refusal lists them,
// in the tables' order joined by ", ": every geometry key (one not stored: "?"), and with
// `preparation` every preparation key stored (an older vppdem's sample did not record them).
// `take`, when given, is asked first about each stored geometry key: nullopt to compare it, or
// the entry to list in its place ("" for none).
std::string sample_differences(const Config& c, const std::map<std::string, double>& stored, bool preparation,
                               const Wording& wording,
                               const std::function<std::optional<std::string>(const StoredKey&, double)>& take = {}) {
    std::string diffs;
    auto add = [&](const std::string& entry) {
        if (!entry.empty()) diffs += (diffs.empty() ? "" : ", ") + entry;
    };
    auto compare = [&](const StoredKey& k, bool geometry) {
        const auto it = stored.find(k.key);
        if (it == stored.end() && !geometry) return;  // an older vppdem's sample: not recorded
        if (it != stored.end() && geometry && take)
            if (const std::optional<std::string> entry = take(k, it->second)) return add(*entry);
        const double value = k.get(c);
        if (it != stored.end() && same_value(it->second, value)) return;
        add(std::string(k.key) + " = " + (it == stored.end() ? std::string("?") : show_value(k.key, it->second)) + " (" +
            wording.asks + " " + show_value(k.key, value) + (geometry ? "" : wording.preparation_note) + ")");
    };
    for (const StoredKey& k : kGeometryKeys) compare(k, true);
    if (preparation)
        for (const StoredKey& k : kPreparationKeys) compare(k, false);
    return diffs;
}

}  // namespace

CheckpointStart adopt_checkpoint_settings(Config& config, const DamperOptions& options) {
    CheckpointStart start;
    dem::World scratch;  // only the app state is needed here; run() loads the World itself
    const RunState ck = RunState::load(dem::load_checkpoint(options.from, scratch), options.from);
    // Geometry: a key the config gives must match the sample's; the others take its values.
    // A study's branch: the keys that acted during the preparation must be the case's too, or
    // the case would cycle a sample its settings did not make (a stiffer grain settles into
    // another packing). A checkpoint of an older vppdem did not record them: not checked.
    auto take = [&](const StoredKey& k, double stored) -> std::optional<std::string> {
        if (!config.given.count(k.key)) {
            k.set(config, stored);
            return std::string();
        }
        // A file key is stored as its numbers' fingerprint: the message names the file, not two fingerprints.
        const bool file = std::string(k.key) == "grains.sieve_curve" || std::string(k.key) == "grains.clump_template";
        if (!file || same_value(stored, k.get(config))) return std::nullopt;
        const std::string& path = std::string(k.key) == "grains.sieve_curve" ? config.grains.sieve_curve
                                                                             : config.grains.clump_template;
        return std::string(k.key) + ": the sample was drawn from " +
               (stored == 0.0 ? std::string("none") : std::string("a file with other numbers")) +
               " (the config asks for " + (path.empty() ? std::string("none") : "'" + path + "'") + ")";
    };
    const std::string diffs = sample_differences(config, stored_sample_keys(ck),
                                                 options.check_preparation && ck.stage == Stage::Prepared,
                                                 {"the config asks for", "; it acts during the preparation"}, take);
    start.grains = ck.grains;
    if (!diffs.empty())
        throw std::runtime_error("checkpoint '" + options.from + "' was prepared with another geometry: " + diffs +
                                 "; prepare a new sample (run without --from)");
    if (ck.settings.empty()) {
        // A prepared sample (or a run stopped before its settings were applied) takes the
        // config's settings. Only a checkpoint of an older vppdem can be past that point
        // without them: it is run with the config's settings, as that vppdem did.
        if (ck.stage > Stage::Prepared) {
            start.warnings.push_back("resume: the checkpoint (an older vppdem's) stores no run settings; the "
                                     "config's are used");
            if (!options.quiet)
                std::fprintf(stderr, "damper: warning: checkpoint '%s' (an older vppdem's) stores no process settings: "
                             "the config's are used; give the ones the run started with\n", options.from.c_str());
        }
        return start;
    }
    // A run that started: it continues with its own settings, whatever the command line says;
    // a key given with another value is refused rather than spliced into the record.
    std::string conflicts;
    for (const StoredKey& k : kRunKeys) {
        const auto it = ck.settings.find(k.key);
        // A key an older vppdem did not store: the run went on with the value it had then
        // (the key's legacy value), e.g. process.pressure_model "constant".
        if (it == ck.settings.end() && !std::isfinite(k.legacy)) continue;
        const double stored = it != ck.settings.end() ? it->second : k.legacy;
        // More cycles than the run started with: it goes on (extend_cycling); fewer would end a
        // record that already holds them, or promise a run it is not.
        if (std::string(k.key) == "process.cycles" && config.given.count(k.key) && k.get(config) > stored) {
            start.cycles_raised_from = int(stored);
            continue;
        }
        if (config.given.count(k.key) && !same_value(k.get(config), stored))
            conflicts += (conflicts.empty() ? "" : ", ") + std::string(k.key) + " = " + show_value(k.key, stored) +
                         " in the checkpoint, " + show_value(k.key, k.get(config)) + " given" +
                         (std::string(k.key) == "process.cycles" ? " (more cycles continue the run, fewer cannot)" : "");
        else
            k.set(config, stored);
    }
    if (!conflicts.empty())
        throw std::runtime_error("checkpoint '" + options.from + "' continues a run with other settings: " + conflicts +
                                 "; a resumed run keeps the settings it started with: leave these keys out (or give "
                                 "the checkpoint's values), or start a new run from the sample's prepared.ckpt");
    return start;
}

}  // namespace damper_detail

SampleRecord read_sample_record(const std::string& checkpoint) {
    using namespace damper_detail;
    dem::World scratch;
    const RunState ck = RunState::load(dem::load_checkpoint(checkpoint, scratch), checkpoint);
    SampleRecord r;
    r.prepared = ck.stage == Stage::Prepared;
    r.keys = stored_sample_keys(ck);
    return r;
}

std::string sample_misfit(const Config& c, const SampleRecord& sample, bool preparation_keys) {
    using namespace damper_detail;
    if (!sample.prepared) return "not a prepared sample (its stage is past the preparation)";
    return sample_differences(c, sample.keys, preparation_keys, {"the case:", ""});
}

}  // namespace vpp
