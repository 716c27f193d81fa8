#include "pictures.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "arrays.h"
#include "inputs.h"
#include "scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bench/ray_sets.h"
#include "thicket/core/error.h"
#include "thicket/render/film.h"
#include "thicket/render/image.h"
#include "thicket/render/integrator.h"
#include "thicket/render/lights.h"
#include "thicket/render/render_json.h"
#include "thicket/render/render_scene.h"
#include "thicket/render/view_buffers.h"
#include "thicket/render/views.h"

namespace thicket::python {

namespace {

using namespace py::literals;

/// The Python package's default structure (thicket.build's), for path_trace given a Scene.

std::string type_name(const py::handle& v) { return py::str(py::type::of(v).attr("__name__")); }

/// A point or direction: any sequence of three finite real numbers (a tuple, a list, a numpy
/// array of any real dtype).
Vec3 vec3_argument(const py::handle& value, const char* what) {
    if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr()))
        throw py::type_error(std::string(what) + " must be three numbers (x, y, z), got " + type_name(value));
    py::array a;
    try {
        a = py::module_::import("numpy").attr("asarray")(value, "dtype"_a = "float64");
    } catch (const py::error_already_set&) {
        throw py::type_error(std::string(what) + " must be three numbers (x, y, z), got " + type_name(value));
    }
    if (a.ndim() != 1 || a.shape(0) != 3)
        throw py::value_error(std::string(what) + " must be three numbers (x, y, z), got shape " + shape_text(a));
    const double* d = static_cast<const double*>(a.data());
    double v[3];
    for (int i = 0; i < 3; ++i) v[i] = d[i * a.strides(0) / py::ssize_t(sizeof(double))];
    for (double c : v)
        if (!std::isfinite(c) || std::fabs(c) > double(std::numeric_limits<float>::max()))
            throw py::value_error(std::string(what) + " must be finite numbers within float's range, got (" +
                                  std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) + ")");
    return Vec3{float(v[0]), float(v[1]), float(v[2])};
}

/// The camera of eye/center/up/vfov_deg (Open3D's names): both eye and center, or neither (the
/// automatic camera, which up and vfov_deg cannot shape).
std::optional<Camera> camera_argument(const py::handle& eye, const py::handle& center, const py::handle& up,
                                      const py::handle& vfov_deg) {
    if (eye.is_none() != center.is_none())
        throw py::value_error("eye and center go together: give both (where the camera stands and the point it looks "
                              "at), or neither for the automatic camera");
    if (eye.is_none()) {
        if (!up.is_none() || !vfov_deg.is_none())
            throw py::value_error(std::string(up.is_none() ? "vfov_deg" : "up") +
                                  " shapes a camera given by eye and center; without them the camera is automatic "
                                  "(as the CLI's without --camera)");
        return std::nullopt;
    }
    const Vec3 e = vec3_argument(eye, "eye"), c = vec3_argument(center, "center");
    const Vec3 u = up.is_none() ? Vec3{0, 1, 0} : vec3_argument(up, "up");
    const float fov = vfov_deg.is_none() ? kDefaultFovDegrees : *float_argument(vfov_deg, "vfov_deg");
    if (!(fov > 0.0f && fov < 180.0f))
        throw py::value_error("vfov_deg must be a vertical field of view in degrees, between 0 and 180 (exclusive), got " +
                              std::to_string(fov));
    if (e == c) throw py::value_error("eye and center are the same point: the camera has no direction to look in");
    if (u == Vec3{}) throw py::value_error("up is (0, 0, 0): give the direction that is up in the image");
    return Camera(e, c, u, fov);
}

int side_argument(const py::handle& v, const char* what, int max) {
    return int(int_argument(v, what, 1, max, ("a pixel count from 1 to " + std::to_string(max)).c_str()));
}

/// `value` as an unsigned 64-bit integer (a seed): a ValueError beyond [0, 2^64 - 1].
uint64_t u64_argument(const py::handle& value, const char* what) {
    if (!PyIndex_Check(value.ptr())) throw py::type_error(std::string(what) + " must be an integer, got " + type_name(value));
    const py::int_ number = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
    if (!number) throw py::error_already_set();
    const unsigned long long v = PyLong_AsUnsignedLongLong(number.ptr());
    if (v == static_cast<unsigned long long>(-1) && PyErr_Occurred()) {
        PyErr_Clear();
        throw py::value_error(std::string(what) + " must be an integer from 0 to 2^64 - 1, got " +
                              std::string(py::str(py::handle(number))));
    }
    return v;
}

