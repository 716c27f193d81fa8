// The registry: every structure is listed here by its register function, explicitly, so that
// no static-initialisation trick can be dropped by the linker.
#include "thicket/accel/registry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "accel/dispatch.h"
#include "thicket/core/error.h"

namespace thicket {

void register_brute(std::vector<AccelInfo>& registry);
void register_bvh(std::vector<AccelInfo>& registry);
void register_grid(std::vector<AccelInfo>& registry);
void register_grid2(std::vector<AccelInfo>& registry);
void register_octree(std::vector<AccelInfo>& registry);
void register_bsp(std::vector<AccelInfo>& registry);
void register_kdtree(std::vector<AccelInfo>& registry);
void register_bih(std::vector<AccelInfo>& registry);
void register_bvh8(std::vector<AccelInfo>& registry);
void register_obb(std::vector<AccelInfo>& registry);
void register_tetra(std::vector<AccelInfo>& registry);
// Instancing sits above the structures (instances/instances.h): the registry, below them, reaches
// it by this declaration alone, as it reaches each structure's register function.
std::unique_ptr<Accel> build_instanced(const Scene& scene, const AccelSpec& bottom);

namespace {

/// Options every structure takes, appended to each entry.
OptionInfo triangle_test_option() {
    return choice_option("isect", "ray/triangle test: Moller-Trumbore or the watertight test (Woop et al. 2013)",
                         TriangleTest::Moller, kTriangleTests);
}

std::vector<AccelInfo> make_registry() {
    std::vector<AccelInfo> r;
    register_brute(r);
    register_bvh(r);
    register_grid(r);
    register_grid2(r);
    register_octree(r);
    register_bsp(r);
    register_kdtree(r);
    register_bih(r);
    register_bvh8(r);
    register_obb(r);
    register_tetra(r);
    for (AccelInfo& info : r) info.options.push_back(triangle_test_option());
    return r;
}

std::string join(const std::vector<std::string>& items, const char* sep = ", ") {
    std::string out;
    for (const auto& s : items) out += (out.empty() ? "" : sep) + s;
    return out;
}

std::string trim(std::string_view s) {
    size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string_view::npos ? std::string() : std::string(s.substr(b, e - b + 1));
}

bool parse_long(const std::string& s, long& out) {
    if (s.empty()) return false;
    size_t pos = 0;
    try {
        out = std::stol(s, &pos);
    } catch (const std::exception&) {
        return false;
    }
    return pos == s.size();
}

/// A finite real number spelled entirely by `s` (strtod's syntax: 0.3, 1e-5).
bool parse_real(const std::string& s, double& out) {
    if (s.empty()) return false;
    size_t pos = 0;
    try {
        out = std::stod(s, &pos);
    } catch (const std::exception&) {
        return false;
    }
    return pos == s.size() && std::isfinite(out);
}

const OptionInfo* find_option(const AccelInfo& info, const std::string& key) {
    for (const OptionInfo& o : info.options)
        if (o.key == key) return &o;
    return nullptr;
}

/// Whether two values of option `o` are the same value (1e-3 and 0.001 are).
bool same_value(const OptionInfo& o, const OptionValue& a, const OptionValue& b) {
    if (!o.choices.empty()) return a.choice == b.choice;
    return o.real ? a.real == b.real : a.integer == b.integer;
}

/// Sets the keys the chosen value of each preset option stands for, then puts the option back
/// at its default (which sets nothing), so that the spec names what is built.
void expand_presets(const AccelInfo& info, AccelSpec& spec) {
    for (const OptionInfo& preset : info.options) {
        if (preset.presets.empty()) continue;
        const OptionValue chosen = spec.options.at(preset.key);
        for (const PresetSetting& set : preset.presets.at(chosen.choice)) {
            const OptionInfo* target = find_option(info, set.key);
            if (!target)
                throw Error(info.name + ": internal error: " + preset.key + "=" + chosen.text + " sets option '" +
                            set.key + "', which is not registered");
            const OptionValue& given = spec.options.at(set.key);
            if (!same_value(*target, given, parse_option_value(info.name, *target, target->default_value)))
                throw Error(info.name + ": " + preset.key + "=" + chosen.text + " sets " + set.key + " itself; drop " +
                            set.key + "=" + given.text + " or use " + preset.key + "=" + preset.default_value);
            spec.options[set.key] = parse_option_value(info.name, *target, set.value);
        }
        spec.options[preset.key] = parse_option_value(info.name, preset, preset.default_value);
    }
}

/// Reads the `key=value,...` part of `text` (which has one) into `spec`, checking each key and
/// value against `info`.
void read_options(const AccelInfo& info, std::string_view text, AccelSpec& spec) {
    std::vector<std::string> seen;
    std::string_view rest = text.substr(text.find(':') + 1);
    while (true) {
        const size_t comma = rest.find(',');
        const std::string item = trim(rest.substr(0, comma));
        const size_t eq = item.find('=');
        if (item.empty() || eq == std::string::npos)
            throw Error("malformed spec '" + std::string(text) + "': expected key=value, got '" + item +
                        "' (form: NAME[:key=value,...])");
        const std::string key = trim(item.substr(0, eq)), value = trim(item.substr(eq + 1));
        const OptionInfo* opt = find_option(info, key);
        if (!opt) {
            std::vector<std::string> keys;
            for (const auto& o : info.options) keys.push_back(o.key);
            throw Error(spec.name + ": unknown option '" + key + "'; allowed options: " + join(keys));
        }
        for (const auto& s : seen)
            if (s == key) throw Error(spec.name + ": option '" + key + "' given twice in '" + std::string(text) + "'");
        seen.push_back(key);
        spec.options[key] = parse_option_value(spec.name, *opt, value);
        if (comma == std::string_view::npos) break;
        rest = rest.substr(comma + 1);
    }
}

}  // namespace

OptionInfo preset_option(std::string key, std::string help, std::vector<Preset> presets) {
    OptionInfo o{std::move(key), std::move(help), {}, {}, 0, 0};
    for (Preset& p : presets) {
        o.choices.push_back(std::move(p.name));
        o.presets.push_back(std::move(p.sets));
    }
    if (o.choices.empty() || !o.presets.front().empty())
        throw Error("preset option '" + o.key + "': the first value is the default and must set nothing");
    o.default_value = o.choices.front();
    return o;
}

const std::vector<AccelInfo>& accel_registry() {
    static const std::vector<AccelInfo> registry = make_registry();
    return registry;
}

const AccelInfo* find_accel(std::string_view name) {
    for (const AccelInfo& info : accel_registry())
        if (info.name == name) return &info;
    return nullptr;
}

const OptionValue& AccelSpec::value(const std::string& key) const {
    auto it = options.find(key);
    if (it == options.end()) throw Error(name + ": internal error: option '" + key + "' is not registered");
    return it->second;
}

const std::string& AccelSpec::get(const std::string& key) const { return value(key).text; }

long AccelSpec::get_int(const std::string& key) const { return value(key).integer; }

double AccelSpec::get_real(const std::string& key) const { return value(key).real; }

OptionValue parse_option_value(const std::string& accel, const OptionInfo& o, const std::string& text) {
    OptionValue v{text};
    if (!o.choices.empty()) {
        v.choice = size_t(std::find(o.choices.begin(), o.choices.end(), text) - o.choices.begin());
        if (v.choice == o.choices.size())
            throw Error(accel + ": " + o.key + "=" + text + " is not allowed; choose one of " + join(o.choices));
    } else if (o.real) {
        if (!parse_real(text, v.real) || v.real < o.real_min || v.real > o.real_max) {
            std::ostringstream range;
            range << "[" << o.real_min << ", " << o.real_max << "]";
            throw Error(accel + ": " + o.key + "=" + text + " must be a number in " + range.str());
        }
    } else if (!parse_long(text, v.integer) || v.integer < o.min || v.integer > o.max) {
        throw Error(accel + ": " + o.key + "=" + text + " must be an integer in [" + std::to_string(o.min) + ", " +
                    std::to_string(o.max) + "]");
    }
    return v;
}

void AccelSpec::refuse_choice(const std::string& key, const std::vector<std::string>& allowed) const {
    throw Error(name + ": " + key + "=" + get(key) + " is not allowed; choose one of " + join(allowed));
}

std::string AccelSpec::str() const {
    std::string s = name;
    char sep = ':';
    for (const auto& [k, v] : options) {
        s += sep + k + "=" + v.text;
        sep = ',';
    }
    return s;
}

AccelSpec parse_accel_spec(std::string_view text) {
    const size_t colon = text.find(':');
    AccelSpec spec;
    spec.name = trim(text.substr(0, colon));
    const AccelInfo* info = find_accel(spec.name);
    if (!info) {
        std::vector<std::string> names;
        for (const auto& i : accel_registry()) names.push_back(i.name);
        throw Error("unknown acceleration structure '" + spec.name + "' in spec '" + std::string(text) +
                    "'; known structures: " + join(names) + " (see `thicket accels`)");
    }
    spec.info = info;
    for (const OptionInfo& o : info->options) spec.options[o.key] = parse_option_value(spec.name, o, o.default_value);
    if (colon != std::string_view::npos) read_options(*info, text, spec);
    expand_presets(*info, spec);
    return spec;
}

std::vector<std::string> all_accel_variants() {
    std::vector<std::string> out;
    for (const AccelInfo& info : accel_registry())
        for (const auto& v : info.variants) out.push_back(v);
    return out;
}

std::unique_ptr<Accel> build_accel(std::string_view spec_text, const Scene& scene, unsigned threads) {
    return build_accel(parse_accel_spec(spec_text), scene, threads);
}

std::unique_ptr<Accel> build_accel(const AccelSpec& parsed, const Scene& scene, unsigned threads) {
    if (!parsed.info)
        throw Error("unknown acceleration structure '" + parsed.name +
                    "' (not a spec made by parse_accel_spec; see `thicket accels`)");
    AccelSpec spec = parsed;
    spec.threads = threads;
    const auto start = std::chrono::steady_clock::now();
    // A scene with instances is two levels: the spec is the bottom level's (instances/instances.h).
    std::unique_ptr<Accel> accel = scene.instances.empty() ? parsed.info->build(scene, spec) : build_instanced(scene, spec);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    accel->set_origin(spec.str(), ms);
    return accel;
}

bool takes_double_rays(const AccelSpec& spec) { return spec.options.count("precision") && wants_double(spec); }

std::string float64_rays_refusal(const std::string& rays, const std::string& structure, const std::string& fix) {
    std::vector<std::string> doubles;
    for (const AccelInfo& info : accel_registry())
        for (const OptionInfo& o : info.options)
            if (o.key == "precision") doubles.push_back(info.name + ":precision=double");
    // Rounding them to float32 would lose what float64 rays are for (coordinates far from the
    // origin), so only a double structure takes them.
    return rays + ": float64 rays are traced by structures built with precision=double (" + join(doubles, " or ") +
           "), and " + structure + " is float32: build one with precision=double, or " + fix;
}

std::string describe_accels() {
    std::ostringstream out;
    out << "Acceleration structures (spec: NAME[:key=value,...], e.g. "
           "bvh:builder=binned-sah,bins=16,traversal=ordered-distance)\n";
    for (const AccelInfo& info : accel_registry()) {
        out << "\n" << info.name << " - " << info.summary << "\n";
        for (const OptionInfo& o : info.options) {
            out << "  " << o.key << "=";
            if (o.real)
                out << "<number " << o.real_min << ".." << o.real_max << ">";
            else if (o.choices.empty())
                out << "<integer " << o.min << ".." << o.max << ">";
            else
                out << join(o.choices, "|");
            out << "  (default " << o.default_value << ")\n      " << o.help << "\n";
            for (size_t i = 0; i < o.presets.size(); ++i) {
                if (o.presets[i].empty()) continue;
                out << "      " << o.key << "=" << o.choices[i] << " sets ";
                for (size_t k = 0; k < o.presets[i].size(); ++k)
                    out << (k ? "," : "") << o.presets[i][k].key << "=" << o.presets[i][k].value;
                out << "\n";
            }
        }
        out << "  variants tested: " << info.variants.size() << "\n";
    }
    return out.str();
}

void Accel::save(std::ostream&) const {
    throw Error("structure '" + spec() + "' cannot be saved to a file");
}

}  // namespace thicket
