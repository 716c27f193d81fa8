// thicket_build_phases: where a `bvh8` build's time goes, phase by phase, beside Embree's own
// builder (rtcBuildBVH) producing the same output, 8-wide nodes and 4-triangle blocks, from the
// same triangles (issue 44's floor). Embree is one library call, so its phases are told apart
// by what it is given and asked to write:
//   refs      the 32-byte RTCBuildPrimitive array (Embree's PrimRefs), on the build's threads;
//   split     rtcBuildBVH whose callbacks only allocate (binning, partition, leaf decisions,
//             Embree's thread-local allocator: everything but our output);
//   emission  the same call whose callbacks also write every node's 8 boxes and child
//             pointers and fill each leaf's 4-triangle blocks from the mesh (the difference);
// and the scene build the bench compares with (rtcCommitScene, Embree's own leaves).
// Ours are our build's public steps run one after another, as the Bvh8 constructor runs them:
// the triangle copy, the boxes, the binary build, block_count, the collapse (nodes) and
// pack_blocks inside it (blocks), and the whole structure built end to end for comparison.
//   build/embree/thicket_build_phases ../shared/scenes/dragon.ply --threads 2 --reps 5
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "thicket/bvh8/bvh8.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/util/parallel.h"

namespace thicket {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

/// The process's minor page faults so far: first touches of fresh memory (on the virtual
/// machines measured, ~10 us each on 4 KiB pages).
long minor_faults() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_minflt;
}

/// What rtcBuildBVH's callbacks write in the full run: a bvh8-sized node (256 bytes of boxes,
/// child slots and masks as our Node) plus the 8 child pointers Embree hands over.
struct EmbreeNode {
    bvh8::Node node;
    void* child[8];
};
/// A leaf: its blocks follow the header.
struct EmbreeLeaf {
    uint32_t blocks;
    uint32_t pad[15];
    bvh8::Tri4* block() { return reinterpret_cast<bvh8::Tri4*>(this + 1); }
};

struct EmbreeUser {
    const TriangleMesh* mesh;
    const Triangles<>* tris;  ///< exact clipping of spatial splits (embree-high)
    bool write;               ///< false: the callbacks only allocate
};

void* create_node(RTCThreadLocalAllocator alloc, unsigned count, void* user) {
    auto* n = static_cast<EmbreeNode*>(rtcThreadLocalAlloc(alloc, sizeof(EmbreeNode), 64));
    if (static_cast<EmbreeUser*>(user)->write) {
        for (auto& axis : n->node.box)
            for (int lane = 0; lane < bvh8::kWidth; ++lane) axis[0][lane] = kInfinity, axis[1][lane] = -kInfinity;
        n->node.valid = (1u << count) - 1;
    }
    return n;
}

void set_children(void* node, void** children, unsigned count, void* user) {
    if (!static_cast<EmbreeUser*>(user)->write) return;
    auto* n = static_cast<EmbreeNode*>(node);
    for (unsigned i = 0; i < count; ++i) n->child[i] = children[i];
}

void set_bounds(void* node, const RTCBounds** bounds, unsigned count, void* user) {
    if (!static_cast<EmbreeUser*>(user)->write) return;
    auto* n = static_cast<EmbreeNode*>(node);
    for (unsigned i = 0; i < count; ++i) {
        const RTCBounds& b = *bounds[i];
        n->node.box[0][0][i] = b.lower_x, n->node.box[1][0][i] = b.lower_y, n->node.box[2][0][i] = b.lower_z;
        n->node.box[0][1][i] = b.upper_x, n->node.box[1][1][i] = b.upper_y, n->node.box[2][1][i] = b.upper_z;
    }
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void* user) {
    const auto* u = static_cast<EmbreeUser*>(user);
    const uint32_t blocks = uint32_t((count + 3) / 4);
    auto* leaf = static_cast<EmbreeLeaf*>(
        rtcThreadLocalAlloc(alloc, sizeof(EmbreeLeaf) + blocks * sizeof(bvh8::Tri4), 64));
    leaf->blocks = blocks;
    if (!u->write) return leaf;
    for (uint32_t b = 0; b < blocks; ++b) {  // as pack_blocks fills them: unused lanes zero, kNoPrim
        bvh8::Tri4& t = leaf->block()[b];
        for (int lane = 0; lane < 4; ++lane) {
            const size_t k = size_t(b) * 4 + size_t(lane);
            const bool used = k < count;
            for (int vertex = 0; vertex < 3; ++vertex) {
                const Vec3 v = used ? u->mesh->vertex(prims[k].primID, vertex) : Vec3(0.0f, 0.0f, 0.0f);
                for (int a = 0; a < 3; ++a) t.v[vertex][a][lane] = v[a];
            }
            t.id[lane] = used ? prims[k].primID : kNoPrim;
        }
    }
    return leaf;
}

