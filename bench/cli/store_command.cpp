// `omnishadow store` (runs into the results database), `omnishadow fetch` (runs back out of it, as folders)
// and `omnishadow export` (a run for a dashboard).

#include <filesystem>
#include <iostream>
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

}  // namespace

FetchSummary fetch_into(const std::string& db, const std::string& device_key, const std::string& dir) {
  ResultsStore store(db);
  FetchSummary summary;
  const std::vector<FetchedRun> runs = store.fetch(device_key, summary.without_document);
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
  return summary;
}

int fetch_command(const std::string& db, const std::string& out, const std::string& device_key) {
  std::error_code ec;
  if (fs::exists(out, ec) && !(fs::is_directory(out, ec) && fs::is_empty(out, ec))) {
    print_error("fetch --out " + out + ": exists and is not an empty folder (fetch writes a fresh one)");
    return 2;
  }
  try {
    const FetchSummary f = fetch_into(db, device_key, out);
    std::cout << "fetched " << f.runs << " runs from " << redacted_store_url(db)
              << (device_key.empty() ? "" : " with device key " + device_key) << " into " << out << "\n";
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
