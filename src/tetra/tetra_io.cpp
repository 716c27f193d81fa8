// Tetra payload: the mesh's arrays, each preceded by its length, the fallback's primitive ids,
// the build report, then the fallback BVH (last: its reader checks for trailing bytes).
// Reading checks every length against the bytes left before allocating (PayloadReader), then the
// structure (validate_tetra); the Tetra that adopts it proves its geometry
// (validate_tetra_geometry).
#include <istream>
#include <ostream>
#include <string>

#include "thicket/bvh/build.h"
#include "thicket/core/error.h"
#include "thicket/tetra/build.h"
#include "thicket/util/binary_io.h"

namespace thicket {

void write_tetra(std::ostream& out, const TetraData& data) {
    const TetraMesh& m = data.mesh;
    write_counted_array<uint64_t>(out, m.points);
    write_counted_array<uint64_t>(out, m.tets);
    write_counted_array<uint64_t>(out, m.neighbors);
    write_counted_array<uint64_t>(out, m.face_tris);
    write_counted_array<uint64_t>(out, m.vertex_offsets);
    write_counted_array<uint64_t>(out, m.vertex_tris);
    write_value(out, m.box_min);
    write_value(out, m.box_max);
    write_value(out, m.grid_res);
    write_counted_array<uint64_t>(out, m.grid_start);
    write_counted_array<uint64_t>(out, data.fallback);
    const TetraReport& r = data.report;
    write_value(out, r.input_triangles);
    write_value(out, r.meshed_triangles);
    write_value(out, r.steiner_points);
    write_value(out, r.tetgen_runs);
    write_value(out, r.tetgen_ms);
    write_counted_array<uint64_t>(out, std::vector<char>(r.outcome.begin(), r.outcome.end()));
    write_bvh(out, data.fallback_bvh);
}

TetraData read_tetra(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "tetra");
    TetraData data;
    TetraMesh& m = data.mesh;
    reader.counted_array<uint64_t>(m.points, PayloadReader::kAnyCount, "points");
    reader.counted_array<uint64_t>(m.tets, PayloadReader::kAnyCount, "tetrahedra");
    reader.counted_array<uint64_t>(m.neighbors, PayloadReader::kAnyCount, "neighbours");
    reader.counted_array<uint64_t>(m.face_tris, PayloadReader::kAnyCount, "face triangles");
    reader.counted_array<uint64_t>(m.vertex_offsets, PayloadReader::kAnyCount, "vertex offsets");
    reader.counted_array<uint64_t>(m.vertex_tris, PayloadReader::kAnyCount, "vertex triangles");
    reader.value(m.box_min, "box");
    reader.value(m.box_max, "box");
    reader.value(m.grid_res, "grid resolution");
    reader.counted_array<uint64_t>(m.grid_start, PayloadReader::kAnyCount, "start grid");
    reader.counted_array<uint64_t>(data.fallback, primitive_count, "fallback primitives");
    TetraReport& r = data.report;
    reader.value(r.input_triangles, "report");
    reader.value(r.meshed_triangles, "report");
    reader.value(r.steiner_points, "report");
    reader.value(r.tetgen_runs, "report");
    reader.value(r.tetgen_ms, "report");
    std::vector<char> outcome;
    reader.counted_array<uint64_t>(outcome, PayloadReader::kAnyCount, "report");
    r.outcome.assign(outcome.begin(), outcome.end());
    data.fallback_bvh = read_bvh(in, data.fallback.size());
    validate_tetra(data, primitive_count);
    return data;
}

}  // namespace thicket
