#include "thicket/render/camera.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <limits>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/render/sampling.h"  // kPi

namespace thicket {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

/// v / |v| without overflow: |v| squares the components, which passes float's range once one
/// exceeds 1.8e19 (a target at 1e20 gave a zero forward vector and NaN rays), so v is first
/// divided by its largest component.
Vec3 unit(Vec3 v) {
    const float m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    return m > 0.0f ? normalize(v / m) : v;
}

std::string vec_text(Vec3 v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%g, %g, %g)", double(v.x), double(v.y), double(v.z));
    return buf;
}

}  // namespace

Camera::Camera(Vec3 position, Vec3 target, Vec3 up, float fov_degrees)
    : position_(position), target_(target), fov_(fov_degrees) {
    if (!is_finite(position) || !is_finite(target) || !is_finite(up))
        throw Error("camera: position, target and up must be finite numbers");
    if (!(fov_degrees > 0.0f && fov_degrees < 180.0f))
        throw Error("camera: field of view " + std::to_string(fov_degrees) + " is not in (0, 180) degrees");
    const Vec3 view = target - position;
    if (view == Vec3{0.0f}) throw Error("camera: position and target are the same point");
    if (!is_finite(view))
        throw Error("camera: from " + vec_text(position) + " to " + vec_text(target) +
                    " the view direction passes float's range (3.4e38): bring the target closer");
    forward_ = unit(view);
    // Looking straight up or down leaves `up` undefined; fall back to the axis pointing "away".
    const Vec3 candidates[] = {up, forward_.y <= 0.0f ? Vec3{0, 0, -1} : Vec3{0, 0, 1}, Vec3{0, 1, 0}};
    for (const Vec3& c : candidates) {
        const Vec3 r = cross(forward_, unit(c));  // unit: a huge `up` must not overflow either
        if (length(r) > 1e-6f) {
            right_ = unit(r);
            break;
        }
    }
    up_ = cross(right_, forward_);
    if (!is_finite(forward_) || !is_finite(right_) || !is_finite(up_) || right_ == Vec3{0.0f})
        throw Error("camera: no view frame from " + vec_text(position) + " toward " + vec_text(target));
    tan_half_ = std::tan(0.5f * fov_ * kPi / 180.0f);
}

Ray Camera::generate(float px, float py, int width, int height) const {
    const float aspect = float(width) / float(height);
    const float sx = (2.0f * px / float(width) - 1.0f) * aspect * tan_half_;
    const float sy = (1.0f - 2.0f * py / float(height)) * tan_half_;
    Ray ray;
    ray.org = position_;
    ray.dir = normalize(forward_ + right_ * sx + up_ * sy);
    ray.tmin = 0.0f;
    ray.tmax = kInfinity;
    return ray;
}

bool Camera::project(Vec3 p, int width, int height, float& px, float& py) const {
    const Vec3 d = p - position_;
    const float z = dot(d, forward_);
    if (!(z > 0.0f)) return false;
    const float aspect = float(width) / float(height);
    const float sx = dot(d, right_) / z, sy = dot(d, up_) / z;
    px = (sx / (aspect * tan_half_) + 1.0f) * 0.5f * float(width);
    py = (1.0f - sy / tan_half_) * 0.5f * float(height);
    return true;
}

Camera auto_camera(const Aabb& bounds, float aspect) {
    if (!(aspect > 0.0f) || !std::isfinite(aspect)) throw Error("auto_camera: aspect ratio must be positive");
    constexpr float kElevation = 10.0f * kPi / 180.0f;
    const Vec3 toward_camera{0.0f, std::sin(kElevation), std::cos(kElevation)};
    if (bounds.empty() || !is_finite(bounds.min) || !is_finite(bounds.max)) return Camera(toward_camera, Vec3{0.0f});

    const Vec3 centre = bounds.center();
    // The frame is fixed by the direction alone, so build a unit-distance camera to read it.
    const Camera probe(centre + toward_camera, centre);
    const float tan_v = std::tan(0.5f * kDefaultFovDegrees * kPi / 180.0f);
    const float tan_h = tan_v * aspect;
    float needed = 0.0f;
    for (int i = 0; i < 8; ++i) {
        const Vec3 corner{(i & 1) ? bounds.max.x : bounds.min.x, (i & 2) ? bounds.max.y : bounds.min.y,
                          (i & 4) ? bounds.max.z : bounds.min.z};
        const Vec3 q = corner - centre;
        // A corner is inside the image when |x| <= tan_h * depth and |y| <= tan_v * depth, with
        // depth = distance - dot(q, toward_camera): solve for the distance.
        const float base = dot(q, toward_camera);
        needed = std::max(needed, base + std::fabs(dot(q, probe.right())) / tan_h);
        needed = std::max(needed, base + std::fabs(dot(q, probe.up())) / tan_v);
    }
    const float scale = std::max(1.0f, length(centre));
    const float distance = needed > 1e-6f * scale ? 1.05f * needed : 1.0f;
    const Vec3 position = centre + toward_camera * distance;
    if (!is_finite(position) || !std::isfinite(distance))
        throw Error("automatic camera: the scene's bounds (extent up to " + std::to_string(std::max({bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y, bounds.max.z - bounds.min.z})) +
                    ") are too large to frame in float coordinates; give --camera");
    return Camera(position, centre);
}

Camera parse_camera(std::string_view text) {
    const std::string quoted = "--camera '" + std::string(text) + "'";
    std::vector<float> values;
    size_t start = 0;
    while (true) {
        const size_t comma = text.find(',', start);
        const std::string_view field = trim(text.substr(start, comma == std::string_view::npos ? text.npos : comma - start));
        // Read as double, so that 1e39 is reported as out of float's range, not as "not a number".
        double v = 0.0;
        const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
        const std::string which = "component " + std::to_string(values.size() + 1) + " ('" + std::string(field.substr(0, 40)) + "')";
        if (field.empty() || end != field.data() + field.size() ||
            (ec != std::errc() && ec != std::errc::result_out_of_range))
            throw Error(quoted + ": " + which + " is not a number; expected px,py,pz,tx,ty,tz[,fov]");
        if (std::isnan(v)) throw Error(quoted + ": " + which + " is not finite (NaN)");
        if (ec == std::errc::result_out_of_range || !(std::fabs(v) <= double(std::numeric_limits<float>::max())))
            throw Error(quoted + ": " + which + " is outside the range of float coordinates (magnitude at most 3.4e38)");
        values.push_back(float(v));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    if (values.size() != 6 && values.size() != 7)
        throw Error(quoted + ": expected 6 or 7 comma-separated numbers px,py,pz,tx,ty,tz[,fov], got " +
                    std::to_string(values.size()));
    const Vec3 position{values[0], values[1], values[2]}, target{values[3], values[4], values[5]};
    const float fov = values.size() == 7 ? values[6] : kDefaultFovDegrees;
    if (!(fov > 0.0f && fov < 180.0f)) throw Error(quoted + ": fov must be in (0, 180) degrees");
    if (position == target) throw Error(quoted + ": position and target are the same point");
    return Camera(position, target, {0, 1, 0}, fov);
}

}  // namespace thicket
