#include "embree_tracer.h"

#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "thicket/core/isa.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket {

namespace {

constexpr size_t kGrain = kTraceGrain;  // the same chunking as Thicket's own tracer

// What Embree's callbacks report while a device lives.
struct DeviceLog {
    std::atomic<int64_t> bytes{0};  // net bytes the device holds (allocations minus frees)
    std::mutex mutex;
    std::string first_error;
};

bool on_memory(void* user, ssize_t bytes, bool) {
    static_cast<DeviceLog*>(user)->bytes.fetch_add(int64_t(bytes), std::memory_order_relaxed);
    return true;  // never veto an allocation
}

void on_error(void* user, RTCError code, const char* message) {
    auto* log = static_cast<DeviceLog*>(user);
    std::lock_guard<std::mutex> lock(log->mutex);
    if (log->first_error.empty())
        log->first_error =
            "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "(no message)");
}

/// Embree's name for the level THICKET_ISA caps bvh8 to ("" when it is unset): the level comes
/// from the library's own reading of the variable (core/isa.h's resolve_isa, which refuses a bad
/// value with its message); Embree has no scalar kernels, so scalar and sse both give its SSE2 level.
std::string embree_isa_for_env() {
    const char* env = std::getenv("THICKET_ISA");
    if (!env || !*env) return "";
    switch (resolve_isa(kAutoIsa, "bvh8")) {
    case Isa::Scalar:
    case Isa::Sse: return "sse2";
    case Isa::Avx2: return "avx2";
    case Isa::Avx512: return "avx512";
    }
    return "";
}

class EmbreeTracer final : public Tracer {
public:
    explicit EmbreeTracer(EmbreeQuality quality) : quality_(quality) {}
    ~EmbreeTracer() override { release(); }
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    std::string name() const override { return embree_tracer_name(quality_); }
    bool parallel_build() const override { return true; }

    double build(const Scene& scene, unsigned threads) override {
        if (scene.has_shapes())
            throw Error("Embree backend: " + scene.name + " has " + std::to_string(scene.shapes.size()) +
                        " shapes, and this backend holds triangles only");
        release();
        log_ = std::make_unique<DeviceLog>();
        // threads=N bounds Embree's task system; 0 leaves it at one thread per core. THICKET_ISA
        // caps Embree's kernels as it caps bvh8's, so that a capped run compares like with like.
        std::string config = threads ? "threads=" + std::to_string(threads) : "";
        const std::string isa = embree_isa_for_env();
        if (!isa.empty()) {
            if (!config.empty()) config += ',';
            config += "isa=";
            config += isa;
        }
        device_ = rtcNewDevice(config.c_str());
        if (!device_)
            throw Error("Embree: cannot create a device (error " + std::to_string(int(rtcGetDeviceError(nullptr))) +
                        ")");
        rtcSetDeviceErrorFunction(device_, on_error, log_.get());
        rtcSetDeviceMemoryMonitorFunction(device_, on_memory, log_.get());

        // Our own copies of the mesh, shared with Embree (not copied by it, so not in its byte
        // count): positions padded by one float because Embree reads vertices with 16-byte loads.
        const TriangleMesh& mesh = scene.mesh;
        vertices_.assign(3 * mesh.positions.size() + 1, 0.0f);
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            vertices_[3 * i] = mesh.positions[i].x;
            vertices_[3 * i + 1] = mesh.positions[i].y;
            vertices_[3 * i + 2] = mesh.positions[i].z;
        }
        indices_ = mesh.indices;
        indices_.push_back(0);
        primitives_ = mesh.triangle_count();

        // Commit an empty scene first, untimed: it starts the device's task system, a one-time cost
        // that would otherwise land on whichever build happens to come first.
        RTCScene warm_up = rtcNewScene(device_);
        rtcCommitScene(warm_up);
        rtcReleaseScene(warm_up);

