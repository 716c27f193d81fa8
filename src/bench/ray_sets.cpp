#include "thicket/bench/ray_sets.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "thicket/bench/rng.h"
#include "thicket/core/error.h"
#include "thicket/util/input_file.h"

namespace thicket {

namespace {

constexpr int kMaxSide = 16384;
// The interior probe (see ray_sets.h).
constexpr int kProbeWidth = 32, kProbeHeight = 24;
constexpr float kProbeFov = 60.0f;
constexpr double kProbeMinHits = 0.9, kProbeMinFront = 0.5;

Camera centre_camera(const Aabb& bounds) {
    const Vec3 c = bounds.center(), e = bounds.extent();
    const Vec3 look = e.x >= e.z ? Vec3{1, 0, 0} : Vec3{0, 0, 1};
    return Camera(c, c + look, {0, 1, 0}, kProbeFov);
}

bool centre_is_interior(const Scene& scene, const Accel& accel, const Camera& probe) {
    size_t hits = 0, front = 0;
    for (int j = 0; j < kProbeHeight; ++j) {
        for (int i = 0; i < kProbeWidth; ++i) {
            const Ray r = probe.generate(float(i) + 0.5f, float(j) + 0.5f, kProbeWidth, kProbeHeight);
            const Hit h = accel.intersect(r);
            if (!h.found()) continue;
            ++hits;
            front += dot(scene.normal(r, h), r.dir) < 0.0f;
        }
    }
    return double(hits) >= kProbeMinHits * kProbeWidth * kProbeHeight &&
           double(front) > kProbeMinFront * double(hits);
}

std::vector<Ray> primary_rays(const Camera& camera, int width, int height) {
    std::vector<Ray> rays;
    rays.reserve(size_t(width) * size_t(height));
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i)
            rays.push_back(camera.generate(float(i) + 0.5f, float(j) + 0.5f, width, height));
    return rays;
}

// A primary hit turned into what secondary rays need: where they start and the faced normal.
struct SurfacePoint {
    uint32_t pixel;
    Vec3 origin;
    Vec3 normal;
};

std::vector<SurfacePoint> surface_points(const Scene& scene, const Accel& accel, const std::vector<Ray>& primary,
                                         unsigned threads) {
    std::vector<Hit> hits(primary.size());
    BatchOptions batch;
    batch.threads = threads;
    accel.intersect(primary, hits, batch);
    const float offset = surface_offset(scene.bounds());
    std::vector<SurfacePoint> points;
    for (size_t i = 0; i < primary.size(); ++i) {
        if (!hits[i].found()) continue;
        const Ray& r = primary[i];
        Vec3 n = scene.normal(r, hits[i]);
        if (n == Vec3{}) continue;  // degenerate triangle: no usable normal
        if (dot(n, r.dir) > 0.0f) n = -n;
        const Vec3 p = r.org + r.dir * hits[i].t;
        points.push_back({uint32_t(i), p + n * offset, n});
    }
    return points;
}

RaySet shadow_set(const std::vector<SurfacePoint>& points, Vec3 light) {
    RaySet set{"shadow", true, {}, {}};
    for (const SurfacePoint& s : points) {
        const Vec3 to_light = light - s.origin;
        if (!(dot(s.normal, to_light) > 0.0f)) continue;
        const float distance = length(to_light);
        Ray r;
        r.org = s.origin;
        r.dir = to_light / distance;
        r.tmin = 0.0f;
        r.tmax = distance * (1.0f - 1e-4f);
        set.rays.push_back(r);
        set.source.push_back(s.pixel);
    }
    return set;
}

RaySet diffuse_set(const std::vector<SurfacePoint>& points) {
    RaySet set{"diffuse", false, {}, {}};
    Pcg32 rng(kDiffuseSeed);
    for (const SurfacePoint& s : points) {
        Ray r;
        r.org = s.origin;
        r.dir = sample_cosine_hemisphere(rng, s.normal);
        set.rays.push_back(r);
        set.source.push_back(s.pixel);
    }
    return set;
}

RaySet random_set(const Aabb& bounds, size_t count) {
    RaySet set{"random", false, {}, {}};
    if (bounds.empty()) return set;
    Pcg32 rng(kRandomSeed);
    const Vec3 extent = bounds.extent();
    set.rays.reserve(count);
    for (size_t i = 0; i < count; ++i) {
        Ray r;
        const float x = rng.next_float(), y = rng.next_float(), z = rng.next_float();
        // min + u * extent can round past max for u close to 1; keep origins inside the box.
        r.org = min(bounds.max, bounds.min + Vec3{x, y, z} * extent);
        r.dir = sample_unit_sphere(rng);
        set.rays.push_back(r);
    }
    return set;
}

void check_request(std::span<const std::string> names, const RaySetOptions& options) {
    if (options.width < 1 || options.height < 1 || options.width > kMaxSide || options.height > kMaxSide)
        throw Error("ray set size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                    ": width and height must be between 1 and " + std::to_string(kMaxSide));
    for (const std::string& name : names) parse_ray_set_list(name);  // validate before the slow work
}

}  // namespace

const std::vector<std::string>& ray_set_names() {
    static const std::vector<std::string> names{"primary", "shadow", "diffuse", "random"};
    return names;
}

std::vector<std::string> parse_ray_set_list(std::string_view text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = std::min(text.find(',', start), text.size());
        std::string name(text.substr(start, comma - start));
        name.erase(0, name.find_first_not_of(" \t"));
        name.erase(name.find_last_not_of(" \t") + 1);
        const auto& known = ray_set_names();
        if (std::find(known.begin(), known.end(), name) == known.end())
            throw Error("unknown ray set '" + name + "' in '" + std::string(text) +
                        "': expected a comma-separated list of primary, shadow, diffuse, random");
        if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
        start = comma + 1;
    }
    return out;
}

