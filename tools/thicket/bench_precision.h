#pragma once
// `thicket bench --offset D`: the figures of precision=double (README, BENCHMARKS.md).
#include <string>
#include <vector>

namespace thicket::cli {

/// For each scene: the time per ray of bvh:precision=double against the float bvh on the bench's
/// primary and diffuse rays (median of `reps` passes on `threads` threads) and their ratio; then,
/// when `offset` is not 0, the scene moved by `offset` on every axis (kept in double): of the rays
/// that double brute force judges (as many as ~2e8 triangle tests allow), how many the double and
/// the float bvh answer differently from it. Prints a table; returns the process exit code.
int run_precision_bench(const std::vector<std::string>& scenes, double offset, int reps, unsigned threads);

}  // namespace thicket::cli
