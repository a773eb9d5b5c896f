#include "bench/report/compare.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include "bench/io/file_io.h"
#include "bench/io/image_io.h"
#include "bench/io/statistics.h"
#include "bench/report/results_writer.h"
#include "bench/truth/image_compare.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string slug(std::string s) {
  std::string out;
  for (char c : s) {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '.')
      out += c;
    else if (!out.empty() && out.back() != '-')
      out += '-';
  }
  while (!out.empty() && out.back() == '-') out.pop_back();
  return out;
}

void compare_counters(const json& base, const json& fresh, CaseComparison& out) {
  for (const char* pass : {"shadow", "lighting"}) {
    if (!base.contains(pass) || !fresh.contains(pass)) continue;
    const json &b = base[pass], &n = fresh[pass];
    if (!b.value("valid", false) || !n.value("valid", false)) continue;
    for (const auto& [field, value] : b.items()) {
      if (field == "valid" || !n.contains(field) || n[field] == value) continue;
      out.work_changes.push_back(std::string(pass) + " " + field + " " + value.dump() + " -> " +
                                 n[field].dump());
    }
  }
}

std::string file_digest(const std::string& path) {
  std::string bytes = read_file(path);
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return std::to_string(h) + ":" + std::to_string(bytes.size());
}

// For a run fetched from the results store (which keeps hashes, not pixels): the SHA-256 of each image, by
// its path, from image_hashes.json beside its results.json, read once per run; empty for any other run.
using StoredHashes = std::map<std::string, std::string>;
StoredHashes stored_image_hashes(const RunData& run) {
  StoredHashes out;
  std::error_code ec;
  const fs::path stored = fs::path(run.dir) / "image_hashes.json";
  if (!fs::is_regular_file(stored, ec)) return out;
  const json hashes = json::parse(read_file(stored.string()), nullptr, false);
  if (hashes.is_object())
    for (const auto& [path, hash] : hashes.items())
      if (hash.is_string()) out[path] = hash.get<std::string>();
  return out;
}

// The SHA-256 of a run's image: of the file, else the stored hash; "" when neither is there.
std::string image_sha256(const RunData& run, const StoredHashes& stored, const std::string& relative) {
  const std::string file = sha256_hex_of_file((fs::path(run.dir) / relative).string());
  if (!file.empty()) return file;
  const auto it = stored.find(relative);
  return it == stored.end() ? "" : it->second;
}

