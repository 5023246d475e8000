#include "render/render_settings.h"

namespace lancer {

std::string_view integrator_name(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::Path: return "path";
    case IntegratorKind::Whitted: return "whitted";
    case IntegratorKind::Sppm: return "sppm";
    case IntegratorKind::Photon: return "photon";
    case IntegratorKind::Normals: return "normals";
    case IntegratorKind::Albedo: return "albedo";
    case IntegratorKind::Depth: return "depth";
    case IntegratorKind::Ao: return "ao";
    case IntegratorKind::PrimId: return "primid";
  }
  return "unknown";
}

std::optional<IntegratorKind> parse_integrator(std::string_view name) {
  for (IntegratorKind k : {IntegratorKind::Path, IntegratorKind::Whitted, IntegratorKind::Sppm, IntegratorKind::Photon,
                           IntegratorKind::Normals, IntegratorKind::Albedo, IntegratorKind::Depth, IntegratorKind::Ao,
                           IntegratorKind::PrimId})
    if (integrator_name(k) == name) return k;
  return std::nullopt;
}

std::string_view trace_mode_name(TraceMode mode) {
  switch (mode) {
    case TraceMode::Packet: return "packet";
    case TraceMode::Single: return "single";
  }
  return "unknown";
}

std::optional<TraceMode> parse_trace_mode(std::string_view name) {
  for (TraceMode m : {TraceMode::Packet, TraceMode::Single})
    if (trace_mode_name(m) == name) return m;
  return std::nullopt;
}

}  // namespace lancer
