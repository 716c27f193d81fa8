#pragma once
/// The Embree backend of the bench: Embree 3 builds one triangle mesh over the scene (primitive id =
/// triangle index) at build quality medium or high and answers rays with rtcIntersect1 /
/// rtcOccluded1, behind the same Tracer interface, so it is timed exactly like Thicket's structures.
///
/// Conventions match Thicket's: rays hit for tmin <= t <= tmax (Embree's interval is (tnear, tfar],
/// so tnear is set just below tmin), t in units of the direction's length, (u, v) the weights of
/// vertices 1 and 2. The
/// scene is built with Embree's default flags (not RTC_SCENE_FLAG_ROBUST), as most users run it.
#include <memory>
#include <string>

#include "thicket/bench/tracer.h"

namespace thicket {

/// Refit: scene build quality low (Embree's two-level structure, the only one that reads a
/// geometry's own quality) with the mesh's geometry at RTC_BUILD_QUALITY_REFIT, so that
/// Tracer::refit (new vertices through rtcUpdateGeometryBuffer, rtcCommitGeometry,
/// rtcCommitScene) refits Embree's BVH instead of rebuilding it (`thicket bench --animate`).
enum class EmbreeQuality { Medium, High, Refit };

/// "embree-medium", "embree-high" or "embree-refit".
const char* embree_tracer_name(EmbreeQuality quality);

/// A tracer whose build() makes a fresh Embree device limited to the threads asked for (so the
/// one-thread build really runs on one thread), counts every byte the device allocates for the
/// scene through rtcSetDeviceMemoryMonitorFunction, and times rtcNewScene through rtcCommitScene.
/// Errors Embree reports become thicket::Error.
std::unique_ptr<Tracer> make_embree_tracer(EmbreeQuality quality);
TracerFactory embree_tracer_factory(EmbreeQuality quality);

/// Version of the Embree library in use, e.g. "3.13.5" (creates and releases a device).
std::string embree_version();

}  // namespace thicket
