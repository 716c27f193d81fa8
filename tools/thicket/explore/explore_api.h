#pragma once
// `thicket explore`'s JSON side: one scene and its structures, built once, answering the page's
// requests (docs/explore.md lists them). No HTTP here: explore_server.h carries requests to
// Session::handle, and the unit tests call it directly.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/scene/scene.h"

namespace thicket::explore {

/// Bounds on what one request may ask; beyond them the answer is a 4xx with the reason.
inline constexpr size_t kMaxBodyBytes = 64 * 1024;        ///< request body (413 above)
inline constexpr uint32_t kMaxImageSide = 1024;          ///< heatmap/trace image width or height
inline constexpr uint64_t kMaxImagePixels = 512 * 512;   ///< heatmap pixels per structure
inline constexpr uint32_t kMaxDepth = 1000;              ///< the depth a node request may name
inline constexpr size_t kMaxBoxes = 50000;               ///< elements drawn in one node answer (every k-th above)
inline constexpr size_t kMaxSteps = 20000;               ///< recorded steps of one ray (the rest counted)
/// Triangles sent for display: above it every k-th triangle is sent, k = ceil(triangles / limit).
inline constexpr size_t kMaxDisplayTriangles = 200000;

/// An answer: HTTP status, body and its content type.
struct Response {
    int status = 200;
    std::string body;
    std::string content_type = "application/json";
};

/// A pinhole camera as the page sends it: eye, target, up, vertical field of view in degrees,
/// and the image it is cut into.
struct View {
    Vec3 eye, target, up{0.0f, 1.0f, 0.0f};
    float fov_deg = 45.0f;
    uint32_t width = 1, height = 1;

    /// The ray through the centre of pixel (x, y), row 0 at the top; x < width, y < height.
    Ray pixel_ray(uint32_t x, uint32_t y) const;
};

/// One ray's traversal through `accel` as JSON text: the ray, the query, the totals, the hit (or
/// null), and the steps with each node's box or tetrahedron (`thicket explain` prints it, the
/// page's trace request returns it). `any_hit`: the shadow query, which stops at the first hit
/// and says `occluded` (no hit record: it finds one, not the closest).
std::string explain_ray(const Accel& accel, const Scene& scene, const Ray& ray, bool any_hit = false);

class Session {
public:
    /// Takes the scene and the structures built over it (at least one); a heatmap is traced on
    /// up to `threads` threads (0: every core).
    Session(Scene scene, std::vector<std::unique_ptr<Accel>> accels, unsigned threads = 0);

    /// Answers one request. Never throws: a bad request gets a 4xx and {"error": "..."} naming
    /// the field or value; an unexpected failure a 500. Safe to call from several threads.
    Response handle(const std::string& method, const std::string& path, const std::string& body) const;

    const Scene& scene() const { return scene_; }
    size_t structures() const { return accels_.size(); }

private:
    Response scene_info() const;
    Response stats() const;
    Response mesh() const;
    Response nodes(const std::string& body) const;
    Response heatmap(const std::string& body) const;
    Response trace(const std::string& body) const;

    Scene scene_;
    std::vector<std::unique_ptr<Accel>> accels_;
    unsigned threads_ = 0;
};

}  // namespace thicket::explore