/// Runs `f` turning thicket::Error into ValueError: for parsing an argument's value, where the
/// library's message (naming the value and the choices) is about the argument.
template <class F>
auto as_value_error(F&& f) {
    try {
        return f();
    } catch (const FileError&) {
        throw;
    } catch (const Error& e) {
        throw py::value_error(e.what());
    }
}

py::tuple vec_tuple(Vec3 v) { return py::make_tuple(v.x, v.y, v.z); }

/// A float32 array of `count` values of `T` (a Vec3 is 3 floats) with shape `shape`.
template <class T>
py::array_t<float> float_array(const std::vector<T>& values, std::initializer_list<py::ssize_t> shape) {
    py::array_t<float> a{std::vector<py::ssize_t>(shape)};
    static_assert(sizeof(Vec3) == 3 * sizeof(float));
    std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(T));
    return a;
}

py::dict ray_set_dict(const std::shared_ptr<Scene>& scene, const std::string& set_name, int width, int height,
                      const std::optional<Camera>& camera, unsigned threads) {
    check_no_nul(set_name, "set");
    const std::vector<std::string> names = as_value_error([&] { return parse_ray_set_list(set_name); });
    if (names.size() != 1) throw py::value_error("set takes one set name, got '" + set_name + "'");
    RaySetOptions options;
    options.width = width;
    options.height = height;
    options.camera = camera;
    check_allocation(ray_set_bytes(options), "rays: the ray sets of a " + std::to_string(width) + "x" +
                                                 std::to_string(height) + " image");
    std::optional<RaySetView> view;
    std::vector<RaySet> sets;
    {
        py::gil_scoped_release nogil;
        const std::unique_ptr<Accel> hits_from = build_accel(kRaySetHitSpec, *scene);
        view = ray_set_view(*scene, *hits_from, options);
        sets = generate_ray_sets(*scene, *hits_from, *view, names, options, threads);
    }
    const RaySet& set = sets.front();
    const py::ssize_t n = py::ssize_t(set.rays.size());
    py::array_t<float> rays({n, py::ssize_t(6)}), tmin(n), tmax(n);
    float* r = rays.mutable_data();
    for (size_t i = 0; i < set.rays.size(); ++i) {
        const Ray& ray = set.rays[i];
        const float row[6] = {ray.org.x, ray.org.y, ray.org.z, ray.dir.x, ray.dir.y, ray.dir.z};
        std::memcpy(r + 6 * i, row, sizeof row);
        tmin.mutable_data()[i] = ray.tmin;
        tmax.mutable_data()[i] = ray.tmax;
    }
    py::dict out("rays"_a = rays, "tmin"_a = tmin, "tmax"_a = tmax, "set"_a = set.name, "any_hit"_a = set.any_hit,
                 "width"_a = width, "height"_a = height, "eye"_a = vec_tuple(view->camera.position()),
                 "center"_a = vec_tuple(view->camera.target()), "vfov_deg"_a = view->camera.fov_degrees(),
                 "light"_a = vec_tuple(view->light), "interior"_a = view->interior);
    // The pixel each ray belongs to: a primary ray's own (rows in pixel order), a secondary ray's
    // primary hit; random rays have none.
    if (set.name == "primary" || !set.source.empty()) {
        py::array_t<uint32_t> pixel(n);
        for (size_t i = 0; i < set.rays.size(); ++i)
            pixel.mutable_data()[i] = set.source.empty() ? uint32_t(i) : set.source[i];
        out["pixel"] = pixel;
    }
    return out;
}

