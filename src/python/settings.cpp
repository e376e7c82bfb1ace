// The settings tables (docs/config.md) and the records' columns as lists of dicts, for a
// notebook's reference: damper_settings, scene_settings, record_columns.
#include "bindings.h"

#include <cmath>

#include "scene/scene_settings.h"
#include "scene/setting.h"
#include "vpp/analysis/records.h"
#include "vpp/settings/settings.h"

namespace bindings {

namespace {

// A settings table's row as a dict: what both tables have (the rest is added by the caller).
py::dict setting_dict(const std::string& key, cfg::SettingType type, const char* unit, const std::string& allowed,
                      const std::string& doc) {
    py::dict r;
    r["key"] = key;
    r["type"] = cfg::type_name(type);
    r["unit"] = unit;
    r["allowed"] = allowed;
    r["doc"] = doc;
    return r;
}

// A numeric default as the Python value of its type.
py::object default_value(cfg::SettingType type, double v) {
    if (type == cfg::SettingType::Boolean) return py::bool_(v != 0.0);
    if (type == cfg::SettingType::Integer) return py::int_(int64_t(v));
    return py::float_(v);
}

}  // namespace

void bind_settings(py::module_& m) {
    m.def("damper_settings", [] {
        py::list rows;
        for (const vpp::Setting& s : vpp::settings()) {
            py::dict r = setting_dict(s.key, s.type, s.unit, cfg::allowed_text(s.type, s.limits()), s.doc);
            r["default"] = std::isnan(s.def) ? py::object(py::str(s.default_text)) : default_value(s.type, s.def);
            if (!std::isnan(s.def_foil)) r["default_tension_envelope"] = s.def_foil;
            r["acts_on"] = vpp::acts_name(s.acts);
            r["shares_preparation"] = s.shares_preparation;
            rows.append(r);
        }
        return rows;
    });
    // The records' columns (vpp/analysis/records.h): what cycles() and forces() hold, with units.
    m.def("record_columns", [] {
        py::list rows;
        auto row = [&](const char* record, const char* name, const char* unit, const char* meaning, const char* only_with) {
            py::dict r;
            r["record"] = record;
            r["name"] = name;
            r["unit"] = unit;
            r["meaning"] = meaning;
            r["only_with"] = only_with;
            rows.append(r);
        };
        for (const vpp::CycleColumn& c : vpp::cycle_columns())
            row("cycles", c.name, c.unit, c.meaning,
                c.group == vpp::CycleGroup::Energy   ? "output.energy"
                : c.group == vpp::CycleGroup::Settle ? "a damper run"
                : c.group == vpp::CycleGroup::Events ? "analysis.event_threshold above 1 (and output.energy)"
                                                     : "");
        for (const vpp::SampleColumn& c : vpp::sample_columns())
            row("forces", c.name, c.unit, c.meaning,
                c.air ? "the air record (process.pressure_model = \"pump\" or output.air)" : "");
        return rows;
    });
    m.def("scene_settings", [] {
        py::list rows;
        for (const scene::SceneSetting& s : scene::scene_settings()) {
            py::dict r = setting_dict(s.key, s.type, s.unit, cfg::allowed_text(s.type, s.limits), s.doc);
            if (s.required) r["default"] = py::none();
            else if (*s.default_text) r["default"] = s.default_text;
            else if (s.type == cfg::SettingType::Vec3) r["default"] = py::make_tuple(s.def3.x, s.def3.y, s.def3.z);
            else r["default"] = default_value(s.type, s.def);
            r["required"] = s.required;
            rows.append(r);
        }
        return rows;
    });
}

}  // namespace bindings
