#include "bench/truth/texel_bounds.h"

#include <cstdio>

namespace omnishadow::bench {

std::string describe_worst(const std::vector<TexelFinding>& worst, const std::string& layer_prefix,
                           const char* const* layer_names) {
  if (worst.empty()) return "";
  const TexelFinding& w = worst.front();
  const std::string layer = layer_names ? layer_names[w.layer] : layer_prefix + std::to_string(w.layer);
  char buf[200];
  auto value = [](double v) { return v < 0 ? std::string("nothing") : std::to_string(v); };
  std::snprintf(buf, sizeof buf, "; worst: %s (%d, %d) got %s want %s, ", layer.c_str(), w.s, w.t,
                value(w.got).c_str(), value(w.want).c_str());
  std::string out = buf;
  if (w.edge_texels < 0)
    out += "no depth edge within 2 texels";
  else {
    std::snprintf(buf, sizeof buf, "a depth edge within %.4g texels", w.edge_texels);
    out += buf;
  }
  return out;
}

}  // namespace omnishadow::bench