py::array render_array(const AccelHandle& h, const std::string& view_name_text, int width, int height,
                       const std::optional<Camera>& given, const py::handle& counter_arg, unsigned threads) {
    check_no_nul(view_name_text, "view");
    const View view = as_value_error([&] { return parse_view(view_name_text); });
    bool prims = false;
    if (!counter_arg.is_none()) {
        if (view != View::Heatmap)
            throw py::value_error("counter chooses what the heatmap view counts; the view is " + view_name_text);
        const std::string c = py::str(counter_arg);
        if (c != "nodes" && c != "prims")
            throw py::value_error("counter must be 'nodes' (nodes visited per ray) or 'prims' (primitive tests per "
                                  "ray), got '" + c + "'");
        prims = c == "prims";
    }
    ViewBufferRequest request;
    request.depth = view == View::Depth;
    request.normal = view == View::Normal;
    request.counters = view == View::Heatmap;
    const py::ssize_t H = height, W = width;
    check_allocation(bytes_of(uint64_t(W) * uint64_t(H), 2 * 12 + 8),
                     "render: a " + std::to_string(width) + "x" + std::to_string(height) + " image");
    const Camera camera = given ? *given : auto_camera(h.scene->bounds(), float(width) / float(height));
    ViewBuffers b;
    {
        py::gil_scoped_release nogil;
        b = render_view_buffers(*h.scene, *h.accel, camera, width, height, request, threads);
    }
    if (view == View::Depth) return float_array(b.depth, {H, W});
    if (view == View::Normal) return float_array(b.normal, {H, W, 3});
    const std::vector<uint32_t>& counts = prims ? b.prims : b.nodes;
    py::array_t<uint32_t> a({H, W});
    std::memcpy(a.mutable_data(), counts.data(), counts.size() * sizeof(uint32_t));
    return a;
}

bool ends_with_json(const std::string& path) {
    if (path.size() < 5) return false;
    std::string tail = path.substr(path.size() - 5);
    for (char& ch : tail) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return tail == ".json";
}

std::vector<PointLight> lights_argument(const py::handle& lights) {
    std::vector<PointLight> out;
    if (lights.is_none()) return out;
    if (!py::isinstance<py::sequence>(lights) || PyUnicode_Check(lights.ptr()))
        throw py::type_error("lights must be a list of (position, intensity) pairs, got " + type_name(lights));
    for (const py::handle item : py::reinterpret_borrow<py::sequence>(lights)) {
        const std::string which = "lights[" + std::to_string(out.size()) + "]";
        if (!py::isinstance<py::sequence>(item) || py::len(item) != 2)
            throw py::value_error(which + " must be a (position, intensity) pair, got " + std::string(py::repr(item)));
        const py::sequence pair = py::reinterpret_borrow<py::sequence>(item);
        PointLight light;
        light.position = vec3_argument(pair[0], (which + " position").c_str());
        const py::object intensity = pair[1];
        if (PyNumber_Check(intensity.ptr()) && !py::isinstance<py::array>(intensity))
            light.intensity = Vec3{*float_argument(intensity, (which + " intensity").c_str())};
        else
            light.intensity = vec3_argument(intensity, (which + " intensity").c_str());
        for (float c : {light.intensity.x, light.intensity.y, light.intensity.z})
            if (!(c >= 0.0f) || double(c) > kMaxPointIntensity)
                throw py::value_error(which + " intensity must be from 0 to 1e20 W/sr per channel, got " +
                                      std::string(py::repr(intensity)));
        out.push_back(light);
    }
    return out;
}

py::array path_trace_array(const py::handle& target, uint32_t spp, int width, int height,
                           const std::optional<Camera>& given, uint64_t seed, uint32_t max_depth,
                           const std::string& integrator_text, const std::vector<PointLight>& lights,
                           unsigned threads) {
    check_no_nul(integrator_text, "integrator");
    const Integrator integrator = as_value_error([&] { return parse_integrator(integrator_text); });
    std::shared_ptr<const Scene> scene;
    std::shared_ptr<const Accel> accel;
    if (py::isinstance<AccelHandle>(target)) {
        const AccelHandle& h = target.cast<const AccelHandle&>();
        scene = h.scene;
        accel = h.accel;
    } else if (py::isinstance<Scene>(target)) {
        scene = target.cast<std::shared_ptr<Scene>>();
    } else {
        throw py::type_error("path_trace: the first argument must be a thicket.Scene or a thicket.Accel, got " +
                             type_name(target));
    }
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    // The per-pixel sums (3 doubles), the means and the array handed back.
    check_allocation(bytes_of(pixels, 3 * 8 + 12 + 12),
                     "path_trace: a " + std::to_string(width) + "x" + std::to_string(height) + " image");
    const std::optional<InputFile> file = scene_file(std::const_pointer_cast<Scene>(scene));
    TraceResult result;
    {
        py::gil_scoped_release nogil;
        RenderScene rs = make_render_scene(*scene);
        // As the CLI: a JSON scene's materials, lights and camera.
        if (file && ends_with_json(file->path)) apply_json_render_settings(file->path, rs);
        rs.point_lights.insert(rs.point_lights.end(), lights.begin(), lights.end());
        if (!accel) accel = build_accel(kDefaultSpec, *scene);
        const Camera camera =
            given ? *given : rs.camera ? *rs.camera : auto_camera(scene->bounds(), float(width) / float(height));
        add_automatic_light(rs, *accel, camera, width, height);
        TraceOptions options;
        options.width = width;
        options.height = height;
        options.spp = spp;
        options.seed = seed;
        options.threads = threads;
        options.max_depth = max_depth;
        options.progress = false;
        result = trace_image(rs, *accel, camera, integrator, options);
    }
    return float_array(result.radiance, {py::ssize_t(height), py::ssize_t(width), 3});
}