        // Embree reads a geometry's own quality (REFIT) only in a scene of quality LOW, the
        // two-level structure whose per-geometry BVHs can be refitted (rtcSetGeometryBuildQuality).
        const RTCBuildQuality quality = quality_ == EmbreeQuality::High     ? RTC_BUILD_QUALITY_HIGH
                                        : quality_ == EmbreeQuality::Medium ? RTC_BUILD_QUALITY_MEDIUM
                                                                            : RTC_BUILD_QUALITY_LOW;
        const RTCBuildQuality geometry_quality = quality_ == EmbreeQuality::Refit ? RTC_BUILD_QUALITY_REFIT : quality;
        const int64_t before = log_->bytes.load();
        const auto start = std::chrono::steady_clock::now();
        scene_ = rtcNewScene(device_);
        rtcSetSceneBuildQuality(scene_, quality);
        if (!scene.instances.empty()) {
            attach_instances(scene, quality);
        } else if (primitives_ > 0) {
            RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
            rtcSetGeometryBuildQuality(geometry, geometry_quality);
            rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_.data(), 0,
                                       3 * sizeof(float), mesh.positions.size());
            rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices_.data(), 0,
                                       3 * sizeof(uint32_t), primitives_);
            rtcCommitGeometry(geometry);
            rtcAttachGeometryByID(scene_, geometry, 0);
            rtcReleaseGeometry(geometry);  // the scene keeps it
            geometry_ = geometry;          // valid as long as scene_ is
        }
        rtcCommitScene(scene_);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        check();
        bytes_ = size_t(std::max<int64_t>(0, log_->bytes.load() - before));
        return ms;
    }

    /// New vertices into the shared buffer, then Embree's refit (EmbreeQuality::Refit only).
    double refit(const Scene& scene, unsigned) override {
        if (quality_ != EmbreeQuality::Refit) return Tracer::refit(scene, 0);
        get();
        if (!instance_first_.empty()) throw Error(name() + " refit: an instanced scene is not refitted here");
        if (scene.mesh.triangle_count() != primitives_ || 3 * scene.mesh.positions.size() + 1 != vertices_.size())
            throw Error(name() + " refit: " + scene.name + " has another topology than the build's");
        const auto start = std::chrono::steady_clock::now();
        const std::vector<Vec3>& p = scene.mesh.positions;
        for (size_t i = 0; i < p.size(); ++i) {
            vertices_[3 * i] = p[i].x;
            vertices_[3 * i + 1] = p[i].y;
            vertices_[3 * i + 2] = p[i].z;
        }
        if (geometry_) {
            rtcUpdateGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, 0);
            rtcCommitGeometry(geometry_);
        }
        rtcCommitScene(scene_);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        check();
        return ms;
    }

    TracerFigures figures() const override {
        TracerFigures f;
        f.spec = std::string("embree ") + embree_version_of(device_) + " rtcIntersect1/rtcOccluded1, build quality " +
                 (quality_ == EmbreeQuality::High     ? "high"
                  : quality_ == EmbreeQuality::Medium ? "medium"
                                                      : "low (two-level), geometry refit");
        if (const std::string isa = embree_isa_for_env(); !isa.empty()) {
            f.spec += ", isa=";
            f.spec += isa;
            f.spec += " (THICKET_ISA)";
        }
        if (!instance_first_.empty()) f.spec += ", instances (RTC_GEOMETRY_TYPE_INSTANCE)";
        f.primitives = primitives_;
        f.bytes = bytes_;
        f.structure_bytes = bytes_;  // Embree's leaves hold the triangles: not separable
        return f;
    }

    bool hits_from_thicket_tests() const override { return false; }

    void trace(std::span<const Ray> rays, std::span<Hit> hits, unsigned threads, bool) const override {
        RTCScene scene = get();
        parallel_for(rays.size(), kGrain, threads, [&](size_t begin, size_t end) {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            for (size_t i = begin; i < end; ++i) {
                RTCRayHit rh;
                set_ray(rh.ray, rays[i]);
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(scene, &context, &rh);
                const bool found = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                // An instance's hit names the flattened id, as Thicket's instanced structure does.
                const uint32_t prim = !found || instance_first_.empty()
                                          ? rh.hit.primID
                                          : uint32_t(instance_first_[rh.hit.instID[0]] + rh.hit.primID);
                hits[i] = found ? Hit{rh.ray.tfar, rh.hit.u, rh.hit.v, prim} : Hit{};
            }
        });
        check();
    }

    void occluded(std::span<const Ray> rays, std::span<uint8_t> out, unsigned threads) const override {
        RTCScene scene = get();
        parallel_for(rays.size(), kGrain, threads, [&](size_t begin, size_t end) {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            for (size_t i = begin; i < end; ++i) {
                RTCRay ray;
                set_ray(ray, rays[i]);
                rtcOccluded1(scene, &context, &ray);
                out[i] = ray.tfar == -INFINITY ? 1 : 0;  // Embree marks an occluded ray with tfar = -inf
            }
        });
        check();
    }

    bool count(std::span<const Ray>, bool, RayCounters&, unsigned) const override { return false; }

    static std::string embree_version_of(RTCDevice device) {
        if (!device) return RTC_VERSION_STRING;
        const ssize_t v = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION);  // e.g. 31305
        return std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) + "." + std::to_string(v % 100);
    }