void split_primitive(const RTCBuildPrimitive* prim, unsigned dim, float position, RTCBounds* left, RTCBounds* right,
                     void* user) {
    const auto* u = static_cast<EmbreeUser*>(user);
    Aabb lo{{prim->lower_x, prim->lower_y, prim->lower_z}, {prim->upper_x, prim->upper_y, prim->upper_z}}, hi = lo;
    lo.max[int(dim)] = position;
    hi.min[int(dim)] = position;
    lo = clipped_bounds(*u->tris, prim->primID, lo);
    hi = clipped_bounds(*u->tris, prim->primID, hi);
    *left = {lo.min.x, lo.min.y, lo.min.z, 0.0f, lo.max.x, lo.max.y, lo.max.z, 0.0f};
    *right = {hi.min.x, hi.min.y, hi.min.z, 0.0f, hi.max.x, hi.max.y, hi.max.z, 0.0f};
}

/// Embree's primitive references, on `threads` threads (Embree's scene build makes them in parallel).
void make_refs(const TriangleMesh& mesh, unsigned threads, std::vector<RTCBuildPrimitive>& refs) {
    parallel_for(mesh.triangle_count(), 16384, threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            Aabb b;
            for (int c = 0; c < 3; ++c) b.grow(mesh.vertex(i, c));
            refs[i] = {b.min.x, b.min.y, b.min.z, 0, b.max.x, b.max.y, b.max.z, uint32_t(i)};
        }
    });
}

struct EmbreeTimes {
    double refs = 0, split = 0, full = 0, scene = 0, scene_faults = 0;
};

/// One Embree build of each kind on `device`.
EmbreeTimes time_embree(RTCDevice device, const TriangleMesh& mesh, const Triangles<>& tris, bool high,
                        unsigned threads) {
    EmbreeTimes t;
    const size_t n = mesh.triangle_count();
    std::vector<RTCBuildPrimitive> refs;
    for (bool write : {false, true}) {
        refs.clear();
        refs.shrink_to_fit();  // fresh memory each build, as Embree's scene build allocates it
        const auto start = Clock::now();
        refs.resize(high ? n + (n + 4) / 5 : n);  // embree-high: 20% more references (Embree's default)
        make_refs(mesh, threads, refs);
        const double refs_ms = ms_since(start);
        EmbreeUser user{&mesh, &tris, write};
        RTCBVH bvh = rtcNewBVH(device);
        RTCBuildArguments args = rtcDefaultBuildArguments();
        args.buildQuality = high ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
        args.maxBranchingFactor = 8;
        args.maxDepth = 40;
        args.sahBlockSize = 4;
        args.minLeafSize = 4;
        args.maxLeafSize = 28;
        args.traversalCost = 1.0f;
        args.intersectionCost = 1.0f;
        args.bvh = bvh;
        args.primitives = refs.data();
        args.primitiveCount = n;
        args.primitiveArrayCapacity = refs.size();
        args.createNode = create_node;
        args.setNodeChildren = set_children;
        args.setNodeBounds = set_bounds;
        args.createLeaf = create_leaf;
        args.splitPrimitive = high ? split_primitive : nullptr;
        args.userPtr = &user;
        const auto built = Clock::now();
        if (!rtcBuildBVH(&args)) throw Error("rtcBuildBVH returned no tree");
        (write ? t.full : t.split) = ms_since(built);
        t.refs = refs_ms;
        rtcReleaseBVH(bvh);
    }
    std::vector<float> vertices(3 * mesh.positions.size() + 1);
    std::memcpy(vertices.data(), mesh.positions.data(), 3 * sizeof(float) * mesh.positions.size());
    const long faults = minor_faults();
    const auto start = Clock::now();
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, high ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(g, high ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices.data(), 0, 12,
                               mesh.positions.size());
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0, 12, n);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    t.scene = ms_since(start);
    t.scene_faults = double(minor_faults() - faults);
    rtcReleaseScene(scene);
    return t;
}

