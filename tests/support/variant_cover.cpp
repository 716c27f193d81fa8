#include "support/variant_cover.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>

#include "thicket/accel/registry.h"

namespace thicket::testing {
namespace {

/// "bvh:builder=lbvh,max-leaf=1" -> name "bvh", values {"builder=lbvh", "max-leaf=1"}.
void split_variant(const std::string& variant, std::string& name, std::set<std::string>& values) {
    const size_t colon = variant.find(':');
    name = variant.substr(0, colon);
    values.clear();
    if (colon == std::string::npos) {
        values.insert(name);
        return;
    }
    size_t start = colon + 1;
    while (start <= variant.size()) {
        const size_t comma = std::min(variant.find(',', start), variant.size());
        if (comma > start) values.insert(variant.substr(start, comma - start));
        start = comma + 1;
    }
}

bool full_run_requested() {
    const char* full = std::getenv("THICKET_FULL");
    return full && *full && std::string(full) != "0";
}

}  // namespace

std::vector<std::string> covering_variants(const std::vector<std::string>& variants) {
    std::vector<std::string> names(variants.size());
    std::vector<std::set<std::string>> values(variants.size());
    std::map<std::string, std::set<std::string>> uncovered;  // per structure name
    for (size_t i = 0; i < variants.size(); ++i) {
        split_variant(variants[i], names[i], values[i]);
        uncovered[names[i]].insert(values[i].begin(), values[i].end());
    }
    std::vector<bool> chosen(variants.size(), false);
    for (auto& [name, left] : uncovered) {
        while (!left.empty()) {
            size_t best = variants.size(), best_gain = 0;
            for (size_t i = 0; i < variants.size(); ++i) {
                if (chosen[i] || names[i] != name) continue;
                size_t gain = 0;
                for (const std::string& v : values[i]) gain += left.count(v);
                if (gain > best_gain) best = i, best_gain = gain;
            }
            chosen[best] = true;  // best_gain > 0: every uncovered value comes from some variant
            for (const std::string& v : values[best]) left.erase(v);
        }
    }
    std::vector<std::string> out;
    for (size_t i = 0; i < variants.size(); ++i)
        if (chosen[i]) out.push_back(variants[i]);
    return out;
}

std::vector<std::string> conformance_variants() {
#ifdef THICKET_SANITIZED
    if (!full_run_requested()) return covering_variants(all_accel_variants());
#endif
    return all_accel_variants();
}

std::vector<std::string> shared_scene_variants() {
    if (full_run_requested()) return all_accel_variants();
    return covering_variants(all_accel_variants());
}

}  // namespace thicket::testing