// One image role of a case: identical bytes pass at once; otherwise decode, measure and draw a diff. An image
// only a hash stands for (a stored run) is compared by that hash.
void compare_image(const RunData& base, const RunData& fresh,
                   const std::pair<StoredHashes, StoredHashes>& stored, const json& bc, const json& nc,
                   const std::string& role, const fs::path& diff_dir, CaseComparison& out) {
  if (!bc.contains("images") || !nc.contains("images") || !bc["images"].contains(role) ||
      !nc["images"].contains(role))
    return;
  const std::string b_rel = bc["images"][role].get<std::string>(),
                    n_rel = nc["images"][role].get<std::string>();
  std::string bp = (fs::path(base.dir) / b_rel).string();
  std::string np = (fs::path(fresh.dir) / n_rel).string();
  if (!fs::exists(bp) || !fs::exists(np)) {
    const std::string b_hash = image_sha256(base, stored.first, b_rel),
                      n_hash = image_sha256(fresh, stored.second, n_rel);
    if (b_hash.empty() || n_hash.empty())
      out.image_changes.push_back(role + ": image missing (" + (b_hash.empty() ? bp : np) + ")");
    else if (b_hash != n_hash)
      out.image_changes.push_back(
          role + ": changed (SHA-256 against the stored run's; the store keeps no pixels to diff)");
    return;
  }
  if (file_digest(bp) == file_digest(np)) return;
  std::vector<float> a, b, grey;
  int w = 0, h = 0;
  bool flip = false;
  if (bp.ends_with(".pfm")) {
    FloatImage x = read_pfm(bp), y = read_pfm(np);
    if (x.width != y.width || x.height != y.height || x.channels != y.channels) {
      out.image_changes.push_back(role + ": size changed");
      return;
    }
    a = x.values;
    b = y.values;
    grey = x.values;
    w = x.width;
    h = x.height * x.channels;
    flip = true;  // PFM rows are bottom-up
  } else {
    ByteImage x = read_png(bp), y = read_png(np);
    if (x.width != y.width || x.height != y.height || x.channels != y.channels) {
      out.image_changes.push_back(role + ": size changed");
      return;
    }
    // Per pixel, the largest channel difference.
    size_t pixels = static_cast<size_t>(x.width) * x.height;
    a.assign(pixels, 0.0f);
    b.assign(pixels, 0.0f);
    grey.assign(pixels, 0.0f);
    for (size_t i = 0; i < pixels; ++i) {
      int d = 0;
      for (int c = 0; c < x.channels; ++c) {
        size_t k = i * static_cast<size_t>(x.channels) + static_cast<size_t>(c);
        d = std::max(d, std::abs(int(x.pixels[k]) - int(y.pixels[k])));
      }
      a[i] = static_cast<float>(d);
      grey[i] = x.pixels[i * static_cast<size_t>(x.channels)] / 255.0f;
    }
    w = x.width;
    h = x.height;
  }
  Difference d = compare_values(a, b, 0.0);
  if (d.differing == 0) return;  // encodings differ, pixels do not
  fs::create_directories(diff_dir);
  std::string diff = (diff_dir / ("diff_" + role + ".png")).string();
  write_png_rgb_top_down(diff, w, h,
                         diff_image_rgb(a, b, grey, w, h, 0.0, bp.ends_with(".pfm") ? 1.0 : 64.0, flip));
  out.image_changes.push_back(role + ": " + fmt("%.4g", d.percent_differing()) + "% of values differ (max " +
                              fmt("%.4g", d.max_abs) + "), diff " + diff);
}

}  // namespace

std::map<std::string, std::string> device_keys(const RunData& run) {
  std::map<std::string, std::string> keys;
  const json& o = run.doc["omnishadow"];
  std::string threads = o.contains("system") ? o["system"].value("LP_NUM_THREADS", "unset") : "unset";
  if (threads.rfind("unset", 0) == 0) threads = "unset";
  if (o.contains("devices") && o["devices"].is_object())
    for (const auto& [backend, d] : o["devices"].items())
      keys[backend] =
          slug(backend + "-" + d.value("renderer", "") + "-" + d.value("version", "") + "-lp-" + threads);
  return keys;
}

// `backends`: the base run's device keys (compare_runs has them already), one per backend it recorded.
static std::vector<std::string> setup_changes(const RunData& base, const RunData& fresh,
                                              const std::map<std::string, std::string>& backends) {
  auto extras = [](const RunData& run, const std::string& backend) -> const json* {
    const json* o = run.doc.contains("omnishadow") ? &run.doc["omnishadow"] : nullptr;
    if (!o || !o->contains("devices") || !(*o)["devices"].contains(backend)) return nullptr;
    const json& d = (*o)["devices"][backend];
    return d.contains("extra") && d["extra"].is_object() ? &d["extra"] : nullptr;
  };
  auto text = [](const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); };
  std::vector<std::string> out;
  for (const auto& [backend, _] : backends) {
    const json *b = extras(base, backend), *n = extras(fresh, backend);
    if (!b || !n) continue;
    for (const auto& [key, value] : b->items())
      if (n->contains(key) && (*n)[key] != value)
        out.push_back(backend + " " + key + ": " + text(value) + " -> " + text((*n)[key]));
  }
  return out;
}

