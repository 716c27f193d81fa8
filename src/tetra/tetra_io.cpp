// Tetra payload: the mesh's arrays, each preceded by its length, the fallback's primitive ids,
// the build report, then the fallback BVH (last: its reader checks for trailing bytes).
// Reading checks every length against the bytes left before allocating, then the structure.
#include <istream>
#include <limits>
#include <ostream>
#include <string>

#include "thicket/bvh/build.h"
#include "thicket/core/error.h"
#include "thicket/tetra/build.h"
#include "thicket/util/binary_io.h"

namespace thicket {

namespace {

/// Writes v's length, then its elements as they are in memory.
template <class T>
void write_vector(std::ostream& out, const std::vector<T>& v) {
    write_value(out, uint64_t(v.size()));
    write_array(out, v.data(), v.size());
}

/// Bytes left in `in` (or the largest size_t when the stream cannot tell).
size_t bytes_left(std::istream& in) {
    const auto here = in.tellg();
    if (here < 0) return std::numeric_limits<size_t>::max();
    in.seekg(0, std::ios::end);
    const auto end = in.tellg();
    in.seekg(here);
    return end < here ? 0 : size_t(end - here);
}

/// Reads what write_vector() wrote, refusing a length the remaining bytes cannot hold.
template <class T>
void read_vector(std::istream& in, PayloadReader& reader, std::vector<T>& v, const char* what) {
    uint64_t n = 0;
    reader.value(n, what);
    if (n > bytes_left(in) / sizeof(T))
        throw Error(std::string("tetra payload claims ") + std::to_string(n) + " entries of " + what +
                    ", more than the file holds");
    v.resize(size_t(n));
    reader.array(v.data(), v.size(), what);
}

}  // namespace

void write_tetra(std::ostream& out, const TetraData& data) {
    const TetraMesh& m = data.mesh;
    write_vector(out, m.points);
    write_vector(out, m.tets);
    write_vector(out, m.neighbors);
    write_vector(out, m.face_tris);
    write_vector(out, m.vertex_offsets);
    write_vector(out, m.vertex_tris);
    write_value(out, m.box_min);
    write_value(out, m.box_max);
    write_value(out, m.grid_res);
    write_vector(out, m.grid_start);
    write_vector(out, data.fallback);
    const TetraReport& r = data.report;
    write_value(out, r.input_triangles);
    write_value(out, r.meshed_triangles);
    write_value(out, r.steiner_points);
    write_value(out, r.tetgen_runs);
    write_value(out, r.tetgen_ms);
    write_vector(out, std::vector<char>(r.outcome.begin(), r.outcome.end()));
    write_bvh(out, data.fallback_bvh);
}

TetraData read_tetra(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "tetra");
    TetraData data;
    TetraMesh& m = data.mesh;
    read_vector(in, reader, m.points, "points");
    read_vector(in, reader, m.tets, "tetrahedra");
    read_vector(in, reader, m.neighbors, "neighbours");
    read_vector(in, reader, m.face_tris, "face triangles");
    read_vector(in, reader, m.vertex_offsets, "vertex offsets");
    read_vector(in, reader, m.vertex_tris, "vertex triangles");
    reader.value(m.box_min, "box");
    reader.value(m.box_max, "box");
    reader.value(m.grid_res, "grid resolution");
    read_vector(in, reader, m.grid_start, "start grid");
    read_vector(in, reader, data.fallback, "fallback primitives");
    TetraReport& r = data.report;
    reader.value(r.input_triangles, "report");
    reader.value(r.meshed_triangles, "report");
    reader.value(r.steiner_points, "report");
    reader.value(r.tetgen_runs, "report");
    reader.value(r.tetgen_ms, "report");
    std::vector<char> outcome;
    read_vector(in, reader, outcome, "report");
    r.outcome.assign(outcome.begin(), outcome.end());
    data.fallback_bvh = read_bvh(in, data.fallback.size());
    validate_tetra(data, primitive_count);
    return data;
}

}  // namespace thicket
