// The answers that look at the structures: their nodes by depth, a heatmap of work per pixel, and
// one ray's recorded traversal (shared with `thicket explain`).
#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "explore_api.h"
#include "explore_draw.h"
#include "explore_json.h"
#include "thicket/util/parallel.h"

namespace thicket::explore {

Ray View::pixel_ray(uint32_t x, uint32_t y) const {
    const Vec3 forward = normalize(target - eye);
    const Vec3 right = normalize(cross(forward, up));
    const Vec3 true_up = cross(right, forward);
    const float half_h = std::tan(fov_deg * 0.5f * 3.14159265358979f / 180.0f);
    const float half_w = half_h * float(width) / float(height);
    const float sx = (2.0f * (float(x) + 0.5f) / float(width) - 1.0f) * half_w;
    const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height)) * half_h;
    Ray r;
    r.org = eye;
    r.dir = normalize(forward + right * sx + true_up * sy);
    return r;
}

namespace {

json vec_json(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

const char* kind_name(TraversalStep::Kind k) {
    switch (k) {
    case TraversalStep::Kind::Enter: return "enter";
    case TraversalStep::Kind::Cull: return "cull";
    case TraversalStep::Kind::Prim: return "prim";
    case TraversalStep::Kind::Skip: return "skip";
    }
    return "?";
}

/// The traversal of `ray` (closest hit, or any hit) as JSON: what explain_ray prints and the
/// trace request returns.
json traversal_json(const Accel& accel, const Scene& scene, const Ray& ray, bool any_hit) {
    TraversalRecorder rec;
    rec.limit = kMaxSteps;
    Hit hit;
    bool blocked = false;
    if (any_hit)
        blocked = accel.occluded(ray, rec);
    else
        hit = accel.intersect(ray, rec);
    // A structure that reports only some of its steps (grid2's cells share the grid's primitive
    // tests but not its walk) would give a list that looks whole and is not: totals only.
    if (!rec.detailed) {
        rec.steps.clear();
        rec.dropped = 0;
    }
    // The nodes the steps name as the structure draws them, found in one pass over its nodes.
    std::unordered_map<uint32_t, DrawnNode> drawn;
    for (const TraversalStep& s : rec.steps)
        if (s.kind != TraversalStep::Kind::Prim) drawn.emplace(s.id, DrawnNode{});
    if (!drawn.empty())
        accel.for_each_node([&](const DrawnNode& n) {
            const auto it = drawn.find(n.id);
            if (it != drawn.end()) it->second = n;
        });
    json steps = json::array();
    for (const TraversalStep& s : rec.steps) {
        json j = {{"kind", kind_name(s.kind)}, {"id", s.id}, {"t", std::isfinite(s.t) ? json(s.t) : json(nullptr)}};
        if (s.kind != TraversalStep::Kind::Prim) {
            const DrawnNode& n = drawn[s.id];
            if (!n.box.empty()) j["box"] = box_json(n.box);
            // A tetrahedral walk names tetrahedra: their corners, for the page to draw the walk.
            if (n.shape == DrawnNode::Shape::Tetra) {
                json corners = json::array();
                for (const Vec3& p : n.points) corners.push_back(vec_json(p));
                j["tetrahedron"] = std::move(corners);
            }
        } else if (s.id < scene.primitive_count()) {
            const PrimRef ref = scene.locate(s.id);
            if (!ref.shape)
                j["triangle"] = json::array({vec_json(scene.mesh.vertex(ref.index, 0)),
                                             vec_json(scene.mesh.vertex(ref.index, 1)),
                                             vec_json(scene.mesh.vertex(ref.index, 2))});
        }
        steps.push_back(std::move(j));
    }
    json hit_json = nullptr;
    if (hit.found())
        hit_json = {{"t", hit.t}, {"prim", hit.prim}, {"u", hit.u}, {"v", hit.v},
                    {"point", vec_json(ray.org + ray.dir * hit.t)}};
    json out = {{"structure", accel.spec()},
            {"query", any_hit ? "any" : "closest"},
            {"ray", {{"org", vec_json(ray.org)}, {"dir", vec_json(ray.dir)}, {"tmin", ray.tmin},
                     {"tmax", std::isfinite(ray.tmax) ? json(ray.tmax) : json(nullptr)}}},
            {"detailed", rec.detailed},
            {"nodes", rec.nodes},
            {"prims", rec.prims},
            {"dropped", rec.dropped},
            {"hit", hit_json},
            {"steps", steps}};
    if (any_hit) out["occluded"] = blocked;
    return out;
}

std::vector<std::string> specs_of(const std::vector<std::unique_ptr<Accel>>& accels) {
    std::vector<std::string> s;
    for (const auto& a : accels) s.push_back(a->spec());
    return s;
}

}  // namespace

std::string explain_ray(const Accel& accel, const Scene& scene, const Ray& ray, bool any_hit) {
    return traversal_json(accel, scene, ray, any_hit).dump(1);
}

Response Session::nodes(const std::string& body) const {
    const json req = parse_body(body);
    const Accel& a = *accels_[read_structure(req, specs_of(accels_))];
    const uint32_t depth = read_uint(req, "depth", 0, kMaxDepth, false, 0);
    const std::optional<Drawing> d = draw_structure(a, depth);
    if (!d) throw RequestError(422, a.spec() + " does not draw its nodes (docs/explore.md lists what each structure draws)");
    // Above the limit every k-th element is sent, so the picture still spans the whole level.
    const size_t count = d->elements.size();
    const size_t stride = count > kMaxBoxes ? (count + kMaxBoxes - 1) / kMaxBoxes : 1;
    json boxes = json::array(), planes = json::array(), oriented = json::array(), tetrahedra = json::array();
    size_t drawn = 0;
    for (size_t i = 0; i < count; i += stride, ++drawn) {
        const DrawnNode& e = d->elements[i];
        json points = json::array();
        for (const Vec3& p : e.points) points.push_back(vec_json(p));
        switch (e.shape) {
        case DrawnNode::Shape::Box:
            boxes.push_back({{"id", e.id}, {"box", box_json(e.box)}, {"leaf", e.leaf}, {"prims", e.prims}});
            break;
        case DrawnNode::Shape::Plane: {
            json j = {{"id", e.id}, {"polygon", points}};
            if (!e.box.empty()) j["cell"] = box_json(e.box);
            planes.push_back(std::move(j));
            break;
        }
        case DrawnNode::Shape::Oriented:
            oriented.push_back({{"id", e.id}, {"center", points[0]}, {"axes", {points[1], points[2], points[3]}},
                                {"leaf", e.leaf}, {"prims", e.prims}});
            break;
        case DrawnNode::Shape::Tetra:
            tetrahedra.push_back({{"id", e.id}, {"corners", points}});
            break;
        }
    }
    return json_response({{"structure", a.spec()}, {"depth", depth}, {"max_depth", d->max_depth},
                          {"drawing", d->legend.kind}, {"depth_means", d->legend.depth_means}, {"count", count}, {"drawn", drawn},
                          {"stride", stride}, {"truncated", stride > 1}, {"limit", kMaxBoxes}, {"boxes", boxes},
                          {"planes", planes}, {"oriented", oriented}, {"tetrahedra", tetrahedra}});
}

Response Session::heatmap(const std::string& body) const {
    const json req = parse_body(body);
    const View view = read_view(req);
    const uint64_t pixels = uint64_t(view.width) * view.height;
    if (pixels > kMaxImagePixels)
        throw RequestError(400, "heatmap of " + std::to_string(view.width) + "x" + std::to_string(view.height) +
                                    " pixels; at most " + std::to_string(kMaxImagePixels));
    std::string metric = "nodes";
    if (req.contains("metric")) {
        if (!req["metric"].is_string() || (req["metric"] != "nodes" && req["metric"] != "prims"))
            throw RequestError(400, "\"metric\" must be \"nodes\" or \"prims\", not " + req["metric"].dump());
        metric = req["metric"].get<std::string>();
    }
    std::vector<size_t> which{0};
    if (req.contains("structures")) {
        const json& s = req["structures"];
        if (!s.is_array() || s.empty() || s.size() > 2)
            throw RequestError(400, "\"structures\" must list 1 or 2 structures (indices or specs)");
        which.clear();
        for (const json& e : s) which.push_back(read_structure(json{{"structure", e}}, specs_of(accels_)));
    }
    const bool prims = metric == "prims";
    json maps = json::array();
    uint64_t shared_max = 0;
    for (size_t w : which) {
        const Accel& a = *accels_[w];
        std::vector<uint64_t> work(pixels);
        parallel_for(view.height, 8, threads_, [&](size_t y0, size_t y1) {
            for (size_t y = y0; y < y1; ++y)
                for (uint32_t x = 0; x < view.width; ++x) {
                    RayCounters c;
                    a.intersect(view.pixel_ray(x, uint32_t(y)), c);
                    work[y * view.width + x] = prims ? c.prims : c.nodes;
                }
        });
        const size_t hottest = size_t(std::max_element(work.begin(), work.end()) - work.begin());
        uint64_t total = 0;
        for (uint64_t v : work) total += v;
        shared_max = std::max(shared_max, work[hottest]);
        maps.push_back({{"structure", a.spec()},
                        {"values", work},
                        {"max", work[hottest]},
                        {"hottest", {hottest % view.width, hottest / view.width}},
                        {"total", total}});
    }
    return json_response({{"width", view.width}, {"height", view.height}, {"metric", metric}, {"max", shared_max},
                          {"maps", maps}});
}

Response Session::trace(const std::string& body) const {
    const json req = parse_body(body);
    const Accel& a = *accels_[read_structure(req, specs_of(accels_))];
    const View view = read_view(req);
    const uint32_t x = read_uint(req, "x", 0, view.width - 1, true);
    const uint32_t y = read_uint(req, "y", 0, view.height - 1, true);
    json j = traversal_json(a, scene_, view.pixel_ray(x, y), false);
    j["pixel"] = {x, y};
    return json_response(j);
}

}  // namespace thicket::explore