static double median_clock(const RunData& run) {
  std::vector<double> clocks;
  for (const auto& [id, c] : run.cases) {
    const json* state = c->contains("device_state") ? &(*c)["device_state"] : nullptr;
    if (!state || !state->is_object() || !state->contains("samples") || !(*state)["samples"].is_array())
      continue;
    for (const json& s : (*state)["samples"])
      if (s.is_object() && s.contains("clock_mhz") && s["clock_mhz"].is_number())
        clocks.push_back(s["clock_mhz"].get<double>());
  }
  return clocks.empty() ? -1.0 : median(clocks);
}

std::string Comparison::clock_note() const {
  if (base_clock_mhz <= 0 || new_clock_mhz <= 0) return "";
  return fmt("clocks (median of every device-state sample): base %.0f MHz, ", base_clock_mhz) +
         fmt("new %.0f MHz ", new_clock_mhz) + fmt("(%+.1f%%)", 100 * (new_clock_mhz / base_clock_mhz - 1));
}

namespace {

std::string status_of(const nlohmann::json& c) {
  return c.contains("status") && c["status"].is_string() ? c["status"].get<std::string>() : "?";
}

const std::map<std::string, std::vector<double>>& samples_of(const RunData& run, const std::string& metric) {
  if (metric == "cpu") return run.cpu_samples;
  if (metric == "gpu") return run.gpu_samples;
  return run.samples;
}

std::string metric_words(const std::string& metric) {
  if (metric == "cpu") return "process CPU time";
  if (metric == "gpu")
    return "GPU time (shadow + lighting passes, timer queries; repetitions whose timer passed its check)";
  return "wall time";
}

// Cases ok in the base that are not ok in the new run, or not there at all (an incomplete run was
// interrupted).
std::vector<std::string> status_regressions(const RunData& base, const RunData& fresh) {
  const json& o = fresh.doc["omnishadow"];
  const bool complete = !o.contains("complete") || !o["complete"].is_boolean() || o["complete"].get<bool>();
  std::string why_missing = complete ? "missing" : "missing (the new run was interrupted)";
  if (o.contains("missing_shards") && o["missing_shards"].is_array() && !o["missing_shards"].empty())
    why_missing = "missing (the merged run lacks shard " + o["missing_shards"].dump() + ")";
  std::vector<std::string> out;
  for (const auto& [id, bc] : base.cases) {
    if (status_of(*bc) != "ok") continue;
    auto it = fresh.cases.find(id);
    if (it == fresh.cases.end()) {
      out.push_back(id + ": ok -> " + why_missing);
      continue;
    }
    const std::string now = status_of(*it->second);
    if (now == "ok") continue;
    const json& nc = *it->second;
    const std::string reason =
        nc.contains("reason") && nc["reason"].is_string() ? nc["reason"].get<std::string>() : "";
    out.push_back(id + ": ok -> " + now + (reason.empty() ? "" : " (" + reason + ")"));
  }
  return out;
}

}  // namespace

bool Comparison::failed(const CompareOptions& options) const {
  if (!status_regressions.empty() || cases.empty()) return true;
  for (const CaseComparison& cc : cases)
    if (cc.regressed(options.timing_fails)) return true;
  return false;
}

