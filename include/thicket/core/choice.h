#pragma once
/// One allowed value of a choice option, on the ground floor so that any header can hold its name
/// table without the registry (the ISA levels: thicket/core/isa.h; the structures' options).

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
