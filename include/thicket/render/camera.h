#pragma once
/// Pinhole camera for the preview renderer. Image coordinates: (0, 0) is the top-left corner of
/// the image, (width, height) the bottom-right one; pixel (i, j) covers [i, i+1) x [j, j+1).
#include <string_view>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

namespace thicket {

inline constexpr float kDefaultFovDegrees = 45.0f;

class Camera {
public:
    /// A camera at `position` looking at `target`, with `up` hinting the image's upward direction
    /// and `fov_degrees` the vertical field of view, in (0, 180). When `up` is (nearly) parallel
    /// to the view direction, -z is up when looking down, +z when looking up (else +y).
    /// Throws Error on a non-finite input, position == target or a fov out of range.
    Camera(Vec3 position, Vec3 target, Vec3 up = {0, 1, 0}, float fov_degrees = kDefaultFovDegrees);

    /// Ray from the camera through image point (px, py) of a width x height image (pass i + 0.5,
    /// j + 0.5 for pixel centres). dir is unit length, so hit t is a distance; tmin 0, tmax inf.
    Ray generate(float px, float py, int width, int height) const;
    /// Inverse of generate(): the image point that `p` projects to. Returns false (and leaves
    /// px, py unset) when p is not in front of the camera.
    bool project(Vec3 p, int width, int height, float& px, float& py) const;

    Vec3 position() const { return position_; }
    Vec3 target() const { return target_; }
    float fov_degrees() const { return fov_; }
    Vec3 forward() const { return forward_; }
    Vec3 right() const { return right_; }
    Vec3 up() const { return up_; }

private:
    Vec3 position_, target_;
    float fov_;
    Vec3 forward_, right_, up_;  // orthonormal view frame
    float tan_half_;             // tan(fov / 2)
};

/// A camera that frames `bounds` in an image of width/height ratio `aspect`. Rule: it looks at
/// the box centre from the +z side, raised 10 degrees above the horizontal plane (direction
/// (0, sin 10, cos 10) from the centre), vertical fov 45 degrees, at the smallest distance at
/// which all eight corners of the box project inside the image, plus 5% of that distance as a
/// margin. An empty or point-sized box gets a camera one unit away from its centre (or origin).
Camera auto_camera(const Aabb& bounds, float aspect);

/// Parses a --camera value "px,py,pz,tx,ty,tz[,fov]" (position, target, optional vertical fov in
/// degrees, default 45); up is +y. Throws Error quoting the text and saying what is wrong.
Camera parse_camera(std::string_view text);

}  // namespace thicket
