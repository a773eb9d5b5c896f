// `omnishadow store` (runs into the results database) and `omnishadow export` (a run for a dashboard).

#include <iostream>

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