Comparison compare_runs(const RunData& base, const RunData& fresh, const CompareOptions& options) {
  Comparison c;
  c.status_regressions = status_regressions(base, fresh);
  c.base_clock_mhz = median_clock(base);
  c.new_clock_mhz = median_clock(fresh);
  c.base_devices = device_keys(base);
  c.new_devices = device_keys(fresh);
  c.setup_changes = setup_changes(base, fresh, c.base_devices);
  for (const auto& [id, _] : base.cases)
    if (!fresh.cases.count(id)) c.only_in_base.push_back(id);
  for (const auto& [id, _] : fresh.cases)
    if (!base.cases.count(id)) c.only_in_new.push_back(id);

  const fs::path out_dir =
      options.out_dir.empty() ? fs::path(fresh.dir) / "compare" : fs::path(options.out_dir);
  std::vector<double> p_values;
  const std::pair<StoredHashes, StoredHashes> stored{stored_image_hashes(base), stored_image_hashes(fresh)};
  for (const auto& [id, bc] : base.cases) {
    auto it = fresh.cases.find(id);
    if (it == fresh.cases.end()) continue;
    const json& nc = *it->second;
    CaseComparison cc;
    cc.id = id;
    cc.verdict = "not timed";
    const auto& base_samples = samples_of(base, options.metric);
    const auto& new_samples = samples_of(fresh, options.metric);
    auto bs = base_samples.find(id), ns = new_samples.find(id);
    if (options.timing && bs != base_samples.end() && ns != new_samples.end()) {
      cc.base_n = bs->second.size();
      cc.new_n = ns->second.size();
      cc.base_ms = median(bs->second);
      cc.new_ms = median(ns->second);
      cc.change = cc.base_ms > 0 ? cc.new_ms / cc.base_ms - 1.0 : 0.0;
      cc.p = mann_whitney_p(bs->second, ns->second);
    } else if (options.timing && options.metric == "gpu" && base.samples.count(id) &&
               fresh.samples.count(id)) {
      cc.verdict = "no GPU time";  // timed, but no repetition's GPU timer passed its check in one of the runs
    }
    if (bc->contains("counters") && nc.contains("counters"))
      compare_counters((*bc)["counters"], nc["counters"], cc);
    for (const char* role : {"lit", "shadow_factor", "cube_faces"})
      compare_image(base, fresh, stored, *bc, nc, role, out_dir / "diffs" / id, cc);
    c.cases.push_back(cc);
  }
  for (const CaseComparison& cc : c.cases)
    if (cc.base_n > 0 && cc.new_n > 0) p_values.push_back(cc.p);
  std::vector<double> adjusted = holm_adjust(p_values);
  size_t k = 0;
  for (CaseComparison& cc : c.cases) {
    if (cc.base_n == 0 || cc.new_n == 0) continue;
    cc.p_adjusted = adjusted[k++];
    cc.resolvable = can_resolve(cc.base_n, cc.new_n, p_values.size(), options.alpha);
    bool significant = cc.p_adjusted < options.alpha;
    if (significant && cc.change > options.min_effect)
      cc.verdict = "regression";
    else if (significant && cc.change < -options.min_effect)
      cc.verdict = "improvement";
    else
      cc.verdict = "no change";
  }
  return c;
}

std::string Comparison::resolution_note(const CompareOptions& options) const {
  size_t timed = 0, blind = 0;
  for (const CaseComparison& cc : cases) {
    if (cc.base_n == 0 || cc.new_n == 0) continue;
    ++timed;
    blind += !cc.resolvable;
  }
  if (blind == 0) return "";
  return std::to_string(blind) + " of " + std::to_string(timed) + " timed cases cannot be flagged at alpha " +
         fmt("%g", options.alpha) + " whatever their change: too few repetitions (over " +
         std::to_string(timed) + " cases the U test needs " +
         std::to_string(fewest_resolving_repetitions(timed, options.alpha)) +
         " a side; run more, or --precision, whose minimum allows for this)";
}

