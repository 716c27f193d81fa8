#pragma once
/// One allowed value of a choice option, on its own so that a structure's plain headers can hold
/// their name tables without the registry (bvh8's ISA levels: thicket/bvh8/isa.h).

namespace thicket {

/// One allowed value of a choice option: its spelling in a spec and the value it stands for.
/// A structure declares each choice option as one array of these, e.g.
///   constexpr Choice<BvhBuilder> kBuilders[] = {{"midpoint", BvhBuilder::Midpoint}, ...};
template <class T>
struct Choice {
    const char* name;
    T value;
};

}  // namespace thicket
