// The session's dispatch, the request readers, and the answers that need no ray: scene, stats, mesh.
#include "explore_api.h"

#include <cmath>
#include <cstring>

#include "explore_draw.h"
#include "explore_json.h"
#include "thicket/core/error.h"

namespace thicket::explore {

json parse_body(const std::string& body) {
    if (body.size() > kMaxBodyBytes)
        throw RequestError(413, "request body of " + std::to_string(body.size()) + " bytes; at most " +
                                    std::to_string(kMaxBodyBytes));
    json j = json::parse(body, nullptr, false);
    if (j.is_discarded()) throw RequestError(400, "the request body is not JSON");
    if (!j.is_object()) throw RequestError(400, "the request body must be a JSON object");
    return j;
}

uint32_t read_uint(const json& body, const char* key, uint32_t lo, uint32_t hi, bool required, uint32_t fallback) {
    const auto it = body.find(key);
    if (it == body.end()) {
        if (required) throw RequestError(400, std::string("missing field \"") + key + "\"");
        return fallback;
    }
    // Appended piece by piece: gcc 12 warns (-Wrestrict, a false positive) on "[" + std::to_string(...).
    std::string range = "[";
    range += std::to_string(lo);
    range += ", ";
    range += std::to_string(hi);
    range += "]";
    if (!it->is_number_integer() && !it->is_number_unsigned())
        throw RequestError(400, std::string("\"") + key + "\" must be a whole number in " + range + ", not " + it->dump());
    const int64_t v = it->is_number_unsigned() && it->get<uint64_t>() > uint64_t(INT64_MAX) ? INT64_MAX : it->get<int64_t>();
    if (v < int64_t(lo) || v > int64_t(hi))
        throw RequestError(400, std::string("\"") + key + "\" = " + it->dump() + " is out of range " + range);
    return uint32_t(v);
}

Vec3 read_vec3(const json& body, const char* key) {
    const auto it = body.find(key);
    if (it == body.end()) throw RequestError(400, std::string("missing field \"") + key + "\"");
    if (!it->is_array() || it->size() != 3)
        throw RequestError(400, std::string("\"") + key + "\" must be an array of 3 numbers");
    Vec3 v;
    for (int a = 0; a < 3; ++a) {
        const json& c = (*it)[size_t(a)];
        if (!c.is_number() || !std::isfinite(c.get<double>()) || std::fabs(c.get<double>()) > 1e30)
            throw RequestError(400, std::string("\"") + key + "\" must hold 3 finite numbers (at most 1e30 in size), not " +
                                        it->dump());
        v[a] = c.get<float>();
    }
    return v;
}

View read_view(const json& body) {
    const auto cam = body.find("camera");
    if (cam == body.end() || !cam->is_object()) throw RequestError(400, "missing object \"camera\" {eye, target, up, fov}");
    View v;
    v.eye = read_vec3(*cam, "eye");
    v.target = read_vec3(*cam, "target");
    if (cam->contains("up")) v.up = read_vec3(*cam, "up");
    v.fov_deg = float(read_uint(*cam, "fov", 1, 179, false, 45));
    v.width = read_uint(body, "width", 1, kMaxImageSide, true);
    v.height = read_uint(body, "height", 1, kMaxImageSide, true);
    const Vec3 forward = v.target - v.eye;
    if (length(forward) == 0.0f || !std::isfinite(length(forward)))
        throw RequestError(400, "camera: \"eye\" and \"target\" must be distinct points");
    if (length(cross(forward, v.up)) <= 1e-6f * length(forward) * length(v.up))
        throw RequestError(400, "camera: \"up\" must not be zero or parallel to target - eye");
    return v;
}

size_t read_structure(const json& body, const std::vector<std::string>& specs) {
    const auto it = body.find("structure");
    if (it == body.end()) return 0;
    std::string have;
    for (size_t i = 0; i < specs.size(); ++i) have += (i ? ", " : "") + std::to_string(i) + " (" + specs[i] + ")";
    if (it->is_number_integer() || it->is_number_unsigned()) {
        if (it->is_number_unsigned() || it->get<int64_t>() >= 0)
            if (it->get<uint64_t>() < specs.size()) return size_t(it->get<uint64_t>());
    } else if (it->is_string()) {
        for (size_t i = 0; i < specs.size(); ++i)
            if (specs[i] == it->get<std::string>()) return i;
    }
    throw RequestError(404, "unknown structure " + it->dump() + "; this server has " + have);
}

Response error_response(int status, const std::string& message) {
    return {status, json{{"error", message}}.dump()};
}

Response json_response(const json& j) { return {200, j.dump()}; }

json box_json(const Aabb& b) { return json::array({b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}); }

Session::Session(Scene scene, std::vector<std::unique_ptr<Accel>> accels, unsigned threads)
    : scene_(std::move(scene)), accels_(std::move(accels)), threads_(threads) {
    if (accels_.empty()) throw Error("explore: no structure to serve");
}

Response Session::handle(const std::string& method, const std::string& path, const std::string& body) const {
    try {
        struct Route {
            const char* path;
            const char* method;
        };
        static constexpr Route kRoutes[] = {{"/api/scene", "GET"},    {"/api/stats", "GET"},   {"/api/mesh", "GET"},
                                            {"/api/nodes", "POST"},   {"/api/heatmap", "POST"}, {"/api/trace", "POST"}};
        for (const Route& r : kRoutes) {
            if (path != r.path) continue;
            if (method != r.method) return error_response(405, path + " takes " + r.method + ", not " + method);
            if (path == "/api/scene") return scene_info();
            if (path == "/api/stats") return stats();
            if (path == "/api/mesh") return mesh();
            if (path == "/api/nodes") return nodes(body);
            if (path == "/api/heatmap") return heatmap(body);
            return trace(body);
        }
        return error_response(404, "no such request: " + method + " " + path.substr(0, 200));
    } catch (const RequestError& e) {
        return error_response(e.status, e.what());
    } catch (const std::exception& e) {
        return error_response(500, std::string("internal error: ") + e.what());
    }
}

Response Session::scene_info() const {
    const size_t triangles = scene_.mesh.triangle_count();
    const size_t stride = triangles > kMaxDisplayTriangles ? (triangles + kMaxDisplayTriangles - 1) / kMaxDisplayTriangles : 1;
    json structures = json::array();
    for (const auto& a : accels_) {
        structures.push_back({{"spec", a->spec()}, {"draws_nodes", draws_itself(*a)}});
    }
    const Aabb b = scene_.bounds();
    return json_response({{"name", scene_.name},
                          {"triangles", triangles},
                          {"shapes", scene_.shapes.size()},
                          {"bounds", b.empty() ? json(nullptr) : box_json(b)},
                          {"display", {{"limit", kMaxDisplayTriangles}, {"stride", stride},
                                       {"triangles", (triangles + stride - 1) / stride}}},
                          {"limits", {{"max_image_side", kMaxImageSide}, {"max_image_pixels", kMaxImagePixels},
                                      {"max_drawn", kMaxBoxes}, {"max_steps", kMaxSteps}}},
                          {"structures", structures}});
}

Response Session::stats() const {
    json out = json::array();
    for (const auto& a : accels_) {
        const AccelStats s = a->stats();
        json extra = json::object();
        for (const auto& [k, v] : s.extra) extra[k] = v;
        out.push_back({{"spec", a->spec()},
                       {"primitives", s.primitives},
                       {"nodes", s.nodes},
                       {"leaves", s.leaves},
                       {"max_depth", s.max_depth},
                       {"bytes", s.bytes},
                       {"primitive_bytes", s.primitive_bytes},
                       {"sah_cost", s.sah_cost > 0 ? json(s.sah_cost) : json(nullptr)},
                       {"build_ms", a->build_ms()},
                       {"extra", extra}});
    }
    return json_response({{"structures", out}});
}

/// The displayed triangles' corners as little-endian float32, 9 per triangle (every k-th
/// triangle above kMaxDisplayTriangles: /api/scene's display.stride).
Response Session::mesh() const {
    const TriangleMesh& m = scene_.mesh;
    const size_t n = m.triangle_count();
    const size_t stride = n > kMaxDisplayTriangles ? (n + kMaxDisplayTriangles - 1) / kMaxDisplayTriangles : 1;
    std::string bytes;
    bytes.reserve(((n + stride - 1) / stride) * 9 * sizeof(float));
    for (size_t t = 0; t < n; t += stride)
        for (int c = 0; c < 3; ++c) {
            const Vec3 p = m.vertex(t, c);
            const float xyz[3] = {p.x, p.y, p.z};
            bytes.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
        }
    return {200, std::move(bytes), "application/octet-stream"};
}

}  // namespace thicket::explore
