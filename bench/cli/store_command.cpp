// `omnishadow store` (runs into the results database), `omnishadow fetch` (runs back out of it, as folders)
// and `omnishadow export` (a run for a dashboard).

#include <filesystem>
#include <iostream>
#include <regex>
#include <set>

#include "bench/cli/commands.h"
#include "bench/io/file_io.h"
#include "bench/io/results_reader.h"
#include "bench/report/export.h"
#include "bench/report/results_store.h"

namespace omnishadow::bench {

int store_command(const std::vector<std::string>& runs, const std::string& db) {
  try {
    ResultsStore store(db);
    for (const std::string& path : runs) {
      const StoredRun s = store.store(load_run(path));
      if (s.added)
        std::cout << "stored " << s.file << " as run " << s.run_key << ": " << s.cases << " cases, "
                  << s.measures << " measures\n";
      else if (s.completed)
        std::cout << "already stored: " << s.file << " (run " << s.run_key << "); its document and "
                  << s.images << " image hashes added (stored before schema 2)\n";
      else
        std::cout << "already stored: " << s.file << " (run " << s.run_key << "), nothing written\n";
    }
    std::cout << "store " << redacted_store_url(db) << ": schema version " << store.schema_version() << ", "
              << store.count("runs") << " runs, " << store.count("cases") << " cases\n";
    return 0;
  } catch (const std::exception& e) {
    print_error("store: " + std::string(e.what()));
    return 2;
  }
}

namespace {

namespace fs = std::filesystem;

// The stored run's folder name ("first" for /tmp/x/first/results.json), its key where that is empty or taken.
std::string folder_name(const FetchedRun& run, std::set<std::string>& taken) {
  fs::path p(run.file);
  if (p.filename() == "results.json") p = p.parent_path();
  std::string name = p.filename().string();
  if (name.empty() || name == "." || name == "..") name = run.run_key;
  if (!taken.insert(name).second) {
    name += "-" + run.run_key;
    taken.insert(name);
  }
  return name;
}

// A pattern history.py will search with Python's re: refused here when not even ECMAScript reads it (the two
// agree on everything but a few extensions), so a typo is one line now, not a traceback later.
void check_pattern(const std::string& option, const std::string& pattern) {
  if (pattern.empty()) throw std::invalid_argument(option + ": an empty pattern");
  try {
    std::regex r(pattern);
  } catch (const std::regex_error&) {
    throw std::invalid_argument(option + ": '" + pattern + "' is not a regular expression");
  }
}

// The store's accepted steps and thresholds beside the runs, in the formats history.py reads (--accepted,
// --thresholds); not run folders, so whatever looks for runs in DIR passes them by.
void write_policies(ResultsStore& store, const std::string& dir, FetchSummary& summary) {
  nlohmann::json steps = nlohmann::json::array(), thresholds = nlohmann::json::array();
  for (const AcceptedStep& a : store.accepted_steps())
    steps.push_back(
        {{"case", a.case_pattern}, {"metric", a.metric_pattern}, {"commit", a.commit}, {"reason", a.reason}});
  for (const Threshold& t : store.thresholds()) {
    nlohmann::json row = {{"device", t.device}, {"metric", t.metric}};
    if (t.alpha) row["alpha"] = *t.alpha;
    if (t.min_effect) row["min_effect"] = *t.min_effect;
    if (t.percent) row["percent"] = *t.percent;
    thresholds.push_back(row);
  }
  write_file_atomic((fs::path(dir) / "accepted_steps.json").string(),
                    nlohmann::json{{"steps", steps}}.dump(1) + "\n");
  write_file_atomic((fs::path(dir) / "thresholds.json").string(),
                    nlohmann::json{{"thresholds", thresholds}}.dump(1) + "\n");
  summary.accepted_steps = int(steps.size());
  summary.thresholds = int(thresholds.size());
}

}  // namespace

FetchSummary fetch_into(const std::string& db, const FetchFilter& filter, const std::string& dir) {
  ResultsStore store(db);
  FetchSummary summary;
  const std::vector<FetchedRun> runs = store.fetch(filter, summary.without_document);
  std::error_code made;
  fs::create_directories(dir, made);  // there even when empty: "fetched 0 runs into DIR" names a folder
  if (made) throw StoreError("cannot make " + dir + ": " + made.message());
  std::set<std::string> taken;
  for (const FetchedRun& run : runs) {
    const fs::path folder = fs::path(dir) / folder_name(run, taken);
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) throw StoreError("cannot make " + folder.string() + ": " + ec.message());
    write_file_atomic((folder / "results.json").string(), run.body);
    write_file_atomic((folder / "image_hashes.json").string(),
                      nlohmann::json(run.image_sha256).dump(1) + "\n");
    ++summary.runs;
  }
  write_policies(store, dir, summary);
  return summary;
}