std::string comparison_table(const Comparison& c, const CompareOptions& o) {
  std::ostringstream s;
  for (const auto& line : c.status_regressions) s << "STATUS REGRESSION " << line << "\n";
  if (c.cases.empty()) s << "no case in common: the two runs compare nothing (different matrices?)\n";
  size_t width = 10;
  for (const auto& cc : c.cases) width = std::max(width, cc.id.size());
  s << std::string(width, ' ').replace(0, 4, "case")
    << "   base ms    new ms   change   p (Holm)  n     verdict\n";
  for (const auto& cc : c.cases) {
    std::string id = cc.id + std::string(width - cc.id.size(), ' ');
    if (cc.base_n && cc.new_n)
      s << id << fmt("%10.3f", cc.base_ms) << fmt("%10.3f", cc.new_ms) << fmt("%+8.1f%%", 100 * cc.change)
        << fmt("%11.4f", cc.p_adjusted) << "  " << cc.base_n << "/" << cc.new_n << "  " << cc.verdict << "\n";
    else
      s << id << "         -         -        -          -  -     " << cc.verdict << "\n";
    for (const auto& w : cc.work_changes) s << "    work change: " << w << "\n";
    for (const auto& i : cc.image_changes) s << "    image change: " << i << "\n";
  }
  for (const auto& id : c.only_in_base) s << "only in base: " << id << "\n";
  for (const auto& id : c.only_in_new) s << "only in new: " << id << "\n";
  int regressions = 0, improvements = 0, work = 0, images = 0;
  for (const auto& cc : c.cases) {
    regressions += cc.verdict == "regression";
    improvements += cc.verdict == "improvement";
    work += !cc.work_changes.empty();
    images += !cc.image_changes.empty();
  }
  if (!c.clock_note().empty()) s << c.clock_note() << "\n";
  for (const std::string& change : c.setup_changes) s << "setup differs: " << change << "\n";
  if (const std::string blind = c.resolution_note(o); !blind.empty()) s << blind << "\n";
  s << c.cases.size() << " cases compared: " << regressions << " timing regressions, " << improvements
    << " improvements, " << work << " work changes, " << images << " image changes (alpha " << o.alpha
    << " family-wise, minimum effect " << 100 * o.min_effect << "%)\n";
  return s.str();
}

std::string comparison_markdown(const Comparison& c, const CompareOptions& o) {
  std::ostringstream s;
  const std::string blind = c.resolution_note(o);
  s << "# omnishadow compare\n\nMann-Whitney U over repetitions of " << metric_words(o.metric)
    << " per frame, Holm-corrected (alpha " << o.alpha << "), minimum effect " << 100 * o.min_effect
    << "%. Work counters compared exactly; images by checksum, "
    << "then metrics." << (c.clock_note().empty() ? "" : " " + c.clock_note() + ".")
    << (blind.empty() ? "" : " **" + blind + ".**") << "\n\n";
  if (!c.setup_changes.empty()) {
    s << "**Setup differs** (the same device, another program or path):\n\n";
    for (const auto& line : c.setup_changes) s << "- " << line << "\n";
    s << "\n";
  }
  if (!c.status_regressions.empty()) {
    s << "**Status regressions** (ok in the base, not in the new run):\n\n";
    for (const auto& line : c.status_regressions)
      s << "- `" << line.substr(0, line.find(':')) << "`" << line.substr(line.find(':')) << "\n";
    s << "\n";
  }
  if (c.cases.empty()) s << "**No case in common: the two runs compare nothing.**\n\n";
  s << "| case | base ms | new ms | change | p (Holm) | verdict | work / image changes |\n"
    << "|---|---|---|---|---|---|---|\n";
  for (const auto& cc : c.cases) {
    std::string notes;
    for (const auto& w : cc.work_changes) notes += (notes.empty() ? "" : "<br>") + w;
    for (const auto& i : cc.image_changes) notes += (notes.empty() ? "" : "<br>") + i;
    bool timed = cc.base_n && cc.new_n;
    s << "| `" << cc.id << "` | " << (timed ? fmt("%.3f", cc.base_ms) : "-") << " | "
      << (timed ? fmt("%.3f", cc.new_ms) : "-") << " | " << (timed ? fmt("%+.1f%%", 100 * cc.change) : "-")
      << " | " << (timed ? fmt("%.4f", cc.p_adjusted) : "-") << " | "
      << (cc.regressed() ? "**" + cc.verdict + "**" : cc.verdict) << " | " << notes << " |\n";
  }
  if (!c.only_in_base.empty() || !c.only_in_new.empty()) {
    s << "\nCases in one run only:\n\n";
    for (const auto& id : c.only_in_base) s << "- base only: `" << id << "`\n";
    for (const auto& id : c.only_in_new) s << "- new only: `" << id << "`\n";
  }
  return s.str();
}

