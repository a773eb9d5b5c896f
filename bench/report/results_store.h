#pragma once
// Runs kept in a database (`omnishadow store RUN... --db URL`), through SOCI: an SQLite file on one machine
// (sqlite:PATH), a PostgreSQL server for a fleet (postgresql://...). The schema is versioned (docs/store.md):
// each migration runs once, in order, inside the transaction of the store that finds it missing. A run is
// stored in one transaction, so a crash, a full disk or a second writer leaves either the whole run or none
// of it; a run is keyed by a hash of its results.json, so storing it again changes nothing.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bench/io/results_reader.h"

namespace omnishadow::bench {

class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr const char* kDefaultStoreUrl = "sqlite:results/omnishadow.db";
// The newest schema version this binary writes (docs/store.md lists each migration).
inline constexpr int kStoreSchemaVersion = 3;

// What one store did: the run's key, and whether it was new (false: already stored, nothing written).
struct StoredRun {
  std::string file;
  std::string run_key;
  bool added = false;
  bool completed = false;  // already stored, under schema 1: its document and image hashes added now
  int cases = 0;
  int measures = 0;
  int images = 0;
};

// A stored run as fetch gives it back: its results.json as stored, and its images' hashes.
struct FetchedRun {
  std::string run_key;
  std::string file;  // as given to `store`
  std::string commit_date;
  std::string body;                                 // the results.json
  std::map<std::string, std::string> image_sha256;  // image path (relative to the run folder) -> SHA-256
};

// Which stored runs fetch gives back: those with a device of this key, of this commit (a prefix will do);
// empty: any.
struct FetchFilter {
  std::string device_key, commit;
};

// A step someone judged meant (`omnishadow accept`): alerts on cases and metrics matching the patterns
// (Python regular expressions, searched) at that commit stop, as results/accepted_steps.json's rows do.
struct AcceptedStep {
  std::string case_pattern, metric_pattern, commit, reason;
};

// What counts as a step for one metric pattern on one device pattern (`omnishadow threshold`): a significance
// test's alpha and minimum effect (timings), or a fixed percentage (any metric: a smaller change is no step).
struct Threshold {
  std::string device, metric;
  std::optional<double> alpha, min_effect, percent;
};

class ResultsStore {
 public:
  // Opens (creating an SQLite file, and migrating the schema). Throws StoreError with one line naming the URL
  // on a URL it cannot read, a server it cannot reach or a database it cannot open.
  explicit ResultsStore(const std::string& url);
  ~ResultsStore();
  ResultsStore(const ResultsStore&) = delete;
  ResultsStore& operator=(const ResultsStore&) = delete;

  // One run, in one transaction. Throws StoreError naming the file and the cause (a locked database, a full
  // disk); nothing of the run is then stored.
  StoredRun store(const RunData& run);
  int schema_version();
  // Every run stored with its document that the filter lets through, oldest commit first (runs of one commit
  // by key). `without_document`: runs stored under schema 1, which have none.
  std::vector<FetchedRun> fetch(const FetchFilter& filter, int& without_document);
  // Each in a transaction of its own; accepting a step or setting a threshold again replaces its reason or
  // values.
  void accept(const AcceptedStep& step);
  void set_threshold(const Threshold& threshold);
  std::vector<AcceptedStep> accepted_steps();
  std::vector<Threshold> thresholds();
  // Rows of a table (tests, `store` summary): runs, cases, measures.
  long long count(const std::string& table);

 private:
  struct Impl;
  Impl* impl_;
  std::string url_;
};

// The URL as messages may show it: a password (postgresql://user:PASSWORD@host, ?password=...) as ***.
std::string redacted_store_url(const std::string& url);

// A content key of a results file: 16 hex digits of a 64-bit FNV-1a over its bytes.
std::string run_key_of(const std::string& text);

}  // namespace omnishadow::bench
