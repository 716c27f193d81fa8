// `thicket bench --offset D`: what double precision costs (time per ray against the float bvh)
// and what it buys (answers 1e7 from the origin that float gets wrong).
#include "bench_precision.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "common.h"
#include "thicket/scene/translate.h"
#include "thicket/accel/registry.h"
#include "thicket/bench/ray_sets.h"
#include "thicket/core/error.h"

namespace thicket::cli {

namespace {

/// Median seconds of `reps` passes of `pass` (after one untimed warm-up).
template <class Pass>
double median_seconds(int reps, Pass&& pass) {
    pass();
    std::vector<double> s;
    for (int i = 0; i < reps; ++i) {
        const auto start = std::chrono::steady_clock::now();
        pass();
        s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(s.begin(), s.end());
    return s[s.size() / 2];
}


}  // namespace

int run_precision_bench(const std::vector<std::string>& scenes, double offset, int reps, unsigned threads) {
    std::printf("%-28s %-8s %8s %12s %12s %7s\n", "scene", "set", "rays", "float ns/ray", "double ns/ray", "ratio");
    std::vector<std::string> offset_lines;
    for (const std::string& path : scenes) {
        const Scene scene = load_scene(path);
        if (scene.has_shapes()) throw Error(path + ": precision=double takes triangle scenes only");
        const auto as_float = build_accel("bvh", scene, threads);
        const auto as_double = build_accel("bvh:precision=double", scene, threads);
        const std::vector<std::string> names = {"primary", "diffuse"};
        const auto hits_from = build_accel(kRaySetHitSpec, scene, threads);
        const std::vector<RaySet> sets = generate_ray_sets(scene, *hits_from, names, RaySetOptions{}, threads);
        std::vector<RayD> judged;  // the rays the offset figure moves
        for (const RaySet& set : sets) {
            std::vector<RayD> rays;
            for (const Ray& r : set.rays) rays.push_back(to_double(r));
            std::vector<Hit> hits(set.rays.size());
            std::vector<HitD> hits_d(rays.size());
            BatchOptions batch;
            batch.threads = threads;
            const double f = median_seconds(reps, [&] { as_float->intersect(set.rays, hits, batch); });
            const double d = median_seconds(reps, [&] { as_double->intersect_double(rays, hits_d, batch); });
            const double n = double(std::max<size_t>(1, rays.size()));
            std::printf("%-28s %-8s %8zu %12.1f %12.1f %6.2fx\n", scene.name.substr(0, 28).c_str(), set.name.c_str(),
                        rays.size(), 1e9 * f / n, 1e9 * d / n, f > 0 ? d / f : 0.0);
            judged.insert(judged.end(), rays.begin(), rays.end());
        }
        if (offset == 0.0) continue;
        const Scene moved = translated_scene(scene, offset);
        const auto moved_float = build_accel("bvh", moved, threads);
        const auto moved_double = build_accel("bvh:precision=double", moved, threads);
        const auto brute = build_accel("brute:precision=double", moved, threads);
        // Brute force costs rays x triangles: every k-th ray, about 2e8 triangle tests in all.
        const size_t want = std::clamp<size_t>(200'000'000 / std::max<size_t>(1, scene.primitive_count()), 100, 20'000);
        const size_t stride = std::max<size_t>(1, judged.size() / want);
        std::vector<RayD> rays;
        for (size_t i = 0; i < judged.size(); i += stride) {
            RayD r = judged[i];
            r.org = r.org + Vec3d(offset, offset, offset);
            rays.push_back(r);
        }
        std::vector<HitD> want_hits(rays.size()), got(rays.size());
        BatchOptions batch;
        batch.threads = threads;
        brute->intersect_double(rays, want_hits, batch);
        moved_double->intersect_double(rays, got, batch);
        size_t double_differs = 0, float_differs = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            double_differs += got[i].prim != want_hits[i].prim || got[i].t != want_hits[i].t;
            const Ray f{rays[i].org.to_float(), float(rays[i].tmin), rays[i].dir.to_float(), float(rays[i].tmax)};
            float_differs += moved_float->intersect(f).prim != want_hits[i].prim;
        }
        char line[512];
        std::snprintf(line, sizeof line,
                      "%-28s moved by %g: %zu rays judged by double brute force: double bvh differs on %zu "
                      "(%.2f%%), float bvh on %zu (%.2f%%)",
                      scene.name.substr(0, 28).c_str(), offset, rays.size(), double_differs,
                      100.0 * double(double_differs) / double(rays.size()), float_differs,
                      100.0 * double(float_differs) / double(rays.size()));
        offset_lines.push_back(line);
    }
    for (const std::string& l : offset_lines) std::printf("%s\n", l.c_str());
    return 0;
}

}  // namespace thicket::cli
