#pragma once
/// The registry of acceleration structures and their spec strings `NAME[:key=value,...]`,
/// e.g. `bvh:builder=binned-sah,bins=16,traversal=ordered-distance`.
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/core/choice.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// One key a preset sets, and the value (as a spec writes it) it sets the key to.
struct PresetSetting {
    std::string key;
    std::string value;
};

/// One named option of a structure: either one of `choices`, an integer in [min, max], or (when
/// `real`, made with real_option()) a real number in [real_min, real_max].
/// Choice options are best made with choice_option() from the same table the builder reads the
/// value with (AccelSpec::choice), so the listing, the parser and the builder cannot disagree.
/// A preset option (preset_option()) is a choice option that the parser expands: no builder
/// reads it.
struct OptionInfo {
    std::string key;
    std::string help;
    std::string default_value;
    std::vector<std::string> choices;  ///< empty: an integer (or real) option
    long min = 0, max = 0;
    bool real = false;                 ///< a real number (AccelSpec::get_real), not an integer
    double real_min = 0.0, real_max = 0.0;
    /// A preset option: per choice, in the same order, the keys that value sets (the default
    /// sets none). Empty for every other option.
    std::vector<std::vector<PresetSetting>> presets = {};
};

/// The OptionInfo of a real-valued option in [lo, hi] (written as C's strtod reads it: 0.3, 1e-5).
inline OptionInfo real_option(std::string key, std::string help, std::string fallback, double lo, double hi) {
    OptionInfo o{std::move(key), std::move(help), std::move(fallback), {}, 0, 0};
    o.real = true;
    o.real_min = lo;
    o.real_max = hi;
    return o;
}

/// The OptionInfo of the option `key` whose allowed values are the names of `table`, listed in
/// the table's order; the default is the name of `fallback`, which must be in the table.
template <class T, size_t N>
OptionInfo choice_option(std::string key, std::string help, T fallback, const Choice<T> (&table)[N]) {
    OptionInfo o{std::move(key), std::move(help), {}, {}, 0, 0};
    for (const Choice<T>& c : table) {
        o.choices.push_back(c.name);
        if (o.default_value.empty() && c.value == fallback) o.default_value = c.name;
    }
    return o;
}

/// One value of a preset option: its name and the keys it sets.
struct Preset {
    std::string name;
    std::vector<PresetSetting> sets;
};

/// The OptionInfo of the preset option `key`, whose values are the names of `presets`; the first
/// is the default and must set nothing. parse_accel_spec() expands the chosen value: it sets
/// each of its keys, refuses a spec that also gives one of them a value other than that key's
/// default, and leaves the option at its default, so that the parsed spec (and the spec a
/// structure records) names what is built.
OptionInfo preset_option(std::string key, std::string help, std::vector<Preset> presets);

struct AccelInfo;

/// One option's value in a parsed spec: as written, and as the typed value of the option's
/// kind, which is what builders read: the index of a choice in OptionInfo::choices (and in the
/// table it was made from), an integer, or a real number.
struct OptionValue {
    std::string text;
    size_t choice = 0;
    long integer = 0;
    double real = 0.0;
};

/// Parses `text` as a value of option `o` of the structure named `accel`. Throws Error naming
/// the structure, key and value, and the allowed values or range.
OptionValue parse_option_value(const std::string& accel, const OptionInfo& o, const std::string& text);

/// A parsed, validated spec with every option present (defaults filled in), each value parsed
/// once (parse_option_value()).
struct AccelSpec {
    std::string name;
    /// The registered structure (parse_accel_spec() sets it): build_accel() builds with it.
    const AccelInfo* info = nullptr;
    std::map<std::string, OptionValue> options;
    /// Threads the build may use (0: every core). Not part of the spec string: a structure builds
    /// the same result on any number of threads.
    unsigned threads = 0;

    /// The value of option `key` as written.
    const std::string& get(const std::string& key) const;
    /// The value of an integer option; the parser has checked its range.
    long get_int(const std::string& key) const;
    /// The value of a real option (real_option()); the parser has checked its range.
    double get_real(const std::string& key) const;
    /// The value `table` gives option `key`: the table's entry at the option's choice index, the
    /// table being the one the option was made from (choice_option()). Throws Error listing the
    /// table's names when the option holds anything else: no value silently becomes a default.
    template <class T, size_t N>
    T choice(const std::string& key, const Choice<T> (&table)[N]) const {
        const OptionValue& v = value(key);
        if (v.choice < N && v.text == table[v.choice].name) return table[v.choice].value;
        std::vector<std::string> names;
        for (const Choice<T>& c : table) names.push_back(c.name);
        refuse_choice(key, names);
    }
    /// Canonical form: name, then every option in key order.
    std::string str() const;

private:
    const OptionValue& value(const std::string& key) const;
    /// Throws Error("NAME: key=value is not allowed; choose one of a, b, ...").
    [[noreturn]] void refuse_choice(const std::string& key, const std::vector<std::string>& allowed) const;
};

