#pragma once
/// Queries from points rather than rays: the closest surface point, the distance to the surface,
/// whether a point is inside a closed surface, and the signed distance. The `thicket closest` and
/// `thicket occupancy` commands, the Python module's compute_* calls and C++ users all ask these.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>

#include "thicket/accel/accel.h"
#include "thicket/core/closest_point.h"
#include "thicket/scene/scene.h"
#include "thicket/util/parallel.h"

namespace thicket {

/// The most parity directions occupancy() votes over (nsamples must be odd and at most this).
inline constexpr int kMaxParitySamples = 5;

/// Throws Error unless nsamples is odd and in [1, kMaxParitySamples].
void check_parity_samples(int nsamples);

/// The index of the first point with a NaN or infinite coordinate, or points.size() if none: such
/// a point has no closest point and no inside, and the front ends refuse it up front.
size_t first_non_finite(std::span<const Vec3> points);

/// inside[k] = 1 if points[k] lies inside the closed surface `accel` holds, else 0: the parity of
/// the crossings (Accel::count_hits) along nsamples fixed directions, none along an axis or a
/// diagonal (so that rays from grid-aligned points do not run along the faces and edges of
/// axis-aligned meshes), the majority deciding. Traced on the calling thread; any number of points.
void inside_by_parity(const Accel& accel, std::span<const Vec3> points, int nsamples, std::span<uint8_t> inside);

/// Point queries over a structure and the scene it was built over; both must outlive this.
/// Closest points come from the structure itself when it answers them (brute, bvh and bvh8 over
/// triangles), else from a bvh8 over the same scene, built once on first use.
class PointQueries {
public:
    PointQueries(const Accel& accel, const Scene& scene) : accel_(accel), scene_(scene) {}

    /// The structure that answers closest points (building the bvh8 on the first call; safe to
    /// call from several threads). Throws Error when none can (a scene with shapes).
    const Accel& closest_accel() const;

    /// Calls f(begin, end, const NearestPoint* closest) for the points in chunks of kBatchGrain on
    /// `threads` threads, closest[k] being point begin + k's closest point: the answers stay on the
    /// stack of the thread that writes them out.
    template <class F>
    void for_each_closest_chunk(std::span<const Vec3> points, unsigned threads, F&& f) const {
        const Accel& accel = closest_accel();
        parallel_for(points.size(), kBatchGrain, threads, [&](size_t begin, size_t end) {
            NearestPoint closest[kBatchGrain];
            for (size_t i = begin; i < end; ++i) closest[i - begin] = accel.closest_point(points[i]);
            f(begin, end, static_cast<const NearestPoint*>(closest));
        });
    }

    /// The closest surface point of every point (prim kNoPrim for an empty scene).
    void closest_points(std::span<const Vec3> points, std::span<NearestPoint> out, const BatchOptions& options = {}) const;
    /// The distance from every point to the surface (inf for an empty scene).
    void distances(std::span<const Vec3> points, std::span<float> out, const BatchOptions& options = {}) const;
    /// 1 where a point is inside (inside_by_parity), else 0.
    void occupancy(std::span<const Vec3> points, std::span<uint8_t> out, int nsamples,
                   const BatchOptions& options = {}) const;
    /// distances(), negative where occupancy() says inside.
    void signed_distances(std::span<const Vec3> points, std::span<float> out, int nsamples,
                          const BatchOptions& options = {}) const;

private:
    const Accel& accel_;
    const Scene& scene_;
    mutable std::once_flag fallback_once_;
    mutable std::unique_ptr<Accel> fallback_;
};

}  // namespace thicket
