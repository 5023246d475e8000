// lancer-bench --json: every raw number of the run (each repetition's seconds, builds,
// memory, checks), for plots and comparisons between runs.
#pragma once

#include <filesystem>
#include <string>

#include "bench_results.h"

namespace lancer::bench {

// The run as JSON text (schema "lancer-bench/1").
std::string run_to_json(const BenchRun& run);

// Writes run_to_json(run) to `file` ("<file>.tmp" first, then renamed over it). Throws
// std::runtime_error naming the file when it cannot be written.
void write_json(const BenchRun& run, const std::filesystem::path& file);

// Writes `text` to `file` atomically, as write_json does (shared with the SVG plot).
void write_text_file(const std::filesystem::path& file, const std::string& text);

}  // namespace lancer::bench
