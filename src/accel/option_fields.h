#pragma once
/// A structure's spec options bound to the members of the settings struct its builder takes.
/// Each option's key, help and range is written once, in its field; an integer's or a choice's
/// default is the member's value in a default-made settings struct (so the listing cannot drift
/// from the struct), and read_settings() fills the struct from a parsed spec. The register_*.cpp
/// files describe their options this way; registry.h's OptionInfo is what a field lists.
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "thicket/accel/registry.h"

namespace thicket {

/// One option of Settings and what it does to a Settings: `read` stores the spec's value (null
/// for an option no builder reads, such as a preset); `default_of` gives the listed default from
/// a default-made Settings (null: info.default_value as written). A field with an empty key
/// lists nothing and carries a value the spec holds beside its options (threads).
template <class Settings>
struct OptionField {
    OptionInfo info;
    std::function<void(const AccelSpec&, Settings&)> read;
    std::function<std::string(const Settings&)> default_of;
};

template <class Settings>
using OptionFields = std::vector<OptionField<Settings>>;

/// An integer option in [lo, hi] stored in `member` (converted to the member's type).
template <class Settings, class T>
OptionField<Settings> int_field(std::string key, std::string help, T Settings::*member, long lo, long hi) {
    OptionInfo info{key, std::move(help), {}, {}, lo, hi};
    return {std::move(info), [key, member](const AccelSpec& spec, Settings& s) { s.*member = T(spec.get_int(key)); },
            [member](const Settings& s) { return std::to_string(long(s.*member)); }};
}

/// A real option in [lo, hi] stored in `member`, its default written as the listing shows it.
template <class Settings>
OptionField<Settings> real_field(std::string key, std::string help, double Settings::*member, std::string fallback,
                                 double lo, double hi) {
    OptionInfo info = real_option(key, std::move(help), std::move(fallback), lo, hi);
    return {std::move(info), [key, member](const AccelSpec& spec, Settings& s) { s.*member = spec.get_real(key); },
            nullptr};
}

/// The name `table` gives `value` (empty if none).
template <class T, size_t N>
std::string choice_name(const Choice<T> (&table)[N], T value) {
    for (const Choice<T>& c : table)
        if (c.value == value) return c.name;
    return {};
}

/// A choice among the names of `table` (choice_option()), stored in `member`.
template <class Settings, class T, size_t N>
OptionField<Settings> choice_field(std::string key, std::string help, T Settings::*member,
                                   const Choice<T> (&table)[N]) {
    OptionInfo info = choice_option(key, std::move(help), Settings{}.*member, table);
    return {std::move(info),
            [key, member, &table](const AccelSpec& spec, Settings& s) { s.*member = spec.choice(key, table); },
            [member, &table](const Settings& s) { return choice_name(table, s.*member); }};
}

/// An option read by `read` (an option whose value is not a plain member), listed as `info`.
template <class Settings, class Read>
OptionField<Settings> custom_field(OptionInfo info, Read read) {
    return {std::move(info), std::function<void(const AccelSpec&, Settings&)>(std::move(read)), nullptr};
}

/// An option listed and parsed but read by no builder (a preset, which the parser expands).
template <class Settings>
OptionField<Settings> listed_field(OptionInfo info) {
    return {std::move(info), nullptr, nullptr};
}

/// The build's thread count (AccelSpec::threads, not an option) stored in `member`.
template <class Settings>
OptionField<Settings> threads_field(unsigned Settings::*member) {
    return {{}, [member](const AccelSpec& spec, Settings& s) { s.*member = spec.threads; }, nullptr};
}

/// `fields` of the struct held in Outer::*member, as fields of Outer: they read into that member
/// and take their defaults from it (bvh8's binary tree defaults are not the lecture BVH's).
template <class Outer, class Inner>
OptionFields<Outer> fields_in(Inner Outer::*member, OptionFields<Inner> fields) {
    OptionFields<Outer> out;
    for (OptionField<Inner>& f : fields) {
        OptionField<Outer> g{std::move(f.info), nullptr, nullptr};
        if (f.read)
            g.read = [member, read = std::move(f.read)](const AccelSpec& spec, Outer& o) { read(spec, o.*member); };
        if (f.default_of)
            g.default_of = [member, d = std::move(f.default_of)](const Outer& o) { return d(o.*member); };
        out.push_back(std::move(g));
    }
    return out;
}

/// The fields of each list, in order.
template <class Settings, class... More>
OptionFields<Settings> join_fields(OptionFields<Settings> first, More&&... more) {
    (first.insert(first.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end())), ...);
    return first;
}

/// The options `fields` list, each default filled in from a default-made Settings.
template <class Settings>
std::vector<OptionInfo> options_of(const OptionFields<Settings>& fields) {
    const Settings defaults{};
    std::vector<OptionInfo> options;
    for (const OptionField<Settings>& f : fields) {
        if (f.info.key.empty()) continue;
        options.push_back(f.info);
        if (f.default_of) options.back().default_value = f.default_of(defaults);
    }
    return options;
}

/// A default-made Settings with every field's value from `spec` stored in it.
template <class Settings>
Settings read_settings(const OptionFields<Settings>& fields, const AccelSpec& spec) {
    Settings s{};
    for (const OptionField<Settings>& f : fields)
        if (f.read) f.read(spec, s);
    return s;
}

/// The settings of a structure whose traversal is chosen beside its build (bvh, kdtree, octree):
/// a loaded tree takes the traversal too. kDefault is the traversal a spec gets by default.
template <class Build, class Traversal, Traversal kDefault>
struct BuildAndTraversal {
    Build build;
    Traversal traversal = kDefault;
};

/// What a registration says of a structure besides its options.
struct AccelText {
    std::string name;
    Partitioning partitioning = Partitioning::Unknown;
    std::string summary;
    /// The specs the conformance suite and `--accel all` run.
    std::vector<std::string> variants;
    /// Whether the build uses spec.threads (AccelInfo::threaded_build).
    bool threaded_build = false;
};

/// The registry entry `text` describes, with the options `fields` list; build and load unset.
template <class Settings>
AccelInfo accel_info(AccelText text, const OptionFields<Settings>& fields) {
    AccelInfo info;
    info.name = std::move(text.name);
    info.partitioning = text.partitioning;
    info.summary = std::move(text.summary);
    info.variants = std::move(text.variants);
    info.threaded_build = text.threaded_build;
    info.options = options_of(fields);
    return info;
}

}  // namespace thicket