void parse_ray_set_size(std::string_view text, RaySetOptions& options) {
    const size_t x = text.find_first_of("xX");
    auto number = [](std::string_view s, int& out) {
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
        return !s.empty() && ec == std::errc() && end == s.data() + s.size();
    };
    int w = 0, h = 0;
    if (x == std::string_view::npos || !number(text.substr(0, x), w) || !number(text.substr(x + 1), h))
        throw Error("size '" + std::string(text) + "': expected WIDTHxHEIGHT, e.g. 320x240");
    if (w < 1 || h < 1 || w > kMaxSide || h > kMaxSide)
        throw Error("size '" + std::string(text) + "': width and height must be between 1 and " +
                    std::to_string(kMaxSide));
    options.width = w;
    options.height = h;
    // Checked now, before the scene is loaded: a size that cannot fit fails at once, saying how
    // much it needs, instead of std::bad_alloc (or swapping) minutes later.
    check_memory(ray_set_bytes(options), "size " + std::string(text) + ": the ray sets (" +
                                             std::to_string(uint64_t(w) * uint64_t(h)) + " rays each)");
}

uint64_t ray_set_bytes(const RaySetOptions& options) {
    // Per pixel: the primary ray and its hit, the surface point, every set's ray (at most four)
    // and the float matrix `thicket rays` writes.
    const uint64_t per_pixel = sizeof(Ray) + sizeof(Hit) + sizeof(SurfacePoint) + 4 * sizeof(Ray) + 8 * sizeof(float);
    return uint64_t(options.width) * uint64_t(options.height) * per_pixel;
}

RaySetView ray_set_view(const Scene& scene, const Accel& hits_from, const RaySetOptions& options) {
    const Aabb bounds = scene.bounds();
    const float aspect = float(options.width) / float(options.height);
    const Camera camera = options.camera ? *options.camera : auto_camera(bounds, aspect);
    RaySetView view{camera, light_above_bounds(bounds), false};
    if (bounds.empty() || !(max_component(bounds.extent()) > 0.0f)) return view;
    const Camera probe = centre_camera(bounds);
    view.interior = centre_is_interior(scene, hits_from, probe);
    if (!view.interior) return view;
    if (!options.camera) view.camera = probe;
    Ray up;
    up.org = bounds.center();
    up.dir = {0, 1, 0};
    const Hit ceiling = hits_from.intersect(up);
    if (ceiling.found()) view.light = up.org + up.dir * (0.75f * ceiling.t);
    return view;
}

Vec3 light_above_bounds(const Aabb& bounds) {
    if (bounds.empty()) return {0.0f, 1.0f, 0.0f};
    const Vec3 c = bounds.center();
    return {c.x, bounds.max.y + 0.5f * std::max(max_component(bounds.extent()), 1e-3f), c.z};
}

float surface_offset(const Aabb& bounds) {
    if (bounds.empty()) return 1e-4f;
    const float magnitude = std::max(max_component(abs(bounds.min)), max_component(abs(bounds.max)));
    const float scale = std::max(max_component(bounds.extent()), magnitude);
    return scale > 0.0f ? 1e-4f * scale : 1e-4f;
}

std::vector<RaySet> generate_ray_sets(const Scene& scene, const Accel& hits_from, std::span<const std::string> names,
                                      const RaySetOptions& options, unsigned threads) {
    check_request(names, options);
    return generate_ray_sets(scene, hits_from, ray_set_view(scene, hits_from, options), names, options, threads);
}

std::vector<RaySet> generate_ray_sets(const Scene& scene, const Accel& hits_from, const RaySetView& view,
                                      std::span<const std::string> names, const RaySetOptions& options,
                                      unsigned threads) {
    check_request(names, options);

    const std::vector<Ray> primary = primary_rays(view.camera, options.width, options.height);
    const bool secondary = std::any_of(names.begin(), names.end(),
                                       [](const std::string& n) { return n == "shadow" || n == "diffuse"; });
    std::vector<SurfacePoint> points;
    if (secondary) points = surface_points(scene, hits_from, primary, threads);

    std::vector<RaySet> sets;
    for (const std::string& name : names) {
        if (name == "primary")
            sets.push_back({"primary", false, primary, {}, true});
        else if (name == "shadow")
            sets.push_back(shadow_set(points, view.light));
        else if (name == "diffuse")
            sets.push_back(diffuse_set(points));
        else
            sets.push_back(random_set(scene.bounds(), primary.size()));
    }
    return sets;
}

std::vector<float> ray_matrix(std::span<const Ray> rays) {
    std::vector<float> out;
    out.reserve(rays.size() * 8);
    for (const Ray& r : rays) {
        const float row[8] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax};
        out.insert(out.end(), row, row + 8);
    }
    return out;
}

}  // namespace thicket