private:
    // Embree accepts t in (tnear, tfar] (its tests compare tnear < t), ours in [tmin, tmax]: start
    // from the float just below tmin. tmin = 0 stays 0 because Embree needs tnear >= 0, so a hit at
    // exactly t = 0, at the very origin, is the one hit Embree cannot report.
    static float embree_tnear(float tmin) { return tmin > 0.0f ? std::nextafter(tmin, 0.0f) : tmin; }

    static void set_ray(RTCRay& out, const Ray& r) {
        out.org_x = r.org.x;
        out.org_y = r.org.y;
        out.org_z = r.org.z;
        out.tnear = embree_tnear(r.tmin);
        out.dir_x = r.dir.x;
        out.dir_y = r.dir.y;
        out.dir_z = r.dir.z;
        out.time = 0.0f;
        out.tfar = r.tmax;
        out.mask = 0xFFFFFFFFu;  // Embree is built with ray masks: a zero mask would hit nothing
        out.id = 0;
        out.flags = 0;
    }

    RTCScene get() const {
        if (!scene_) throw Error(name() + " used before build()");
        return scene_;
    }

    void check() const {
        std::lock_guard<std::mutex> lock(log_->mutex);
        if (!log_->first_error.empty()) throw Error(name() + ": " + log_->first_error);
    }

    /// Embree's two-level instancing (RTC_GEOMETRY_TYPE_INSTANCE) for a scene with instances: one
    /// child scene per geometry some instance uses, over our shared copies of its vertices (the
    /// buffer offset at its first vertex) and of its indices made relative to that vertex; one
    /// instance geometry per instance, its id the instance's, with the 3x4 row-major transform.
    void attach_instances(const Scene& scene, RTCBuildQuality quality) {
        instance_first_ = scene.instance_first;
        primitives_ = size_t(scene.instanced_primitive_count());
        for (size_t g = 0; g < scene.geometry_count(); ++g) {
            const Geometry geo = scene.geometry(uint32_t(g));
            if (geo.count == 0) continue;
            const size_t tri = scene.locate(geo.first).index;
            for (size_t k = 3 * tri; k < 3 * (tri + geo.count); ++k) indices_[k] -= geo.vertex_first;
        }
        children_.assign(scene.geometry_count(), nullptr);
        for (size_t i = 0; i < scene.instances.size(); ++i) {
            const Instance& inst = scene.instances[i];
            RTCScene& child = children_[inst.geometry];
            if (!child) {
                const Geometry geo = scene.geometry(inst.geometry);
                child = rtcNewScene(device_);
                rtcSetSceneBuildQuality(child, quality);
                if (geo.count > 0) {
                    const size_t tri = scene.locate(geo.first).index;
                    RTCGeometry mesh = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
                    rtcSetGeometryBuildQuality(mesh, quality);
                    rtcSetSharedGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_.data(),
                                               3 * sizeof(float) * geo.vertex_first, 3 * sizeof(float),
                                               geo.vertex_count);
                    rtcSetSharedGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices_.data(),
                                               3 * sizeof(uint32_t) * tri, 3 * sizeof(uint32_t), geo.count);
                    rtcCommitGeometry(mesh);
                    rtcAttachGeometryByID(child, mesh, 0);
                    rtcReleaseGeometry(mesh);
                }
                rtcCommitScene(child);
            }
            RTCGeometry placed = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(placed, child);
            rtcSetGeometryTransform(placed, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &inst.transform.m[0][0]);
            rtcCommitGeometry(placed);
            rtcAttachGeometryByID(scene_, placed, unsigned(i));
            rtcReleaseGeometry(placed);
        }
    }

    void release() {
        for (RTCScene child : children_)
            if (child) rtcReleaseScene(child);
        children_.clear();
        instance_first_.clear();
        if (scene_) rtcReleaseScene(scene_);
        if (device_) rtcReleaseDevice(device_);
        scene_ = nullptr;
        device_ = nullptr;
        geometry_ = nullptr;
    }

    EmbreeQuality quality_;
    std::unique_ptr<DeviceLog> log_;
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    RTCGeometry geometry_ = nullptr;  ///< the mesh, owned by scene_ (refit updates its vertices)
    std::vector<float> vertices_;
    std::vector<uint32_t> indices_;
    size_t primitives_ = 0;
    size_t bytes_ = 0;
    std::vector<RTCScene> children_;        ///< per geometry of an instanced scene: its own scene, or null
    std::vector<uint64_t> instance_first_;  ///< Scene::instance_first of an instanced scene; empty otherwise
};

}  // namespace

const char* embree_tracer_name(EmbreeQuality quality) {
    switch (quality) {
    case EmbreeQuality::High: return "embree-high";
    case EmbreeQuality::Medium: return "embree-medium";
    case EmbreeQuality::Refit: return "embree-refit";
    }
    return "embree";
}

std::unique_ptr<Tracer> make_embree_tracer(EmbreeQuality quality) {
    return std::make_unique<EmbreeTracer>(quality);
}

TracerFactory embree_tracer_factory(EmbreeQuality quality) {
    return {embree_tracer_name(quality), [quality] { return make_embree_tracer(quality); }};
}

std::string embree_version() {
    RTCDevice device = rtcNewDevice("threads=1");
    if (!device) return RTC_VERSION_STRING;
    const std::string v = EmbreeTracer::embree_version_of(device);
    rtcReleaseDevice(device);
    return v;
}

}  // namespace thicket