struct OurTimes {
    double copy = 0, boxes = 0, binary = 0, count = 0, collapse = 0, blocks = 0, whole = 0, whole_faults = 0;
};

/// Our build's steps one after another (as Bvh8's constructor and build_binary run them), then
/// the whole structure end to end.
OurTimes time_ours(const TriangleMesh& mesh, const Bvh8Options& options) {
    OurTimes t;
    auto start = Clock::now();
    const Triangles<> tris(mesh);
    t.copy = ms_since(start);
    start = Clock::now();
    std::vector<Aabb> bounds;
    std::vector<Vec3> centroids;
    primitive_boxes(
        uint32_t(tris.size()), options.binary.threads, bounds, centroids, [&](uint32_t i) { return tris.bounds(i); },
        [&](uint32_t i) { return bounds[i].center(); });
    t.boxes = ms_since(start);
    start = Clock::now();
    const ClipFunction clip = [&tris](uint32_t i, const Aabb& box) { return clipped_bounds(tris, i, box); };
    const BvhData binary = build_bvh({bounds, centroids, clip}, options.binary);
    t.binary = ms_since(start);
    start = Clock::now();
    bvh8::Blocks blocks;
    reserve_huge(blocks, bvh8::block_count(binary, options.merge_below));
    t.count = ms_since(start);
    bvh8::BlockPacking packing{binary.prim_indices.size() > tris.size()};
    double packing_ms = 0;
    start = Clock::now();
    const bvh8::Tree tree = bvh8::collapse(
        binary,
        [&](uint32_t first, uint32_t count) {
            const auto packed = Clock::now();
            const bvh8::LeafPlacement p = bvh8::pack_blocks(blocks, tris, binary.prim_indices.data() + first, count, packing);
            packing_ms += ms_since(packed);
            return p;
        },
        options.merge_below);
    t.collapse = ms_since(start) - packing_ms;
    t.blocks = packing_ms;
    if (tree.nodes.empty()) throw Error("the collapse wrote no node");
    const long faults = minor_faults();
    start = Clock::now();
    { const Bvh8<Triangles<>> whole(Triangles<>(mesh), options); }
    t.whole = ms_since(start);
    t.whole_faults = double(minor_faults() - faults);
    return t;
}

template <class T>
double median(std::vector<T> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : double(v[v.size() / 2]);
}

void usage() {
    std::puts(
        "usage: thicket_build_phases SCENE... [--threads N] [--reps R] [--quality medium|high|low]\n"
        "  Times a bvh8 build phase by phase beside Embree's rtcBuildBVH writing the same 8-wide nodes and\n"
        "  4-triangle blocks from the same triangles, and Embree's scene build. Prints a markdown table of\n"
        "  medians in ms over R rounds (default 5; the first round, first build in the process, is printed\n"
        "  apart). --threads: the build's threads for both libraries (default 2). --quality: bvh8's preset\n"
        "  (low and medium compare with Embree's medium builder, high with Embree's high).");
}