/// How a structure divides the scene (the lecture's comparison table, `thicket compare`):
/// Object: primitives into groups whose bounds may overlap, each primitive in one leaf (BVH, BIH;
/// a BVH with spatial splits, builder=sbvh, still counts: it cuts only where boxes overlap);
/// Space: space into disjoint cells, a primitive referenced by every cell it overlaps (grid,
/// octree, kD-tree, BSP); None: no division at all (brute force). Unknown: not declared.
enum class Partitioning { Unknown, None, Object, Space };

/// "object", "space", "none" or "unknown".
inline const char* partitioning_name(Partitioning p) {
    switch (p) {
    case Partitioning::None: return "none";
    case Partitioning::Object: return "object";
    case Partitioning::Space: return "space";
    default: return "unknown";
    }
}

struct AccelInfo {
    std::string name;
    std::string summary;
    Partitioning partitioning = Partitioning::Unknown;
    std::vector<OptionInfo> options;
    /// Specs of the variants that the conformance suite and `--accel all` run.
    std::vector<std::string> variants;
    std::function<std::unique_ptr<Accel>(const Scene&, const AccelSpec&)> build;
    /// Whether `build` uses spec.threads (the bench then times it on each thread count).
    bool threaded_build = false;
    /// Restores a saved structure (the header is already read and checked); null if unsupported.
    std::function<std::unique_ptr<Accel>(std::istream&, const Scene&, const AccelSpec&)> load;
    /// For a structure whose kernels are chosen at run time: the kernels `spec` runs on this
    /// machine (bvh8: its ISA level, e.g. "avx2"), what the bench prints before it measures;
    /// null for the others.
    std::function<std::string(const AccelSpec&)> kernels;
};

/// Every registered structure, in registration order.
const std::vector<AccelInfo>& accel_registry();
const AccelInfo* find_accel(std::string_view name);

/// Parses and validates a spec and expands its preset options (preset_option()); throws Error
/// naming the bad name, key or value and listing what is allowed.
AccelSpec parse_accel_spec(std::string_view spec);

/// Every variant spec of every registered structure (what `--accel all` means).
std::vector<std::string> all_accel_variants();

/// The structure every front end builds when the user names none (`thicket render`, `trace`,
/// `info`, `bench`; the module's build(), its pictures, RaycastingScene, thicket.dask): the fastest.
inline constexpr const char* kDefaultSpec = "bvh8";
/// The structure that answers closest points for one that cannot (PointQueries' fallback, the
/// default of `thicket closest`): its 8-wide point traversal is the fastest.
inline constexpr const char* kClosestPointSpec = "bvh8";

/// Whether the structure `spec` builds traces float64 rays in double (precision=double): what
/// both front ends ask before taking float64 rays (a built one answers Accel::double_precision()).
bool takes_double_rays(const AccelSpec& spec);
/// The one refusal of float64 rays: `rays` names them (a file, an argument), `structure` the
/// float32 structure ("'bvh8'"), `fix` how the caller makes float32 rays. Lists every registered
/// structure with a precision option, so the next one is named without an edit.
std::string float64_rays_refusal(const std::string& rays, const std::string& structure, const std::string& fix);

/// Parses `spec` and builds the structure over `scene` on up to `threads` threads (0: every
/// core), filling stats().build_ms. The result does not depend on `threads`.
std::unique_ptr<Accel> build_accel(std::string_view spec, const Scene& scene, unsigned threads = 0);
/// Builds from a spec parse_accel_spec() already parsed, with the structure it names (a caller
/// that validated the spec up front need not parse it again).
std::unique_ptr<Accel> build_accel(const AccelSpec& spec, const Scene& scene, unsigned threads = 0);

/// Saves/loads a structure with a versioned header bound to the scene's fingerprint; the checksum
/// covers the spec text and the payload. save_accel writes through write_atomically().
void save_accel(const Accel& accel, const Scene& scene, const std::string& path);
std::unique_ptr<Accel> load_accel(const std::string& path, const Scene& scene);
/// The bytes save_accel() writes, and load_accel() of such bytes (`name` stands for the file in
/// messages): what the saved-structure fuzzer drives.
std::string saved_accel_bytes(const Accel& accel, const Scene& scene);
std::unique_ptr<Accel> load_accel_bytes(std::string_view bytes, const Scene& scene, const std::string& name);
/// The checksum save_accel() stores: FNV-1a over the spec text, then the payload.
uint64_t saved_accel_checksum(std::string_view spec, std::string_view payload);

/// Human-readable listing of every structure, its keys and allowed values (`thicket accels`).
std::string describe_accels();

}  // namespace thicket
