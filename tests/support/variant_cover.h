#pragma once
// Which registered variants the conformance suite instantiates: all of them in Release; under the
// sanitizers a smaller set that still runs every option value of every structure.
#include <string>
#include <vector>

namespace thicket::testing {

/// The variants whose option values (`key=value` after the name) cover all the values the given
/// variants use, per structure name, chosen greedily (the variant adding the most values not yet
/// covered, earlier on ties), returned in their original order. A variant without options counts
/// as covering its bare name.
std::vector<std::string> covering_variants(const std::vector<std::string>& variants);

/// every registered variant (all_accel_variants()) in Release builds and under THICKET_FULL; in
/// sanitized builds covering_variants() of them: the cross products of builders and traversals
/// run no code that their separate values do not, and the sanitizer job is ten times slower.
std::vector<std::string> conformance_variants();

/// The variants the shared real scenes run: covering_variants() of every registered variant, in
/// every build; all of them under THICKET_FULL (`scripts/test --full`). The full cross product of
/// builders and traversals runs on the nasty scenes (conformance_variants(), Release); on a real
/// scene each combination costs 10-100x as much and runs no code that its separate values do not.
std::vector<std::string> shared_scene_variants();

}  // namespace thicket::testing