int run(int argc, char** argv) {
    std::vector<std::string> scenes;
    unsigned threads = 2;
    int reps = 5;
    std::string quality = "medium";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw Error(a + " needs a value");
            return argv[++i];
        };
        if (a == "--help" || a == "-h") {
            usage();
            return 0;
        } else if (a == "--threads") {
            threads = unsigned(std::stoul(value()));
        } else if (a == "--reps") {
            reps = std::stoi(value());
        } else if (a == "--quality") {
            quality = value();
            if (quality != "low" && quality != "medium" && quality != "high")
                throw Error("--quality " + quality + ": expected low, medium or high");
        } else if (!a.empty() && a[0] == '-') {
            throw Error("unknown option " + a + " (see --help)");
        } else {
            scenes.push_back(a);
        }
    }
    if (scenes.empty() || reps < 1 || threads < 1) {
        usage();
        return 2;
    }
    Bvh8Options options;
    options.binary.threads = threads;
    if (quality == "low") options.binary.builder = BvhBuilder::Lbvh;
    if (quality == "high") {
        options.binary.builder = BvhBuilder::Sbvh;
        options.binary.optimize = BvhOptimize::Reinsertion;
    }
    const bool high = quality == "high";
    const std::string config = "threads=" + std::to_string(threads);
    RTCDevice device = rtcNewDevice(config.c_str());
    if (!device) throw Error("Embree: cannot create a device");
    {  // start Embree's task system outside the timings
        RTCScene s = rtcNewScene(device);
        rtcCommitScene(s);
        rtcReleaseScene(s);
    }
    std::printf("bvh8 (quality=%s) against Embree %s, %u thread(s), medians of %d rounds (first round in brackets), ms\n\n",
                quality.c_str(), high ? "high" : "medium", threads, reps);
    std::puts("| scene (triangles) | side | boxes / refs | binary build / rtcBuildBVH (split) | block_count | "
              "collapse (nodes) | blocks | emission total | sum | whole structure / Embree scene | its minor faults |");
    std::puts("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (const std::string& path : scenes) {
        const TriangleMesh mesh = load_mesh(path);
        const Triangles<> tris(mesh);
        std::vector<OurTimes> ours;
        std::vector<EmbreeTimes> theirs;
        for (int r = 0; r < reps; ++r) {  // alternating, so drift on a shared machine hits both
            ours.push_back(time_ours(mesh, options));
            theirs.push_back(time_embree(device, mesh, tris, high, threads));
            std::fprintf(stderr, "%s: round %d of %d\n", path.c_str(), r + 1, reps);
        }
        auto med = [](const auto& v, auto field) {
            std::vector<double> x;
            for (const auto& e : v) x.push_back(e.*field);
            return median(x);
        };
        const std::string name = path.substr(path.find_last_of('/') + 1) + " (" + std::to_string(mesh.triangle_count()) + ")";
        const OurTimes& o1 = ours.front();
        const double o_sum = med(ours, &OurTimes::copy) + med(ours, &OurTimes::boxes) + med(ours, &OurTimes::binary) +
                             med(ours, &OurTimes::count) + med(ours, &OurTimes::collapse) + med(ours, &OurTimes::blocks);
        std::printf("| %s | bvh8 | %.1f copy + %.1f boxes | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f [%.1f] | %.0f |\n",
                    name.c_str(), med(ours, &OurTimes::copy), med(ours, &OurTimes::boxes), med(ours, &OurTimes::binary),
                    med(ours, &OurTimes::count), med(ours, &OurTimes::collapse), med(ours, &OurTimes::blocks),
                    med(ours, &OurTimes::count) + med(ours, &OurTimes::collapse) + med(ours, &OurTimes::blocks), o_sum,
                    med(ours, &OurTimes::whole), o1.whole, med(ours, &OurTimes::whole_faults));
        const EmbreeTimes& e1 = theirs.front();
        const double e_refs = med(theirs, &EmbreeTimes::refs), e_split = med(theirs, &EmbreeTimes::split),
                     e_full = med(theirs, &EmbreeTimes::full);
        std::printf("| | rtcBuildBVH | %.1f | %.1f | - | - | - | %.1f | %.1f | %.1f [%.1f] | %.0f |\n", e_refs, e_split,
                    e_full - e_split, e_refs + e_full, med(theirs, &EmbreeTimes::scene), e1.scene, med(theirs, &EmbreeTimes::scene_faults));
        std::fflush(stdout);
    }
    rtcReleaseDevice(device);
    return 0;
}

}  // namespace
}  // namespace thicket

int main(int argc, char** argv) {
    try {
        return thicket::run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "thicket_build_phases: %s\n", e.what());
        return 1;
    }
}
