#include "thicket/bench/bench_json.h"
#include "thicket/bench/number_text.h"

#include <cmath>
#include <cstdio>

namespace thicket {

std::string JsonObjectWriter::number_text(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

std::string json_quote(std::string_view s) {
    std::string out = "\"";
    for (char ch : s) {
        const unsigned char c = static_cast<unsigned char>(ch);
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        case '\b': out += "\\b"; break;
        case '\f': out += "\\f"; break;
        default:
            if (c < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
                out += buf;
            } else {
                out += ch;
            }
        }
    }
    return out + "\"";
}

std::string bench_rows_json(std::span<const BenchRow> rows) {
    return json_array(rows, [](JsonObjectWriter& o, const BenchRow& r) {
        write_row_names(o, r);
        o.str("set", r.set);
        o.boolean("any_hit", r.any_hit);
        o.integer("threads", r.threads);
        o.integer("set_rays", r.set_rays);
        o.integer("rays", r.rays);
        o.integer("stride", r.stride);
        o.integer("reps", (unsigned long long)r.reps);
        o.integer("rounds", (unsigned long long)r.rounds);
        o.number("mrays", r.mrays);
        o.number("mrays_min", r.mrays_min);
        o.number("mrays_max", r.mrays_max);
        o.optional("ratio", r.ratio);
        o.number("cpu_util", r.cpu_util);
        o.integer("attempts", (unsigned long long)r.attempts);
        o.number("build_ms", r.build_ms);
        o.boolean("build_parallel", r.build_parallel);
        o.integer("bytes", r.bytes);
        o.integer("structure_bytes", r.structure_bytes);
        o.integer("primitive_bytes", r.primitive_bytes);
        o.number("bytes_per_prim", r.bytes_per_primitive());
        o.integer("nodes", r.nodes);
        o.optional("sah_cost", r.sah_cost > 0.0 ? std::optional<double>(r.sah_cost) : std::nullopt);
        o.optional("nodes_per_ray", r.nodes_per_ray);
        o.optional("prims_per_ray", r.prims_per_ray);
        if (!r.entered_share.empty()) {
            std::string shares = "[";
            for (size_t k = 0; k < r.entered_share.size(); ++k)
                shares += (k ? "," : "") + printf_string("%.6f", r.entered_share[k]);
            o.raw("entered_children", shares + "]");
        } else {
            o.raw("entered_children", "null");
        }
        o.number("hit_rate", r.hit_rate);
        o.optional("agree", r.agree);
        if (r.agree) {
            o.integer("disagreeing", r.disagreeing);
            o.integer("arbitrated", r.arbitrated);
        } else {
            o.raw("disagreeing", "null");
            o.raw("arbitrated", "null");
        }
        o.optional("max_dt", r.max_dt);
        o.optional("max_dt_rel", r.max_dt_rel);
    }) + "\n";
}

}  // namespace thicket
