// The Tracer adapter of Thicket's own structures: Accel's batch queries (one virtual call per
// ray unless the structure traces packets of coherent rays).
#include <chrono>
#include <memory>
#include <mutex>

#include "thicket/accel/registry.h"
#include "thicket/bench/tracer.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket {

namespace {

constexpr size_t kGrain = kTraceGrain;

class AccelTracer final : public Tracer {
public:
    /// `spec`: `name` parsed (once: every build of this tracer uses it).
    AccelTracer(std::string name, AccelSpec spec) : name_(std::move(name)), spec_(std::move(spec)) {}

    std::string name() const override { return name_; }
    bool parallel_build() const override {
        return spec_.info && spec_.info->threaded_build;
    }

    double build(const Scene& scene, unsigned threads) override {
        accel_.reset();  // free the old structure before building the next
        accel_ = build_accel(spec_, scene, threads);
        return accel_->build_ms();
    }

    double refit(const Scene& scene, unsigned threads) override {
        Accel& accel = get_mutable();
        const auto start = std::chrono::steady_clock::now();
        accel.refit(scene, threads);
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }

    TracerFigures figures() const override {
        const AccelStats s = get().stats();
        TracerFigures f;
        f.spec = s.spec;
        f.primitives = s.primitives;
        f.structure_bytes = s.bytes;
        f.primitive_bytes = s.primitive_bytes;
        f.bytes = s.bytes + s.primitive_bytes;
        f.nodes = s.nodes;
        f.sah_cost = s.sah_cost;
        return f;
    }

    void trace(std::span<const Ray> rays, std::span<Hit> hits, unsigned threads, bool coherent) const override {
        BatchOptions batch;
        batch.threads = threads;
        batch.coherent = coherent;
        get().intersect(rays, hits, batch);
    }

    void occluded(std::span<const Ray> rays, std::span<uint8_t> out, unsigned threads) const override {
        BatchOptions batch;
        batch.threads = threads;
        get().occluded(rays, out, batch);
    }

    bool count(std::span<const Ray> rays, bool any_hit, RayCounters& total, unsigned threads) const override {
        const Accel& a = get();
        std::mutex mutex;
        parallel_for(rays.size(), kGrain, threads, [&](size_t begin, size_t end) {
            RayCounters local;
            for (size_t i = begin; i < end; ++i) {
                if (any_hit)
                    a.occluded(rays[i], local);
                else
                    a.intersect(rays[i], local);
            }
            std::lock_guard<std::mutex> lock(mutex);
            total += local;
        });
        return true;
    }

private:
    const Accel& get() const {
        if (!accel_) throw Error("tracer '" + name_ + "' used before build()");
        return *accel_;
    }
    Accel& get_mutable() {
        if (!accel_) throw Error("tracer '" + name_ + "' used before build()");
        return *accel_;
    }

    std::string name_;
    AccelSpec spec_;
    std::unique_ptr<Accel> accel_;
};

}  // namespace

double Tracer::refit(const Scene&, unsigned) {
    throw Error("'" + name() + "' cannot refit: rebuild it instead");
}

std::unique_ptr<Tracer> make_accel_tracer(const std::string& spec) {
    return std::make_unique<AccelTracer>(spec, parse_accel_spec(spec));
}

TracerFactory accel_tracer_factory(const std::string& spec) {
    return accel_tracer_factory(spec, parse_accel_spec(spec));  // a typo fails here, before any tracer is made
}

TracerFactory accel_tracer_factory(const std::string& name, const AccelSpec& parsed) {
    return {name, [name, parsed] { return std::unique_ptr<Tracer>(std::make_unique<AccelTracer>(name, parsed)); }};
}

}  // namespace thicket
