#include "cycles_runner.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <deque>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace lancer::bench {

namespace {

// Single quotes for /bin/sh: the only character to escape is the quote itself.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Cycles' max_bounces counts the bounces after the first hit (0: direct light only), Lancer's
// max_depth the rays after the camera ray (1: direct light only).
int cycles_bounces(int lancer_max_depth) { return lancer_max_depth > 0 ? lancer_max_depth - 1 : 0; }

}  // namespace

bool blender_available(const std::string& blender) {
  const std::string cmd = "command -v " + shell_quote(blender) + " >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

double run_cycles(const std::string& blender, const std::filesystem::path& script, const CyclesJob& job) {
  const std::string cmd = shell_quote(blender) + " -b --factory-startup -P " + shell_quote(script.string()) +
                          " -- --scene " + shell_quote(job.scene.string()) + " --output " +
                          shell_quote(job.output.string()) + " --width " + std::to_string(job.size) +
                          " --height " + std::to_string(job.size) + " --spp " + std::to_string(job.spp) +
                          " --max-bounces " + std::to_string(cycles_bounces(job.max_depth)) + " --threads " +
                          std::to_string(job.threads) + " --seed " + std::to_string(job.seed) + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + blender);
  std::deque<std::string> tail;  // the last lines, for the message when it fails
  std::string result;
  std::array<char, 4096> buf{};
  std::string line;
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe)) {
    line += buf.data();
    if (line.empty() || line.back() != '\n') continue;
    line.pop_back();
    const std::string prefix = "cycles_render: {";
    if (line.rfind(prefix, 0) == 0) result = line.substr(prefix.size() - 1);
    tail.push_back(line);
    if (tail.size() > 8) tail.pop_front();
    line.clear();
  }
  const int status = ::pclose(pipe);
  if (status != 0 || result.empty()) {
    std::string msg = "Cycles failed on " + job.scene.string() + " (exit status " +
                      std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + "):";
    for (const std::string& l : tail) msg += "\n  " + l;
    throw std::runtime_error(msg);
  }
  const nlohmann::json j = nlohmann::json::parse(result, nullptr, false);
  if (j.is_discarded() || !j.contains("render_seconds") || !j["render_seconds"].is_number())
    throw std::runtime_error("Cycles printed no render time: " + result);
  return j["render_seconds"].get<double>();
}

}  // namespace lancer::bench