/// `value` as a numpy array (a list becomes one), for arguments that take any array-like.
py::array array_argument(const py::handle& value) { return py::module_::import("numpy").attr("asarray")(value); }

py::array heat_colour_array(const py::handle& counts_arg, const py::handle& heat_max_arg) {
    const py::array counts = array_argument(counts_arg);
    if (!(counts.dtype().kind() == 'u' || counts.dtype().kind() == 'i' || counts.dtype().kind() == 'f'))
        throw py::value_error("counts: expected an array of numbers (Accel.render(view='heatmap')'s), got dtype " +
                              std::string(py::str(counts.dtype())));
    const py::array_t<double> c = contiguous(counts, py::dtype::of<double>(), "counts");
    const size_t n = size_t(c.size());
    double scale = 0.0;
    if (std::optional<float> m = float_argument(heat_max_arg, "heat_max")) {
        if (!(*m > 0.0f) || !std::isfinite(*m))
            throw py::value_error("heat_max must be a count > 0 at the top of the ramp (or None: the largest count)");
        scale = *m;
    }
    const double* d = c.data();
    for (size_t i = 0; i < n; ++i)
        if (!(d[i] >= 0.0) || !std::isfinite(d[i]))
            throw py::value_error("counts: every count must be a finite number >= 0, got " + std::to_string(d[i]) +
                                  " at flat index " + std::to_string(i));
    if (scale == 0.0) scale = std::max(1.0, n ? *std::max_element(d, d + n) : 0.0);  // the CLI's image maximum
    std::vector<py::ssize_t> shape(counts.shape(), counts.shape() + counts.ndim());
    shape.push_back(3);
    py::array_t<uint8_t> out(shape);
    uint8_t* o = out.mutable_data();
    for (size_t i = 0; i < n; ++i) {
        const Rgb8 rgb = to_rgb8(heat_colour(float(d[i] / scale)));
        o[3 * i] = rgb.r;
        o[3 * i + 1] = rgb.g;
        o[3 * i + 2] = rgb.b;
    }
    return out;
}

void save_png_file(const py::object& path_arg, const py::handle& image_arg, const py::handle& exposure_arg, bool overwrite) {
    const std::string path = path_argument(path_arg, "path");
    const py::array image = array_argument(image_arg);
    const char kind = image.dtype().kind();
    const bool bytes = image.dtype().is(py::dtype::of<uint8_t>());
    const bool grey = bytes && image.ndim() == 2;
    if (!(grey || (image.ndim() == 3 && image.shape(2) == 3 && (bytes || kind == 'f'))))
        throw py::value_error("image: expected uint8 (H, W) or (H, W, 3), or float (H, W, 3) radiance, got shape " +
                              shape_text(image) + " " + std::string(py::str(image.dtype())));
    const float exposure = float_argument(exposure_arg, "exposure").value_or(1.0f);
    if (!(exposure > 0.0f) || !std::isfinite(exposure))
        throw py::value_error("exposure must be a finite number > 0 (it scales float radiance)");
    if (bytes && !exposure_arg.is_none())
        throw py::value_error("exposure scales float radiance; a uint8 image is written as it is");
    const int H = int(std::min<py::ssize_t>(image.shape(0), INT_MAX)), W = int(std::min<py::ssize_t>(image.shape(1), INT_MAX));
    if (H < 1 || W < 1 || H > Image::kMaxSide || W > Image::kMaxSide)
        throw py::value_error("image: a PNG side must be from 1 to " + std::to_string(Image::kMaxSide) +
                              " pixels, got shape " + shape_text(image));
    refuse_clobber(path, {}, overwrite);
    Image out;
    if (bytes) {
        const py::array_t<uint8_t> a = contiguous(image, py::dtype::of<uint8_t>(), "image");
        out = Image(W, H);
        const uint8_t* d = a.data();
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const size_t i = size_t(y) * size_t(W) + size_t(x);
                out.at(x, y) = grey ? Rgb8{d[i], d[i], d[i]} : Rgb8{d[3 * i], d[3 * i + 1], d[3 * i + 2]};
            }
    } else {
        const py::array_t<float> a = contiguous(image, py::dtype::of<float>(), "image");
        std::vector<Vec3> radiance(size_t(W) * size_t(H));
        const float* d = a.data();
        for (size_t i = 0; i < radiance.size(); ++i) radiance[i] = Vec3{d[3 * i], d[3 * i + 1], d[3 * i + 2]};
        out = tonemap_srgb(radiance, W, H, exposure);
    }
    py::gil_scoped_release nogil;
    write_png(out, path);
}

}  // namespace

