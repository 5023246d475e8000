#include "report_json.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

namespace lancer::bench {

namespace {

using nlohmann::json;

json ms_list(const std::vector<std::pair<int, double>>& list) {
  json a = json::array();
  for (const auto& [threads, ms] : list) a.push_back({{"threads", threads}, {"ms", ms}});
  return a;
}

json options_json(const BenchRun& run) {
  const BenchOptions& o = run.options;
  json j;
  j["size"] = o.size;
  j["reps"] = o.reps;
  j["quick"] = o.quick;
  j["threads_requested"] = o.threads;
  j["threads"] = run.threads;
  j["models"] = o.models.string();
  for (RaySet s : o.sets) j["sets"].push_back(std::string(ray_set_name(s)));
  for (Mode m : o.modes) j["modes"].push_back(std::string(mode_name(m)));
  for (Isa i : o.isas) j["isas"].push_back(std::string(isa_name(i)));
  return j;
}

json row_json(const Row& r) {
  json j = {{"set", std::string(ray_set_name(r.set))},
            {"isa", std::string(isa_name(r.isa))},
            {"threads", r.threads},
            {"rays", r.rays}};
  if (!r.failure.empty()) j["failure"] = r.failure;
  j["modes"] = json::object();
  for (const ModeTiming& t : r.modes) {
    const RateSummary s = summarize(t.seconds, r.rays);
    j["modes"][std::string(mode_name(t.mode))] = {
        {"call", t.call},           {"passes_per_run", t.passes}, {"seconds_per_pass", t.seconds},
        {"mrays_median", s.median}, {"mrays_min", s.min},         {"mrays_max", s.max}};
  }
  return j;
}

json check_json(const SetCheck& c) {
  json j = {{"set", std::string(ray_set_name(c.set))},
            {"isa", std::string(isa_name(c.isa))},
            {"rays", c.rays},
            {"answered", c.answered}};
  if (c.packet_checked) j["packet_mismatches"] = c.packet_mismatches;
  if (c.work_counted)
    j["single_work_per_ray"] = {
        {"inner_steps", c.work.inner_steps}, {"leaves", c.work.leaves}, {"triangle_tests", c.work.triangle_tests}};
  if (c.embree_checked) {
    j["embree_ties"] = c.embree_ties;
    j["embree_disagreements"] = c.embree_disagreements;
  }
  if (!c.embree_call.empty()) j["embree_call"] = c.embree_call;
  for (const auto& [call, mrays] : c.embree_calibration)
    j["embree_calibration"].push_back({{"call", call}, {"mrays", mrays}});
  if (!c.failure.empty()) j["failure"] = c.failure;
  return j;
}

json scene_json(const SceneResult& s) {
  json j = {{"name", s.name},
            {"origin", s.origin},
            {"source", s.source},
            {"triangles", s.triangles},
            {"added_light", s.added_light},
            {"load_ms", s.load_ms},
            {"peak_rss_bytes", s.peak_rss_bytes}};
  if (!s.failure.empty()) j["failure"] = s.failure;
  j["builds"] = json::array();
  for (const IsaBuild& b : s.builds) {
    json bj = {{"isa", std::string(isa_name(b.isa))},
               {"lancer_build", ms_list(b.lancer_ms)},
               {"lancer_bytes", b.lancer_bytes}};
    if (b.embree_bytes >= 0) {
      bj["embree_build"] = ms_list(b.embree_ms);
      bj["embree_bytes"] = b.embree_bytes;
    }
    j["builds"].push_back(bj);
  }
  j["checks"] = json::array();
  for (const SetCheck& c : s.checks) j["checks"].push_back(check_json(c));
  j["rows"] = json::array();
  for (const Row& r : s.rows) j["rows"].push_back(row_json(r));
  return j;
}

}  // namespace

std::string run_to_json(const BenchRun& run) {
  json j;
  j["schema"] = "lancer-bench/1";
  j["options"] = options_json(run);
  j["machine"] = {{"hardware_threads", run.hardware_threads},
                  {"load_average_start", run.load_average_start},
                  {"load_average_end", run.load_average_end}};
  j["embree"] = run.embree;
  j["wall_seconds"] = run.wall_seconds;
  j["peak_rss_bytes"] = run.peak_rss_bytes;
  j["scenes"] = json::array();
  for (const SceneResult& s : run.scenes) j["scenes"].push_back(scene_json(s));
  return j.dump(1, ' ', false, json::error_handler_t::replace) + "\n";
}

void write_text_file(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::path tmp = file;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(file.string() + ": cannot write (" + std::strerror(errno) + ")");
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(file.string() + ": write failed (" + std::strerror(errno) + ")");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) throw std::runtime_error(file.string() + ": cannot rename " + tmp.string() + " over it: " + ec.message());
}

void write_json(const BenchRun& run, const std::filesystem::path& file) { write_text_file(file, run_to_json(run)); }

}  // namespace lancer::bench