nlohmann::json comparison_json(const Comparison& c, const CompareOptions& o) {
  json cases = json::array();
  for (const auto& cc : c.cases)
    cases.push_back({{"id", cc.id},
                     {"verdict", cc.verdict},
                     {"regressed", cc.regressed()},
                     {"base_ms", cc.base_ms},
                     {"new_ms", cc.new_ms},
                     {"change", cc.change},
                     {"p", cc.p},
                     {"p_adjusted", cc.p_adjusted},
                     {"base_n", cc.base_n},
                     {"new_n", cc.new_n},
                     {"resolvable", cc.resolvable},
                     {"work_changes", cc.work_changes},
                     {"image_changes", cc.image_changes}});
  return {{"alpha", o.alpha},
          {"min_effect", o.min_effect},
          {"cases", cases},
          {"status_regressions", c.status_regressions},
          {"failed", c.failed(o)},
          {"metric", o.metric},
          {"only_in_base", c.only_in_base},
          {"only_in_new", c.only_in_new},
          {"base_devices", c.base_devices},
          {"new_devices", c.new_devices},
          {"setup_changes", c.setup_changes}};
}

void apply_gate_file(const std::string& path, CompareOptions& options) {
  nlohmann::json gate;
  try {
    gate = nlohmann::json::parse(read_file(path));
  } catch (const std::exception& e) {
    throw CompareError("gate file " + path + ": cannot read it as JSON (" + std::string(e.what()) + ")");
  }
  auto number = [&](const char* field, double low, double high) {
    if (!gate.contains(field) || !gate[field].is_number())
      throw CompareError("gate file " + path + ": field '" + field + "' missing or not a number");
    const double v = gate[field].get<double>();
    if (v < low || v > high)
      throw CompareError("gate file " + path + ": field '" + field + "' out of range [" +
                         std::to_string(low) + ", " + std::to_string(high) + "]");
    return v;
  };
  options.alpha = number("alpha", 1e-9, 0.5);
  options.min_effect = number("min_effect", 0.0, 10.0);
  options.metric =
      gate.contains("metric") && gate["metric"].is_string() ? gate["metric"].get<std::string>() : "wall";
  if (options.metric != "wall" && options.metric != "cpu" && options.metric != "gpu")
    throw CompareError("gate file " + path + ": field 'metric' must be wall, cpu or gpu");
}

int compare_command(const std::string& base_path, const std::string& new_path,
                    const CompareOptions& options) {
  RunData base = load_run(base_path), fresh = load_run(new_path);
  const fs::path out_dir =
      options.out_dir.empty() ? fs::path(fresh.dir) / "compare" : fs::path(options.out_dir);
  create_writable_folder(out_dir.string(), "compare --out");  // before anything is printed
  Comparison c = compare_runs(base, fresh, options);
  if (c.base_devices != c.new_devices && !options.allow_device_mismatch) {
    std::string b, n;
    for (const auto& [k, v] : c.base_devices) b += (b.empty() ? "" : ", ") + v;
    for (const auto& [k, v] : c.new_devices) n += (n.empty() ? "" : ", ") + v;
    throw CompareError("different devices: base " + b + " vs new " + n +
                       " (timings are not comparable; --allow-device-mismatch compares anyway)");
  }
  std::cout << comparison_table(c, options);
  write_file_atomic((out_dir / "summary.md").string(), comparison_markdown(c, options));
  write_file_atomic((out_dir / "comparison.json").string(), comparison_json(c, options).dump(2) + "\n");
  std::cout << "summary: " << (out_dir / "summary.md").string() << "\n";
  return c.failed(options) ? 1 : 0;
}

}  // namespace omnishadow::bench