void add_picture_functions(py::module_& m) {
    auto accel_class = py::reinterpret_borrow<py::class_<AccelHandle>>(m.attr("Accel"));

    m.def("rays", [](std::shared_ptr<Scene> scene, const std::string& set, const py::handle& width,
                     const py::handle& height, const py::handle& eye, const py::handle& center, const py::handle& up,
                     const py::handle& vfov_deg, const py::handle& nthreads) {
        if (!scene) throw py::value_error("rays: scene is None");
        const int w = side_argument(width, "width", 16384), h = side_argument(height, "height", 16384);
        return ray_set_dict(scene, set, w, h, camera_argument(eye, center, up, vfov_deg), thread_count(nthreads));
    }, "scene"_a, "set"_a = "primary", "width"_a = 320, "height"_a = 240, "eye"_a = py::none(),
          "center"_a = py::none(), "up"_a = py::none(), "vfov_deg"_a = py::none(), "nthreads"_a = 0,
          "rays(scene, set='primary', width=320, height=240, eye=None, center=None, up=None, vfov_deg=None, "
          "nthreads=0) -> dict. The bench's standard ray set `set` (primary, shadow, diffuse or random), the very "
          "rays `thicket rays SCENE --set SET --size WxH [--camera ...]` writes (fixed seeds: the same arguments "
          "give the same rays). rays: float32 (N, 6), Open3D's layout ox oy oz dx dy dz (unit directions); tmin, "
          "tmax: float32 (N,), each ray's interval (tmin 0; tmax inf except for shadow rays, which stop short of "
          "the light): np.column_stack((rays, tmin, tmax)) is the CLI's (N, 8); any_hit: bool, True for shadow "
          "rays (trace them with test_occlusions); pixel: uint32 (N,), the pixel y * width + x each primary ray "
          "goes through or each shadow and diffuse ray starts from (absent for random); set (str), width, height "
          "(ints); eye, center (tuples), vfov_deg (float): the camera used; light (tuple): the shadow set's point "
          "light; interior (bool): the scene was seen from inside. width, height: the primary image, 1 to 16384 "
          "(random: width * height rays). eye and center (3 numbers each) give the camera (up default (0, 1, 0), "
          "vfov_deg vertical, default 45); without them the CLI's automatic view");

    accel_class.def("render", [](const AccelHandle& h, const std::string& view, const py::handle& width,
                                 const py::handle& height, const py::handle& eye, const py::handle& center,
                                 const py::handle& up, const py::handle& vfov_deg, const py::handle& counter,
                                 const py::handle& nthreads) {
        const int w = side_argument(width, "width", Image::kMaxSide), hh = side_argument(height, "height", Image::kMaxSide);
        return render_array(h, view, w, hh, camera_argument(eye, center, up, vfov_deg), counter, thread_count(nthreads));
    }, "view"_a = "normal", "width"_a = 640, "height"_a = 480, "eye"_a = py::none(), "center"_a = py::none(),
          "up"_a = py::none(), "vfov_deg"_a = py::none(), "counter"_a = py::none(), "nthreads"_a = 0,
          "render(view='normal', width=640, height=480, eye=None, center=None, up=None, vfov_deg=None, counter=None, "
          "nthreads=0) -> ndarray. The CLI's preview views (`thicket render --view`) as numbers, one ray per pixel "
          "centre, row 0 at the top: 'normal' float32 (height, width, 3), the hit triangle's unit geometric normal "
          "turned toward the camera ((0, 0, 0) on a miss; 0.5 * n + 0.5 is the CLI's colour); 'depth' float32 "
          "(height, width), the hit distance t (inf on a miss); 'heatmap' uint32 (height, width), the work of each "
          "ray: nodes visited (counter='nodes', the default) or primitives tested (counter='prims') - "
          "thicket.heat_colours makes the CLI's colours of it. eye and center (3 numbers each) give the camera (up "
          "default (0, 1, 0); vfov_deg the vertical field of view, default 45, where create_rays_pinhole's fov_deg is "
          "horizontal); without them the CLI's "
          "automatic camera (from +z, 10 degrees up, framing the bounds). width, height: 1 to 32768");

    m.def("path_trace", [](const py::handle& scene, const py::handle& spp, const py::handle& width,
                           const py::handle& height, const py::handle& eye, const py::handle& center,
                           const py::handle& up, const py::handle& vfov_deg, const py::handle& seed,
                           const py::handle& max_depth, const std::string& integrator, const py::handle& lights,
                           const py::handle& nthreads) {
        const uint32_t s = uint32_t(int_argument(spp, "spp", 1, UINT32_MAX, "a sample count from 1 to 2^32 - 1"));
        const uint32_t d = uint32_t(int_argument(max_depth, "max_depth", 1, UINT32_MAX, "a segment count from 1 to 2^32 - 1"));
        const int w = side_argument(width, "width", Image::kMaxSide), h = side_argument(height, "height", Image::kMaxSide);
        const std::optional<Camera> camera = camera_argument(eye, center, up, vfov_deg);
        return path_trace_array(scene, s, w, h, camera, u64_argument(seed, "seed"), d, integrator,
                                lights_argument(lights), thread_count(nthreads));
    }, "scene"_a, "spp"_a = 16, "width"_a = 640, "height"_a = 480, "eye"_a = py::none(), "center"_a = py::none(),
          "up"_a = py::none(), "vfov_deg"_a = py::none(), "seed"_a = 0, "max_depth"_a = 64, "integrator"_a = "path",
          "lights"_a = py::none(), "nthreads"_a = 0,
          "path_trace(scene, spp=16, width=640, height=480, eye=None, center=None, up=None, vfov_deg=None, seed=0, "
          "max_depth=64, integrator='path', lights=None, nthreads=0) -> float32 ndarray (height, width, 3). Linear "
          "radiance per pixel (row 0 at the top) from the library's path tracer (integrator='whitted': the Whitted "
          "ray tracer), as `thicket render SCENE --integrator path --spp N --seed S --max-depth D` renders it: the "
          "same arguments give the same floats (its .exr), and save_png gives its .png. scene: a Scene (a 'bvh8' "
          "is built) or an Accel. Materials and lights are the CLI's: a JSON scene's own materials, lights and "
          "camera, else Lambertian 0.8; lights: a list of point lights (position, intensity), intensity in W/sr, "
          "one number or (r, g, b), added to the scene's; with no light at all, the CLI's automatic light at the "
          "camera. Camera: eye and center (up, vfov_deg), else the scene's own, else the automatic one. spp >= 1, "
          "seed 0 to 2^64 - 1 (bit-identical images for a seed, whatever nthreads), max_depth >= 1 path segments");

    m.def("heat_colours", &heat_colour_array, "counts"_a, "heat_max"_a = py::none(),
          "heat_colours(counts, heat_max=None) -> uint8 ndarray (..., 3). The CLI's heatmap colours of counts "
          "(Accel.render(view='heatmap')'s, any shape of numbers >= 0): the ramp black, blue, magenta, orange, "
          "yellow, white from 0 to heat_max (default: the largest count, as the CLI's --heat-max 0); "
          "save_png(path, heat_colours(counts)) is `thicket render --view heatmap --no-legend`'s picture");

    m.def("save_png", [](const py::object& path, const py::handle& image, const py::handle& exposure, bool overwrite) {
        save_png_file(path, image, exposure, overwrite);
    }, "path"_a, "image"_a, "exposure"_a = py::none(), "overwrite"_a = false,
          "save_png(path, image, exposure=None, overwrite=False) -> None. Writes an 8-bit RGB PNG: a uint8 image "
          "(H, W, 3) or (H, W) (grey) as it is; a float image (H, W, 3) as linear radiance (path_trace's), scaled "
          "by exposure (default 1), clamped to [0, 1] and sRGB-encoded, as the CLI's render writes it. path: str, "
          "bytes or os.PathLike; an existing file is replaced only with overwrite=True (FileExistsError "
          "otherwise)");
}

}  // namespace thicket::python