int fetch_command(const std::string& db, const std::string& out, const FetchFilter& filter) {
  std::error_code ec;
  if (fs::exists(out, ec) && !(fs::is_directory(out, ec) && fs::is_empty(out, ec))) {
    print_error("fetch --out " + out + ": exists and is not an empty folder (fetch writes a fresh one)");
    return 2;
  }
  try {
    const FetchSummary f = fetch_into(db, filter, out);
    std::cout << "fetched " << f.runs << " runs from " << redacted_store_url(db)
              << (filter.device_key.empty() ? "" : " with device key " + filter.device_key)
              << (filter.commit.empty() ? "" : " of commit " + filter.commit) << " into " << out << "\n";
    if (f.without_document > 0)
      std::cout << f.without_document
                << " stored run(s) have no document (stored before schema 2): store their folders again to "
                   "add it\n";
    return 0;
  } catch (const std::exception& e) {
    print_error("fetch: " + std::string(e.what()));
    return 2;
  }
}

int accept_command(const AcceptArgs& a) {
  try {
    check_pattern("--case", a.step.case_pattern);
    check_pattern("--metric", a.step.metric_pattern);
    if (a.step.commit.empty() || a.step.reason.empty())
      throw std::invalid_argument("--commit and --reason must not be empty");
    ResultsStore store(a.db);
    store.accept(a.step);
    std::cout << "accepted in " << redacted_store_url(a.db) << ": " << a.step.metric_pattern << " of "
              << a.step.case_pattern << " at " << a.step.commit << " (" << a.step.reason << ")\n";
    return 0;
  } catch (const std::exception& e) {
    print_error("accept: " + std::string(e.what()));
    return 2;
  }
}

int threshold_command(const ThresholdArgs& a) {
  try {
    const Threshold& t = a.threshold;
    check_pattern("--device", t.device);
    check_pattern("--metric", t.metric);
    if (t.percent.has_value() == (t.alpha.has_value() || t.min_effect.has_value()))
      throw std::invalid_argument("give --percent P, or --alpha A with --min-effect E, not both or neither");
    if (!t.percent && !(t.alpha && t.min_effect))
      throw std::invalid_argument("--alpha and --min-effect go together");
    ResultsStore store(a.db);
    store.set_threshold(t);
    char rule[96];
    if (t.percent)
      std::snprintf(rule, sizeof rule, "a step of %g%% or more", *t.percent);
    else
      std::snprintf(rule, sizeof rule, "alpha %g, minimum effect %g", *t.alpha, *t.min_effect);
    std::cout << "threshold in " << redacted_store_url(a.db) << " for " << t.metric << " on " << t.device
              << ": " << rule << "\n";
    return 0;
  } catch (const std::exception& e) {
    print_error("threshold: " + std::string(e.what()));
    return 2;
  }
}

int export_command(const std::string& run, const std::string& format, const std::string& out) {
  try {
    const ExportFormat f = parse_export_format(format);
    const std::string text = export_run(load_run(run), f).dump(1) + "\n";
    if (out.empty()) {
      std::cout << text;
    } else {
      write_file_atomic(out, text);
      std::cout << "exported " << run << " as " << format << " to " << out << "\n";
    }
    return 0;
  } catch (const std::exception& e) {
    print_error("export: " + std::string(e.what()));
    return 2;
  }
}

}  // namespace omnishadow::bench
