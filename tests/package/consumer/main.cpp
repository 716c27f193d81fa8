// Casts one ray into the built-in Cornell box through the installed public API; exits 0 only if
// it hits the back wall and the direct (non-virtual) BVH class agrees.
#include <thicket/thicket.h>

#include <cstdio>

int main() {
    const thicket::Scene scene = thicket::load_scene("cornell");
    auto accel = thicket::build_accel("bvh", scene);
    const thicket::Ray ray{{0.0f, 1.5f, 3.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, thicket::kInfinity};
    const thicket::Hit hit = accel->intersect(ray);
    thicket::Bvh<thicket::Triangles<>> direct(thicket::Triangles<>(scene.mesh), thicket::BvhBuildOptions{});
    thicket::NoCounters none;
    const thicket::Hit same = direct.closest(ray, none);
    std::printf("hit prim %u at t=%g\n", hit.prim, hit.t);
    return hit.found() && same.prim == hit.prim && hit.t > 3.9f && hit.t < 4.1f ? 0 : 1;
}
