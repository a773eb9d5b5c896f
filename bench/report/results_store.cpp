#include "bench/report/results_store.h"

#include <soci/postgresql/soci-postgresql.h>
#include <soci/soci.h>
#include <soci/sqlite3/soci-sqlite3.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <regex>
#include <set>

#include "bench/io/file_io.h"
#include "bench/report/compare.h"

namespace omnishadow::bench {

using nlohmann::json;

namespace {

// Each migration's statements, in order; version k is kMigrations[k - 1]. The SQL is what SQLite and
// PostgreSQL both read (TEXT, INTEGER, DOUBLE PRECISION, composite primary keys). Never edit a published
// migration: add the next one.
struct Migration {
  const char* description;
  std::vector<const char*> statements;
};
const std::vector<Migration> kMigrations = {
    {"runs, their devices, cases with their axes and statuses, every measure, every finding",
     {"CREATE TABLE runs (run_key TEXT PRIMARY KEY, file TEXT NOT NULL, format TEXT NOT NULL, commit_sha "
      "TEXT "
      "NOT NULL, commit_date TEXT NOT NULL, command_line TEXT NOT NULL, shard_index INTEGER NOT NULL, "
      "shard_count INTEGER NOT NULL, complete INTEGER NOT NULL)",
      "CREATE TABLE devices (run_key TEXT NOT NULL, backend TEXT NOT NULL, device_key TEXT NOT NULL, api "
      "TEXT "
      "NOT NULL, renderer TEXT NOT NULL, version TEXT NOT NULL, PRIMARY KEY (run_key, backend))",
      "CREATE TABLE cases (run_key TEXT NOT NULL, case_id TEXT NOT NULL, backend TEXT NOT NULL, status TEXT "
      "NOT "
      "NULL, reason TEXT NOT NULL, axes TEXT NOT NULL, PRIMARY KEY (run_key, case_id))",
      "CREATE INDEX cases_by_id ON cases (case_id)",
      "CREATE TABLE measures (run_key TEXT NOT NULL, case_id TEXT NOT NULL, metric TEXT NOT NULL, repetition "
      "INTEGER NOT NULL, value DOUBLE PRECISION NOT NULL, PRIMARY KEY (run_key, case_id, metric, "
      "repetition))",
      "CREATE TABLE findings (run_key TEXT NOT NULL, case_id TEXT NOT NULL, seq INTEGER NOT NULL, check_name "
      "TEXT NOT NULL, status TEXT NOT NULL, message TEXT NOT NULL, PRIMARY KEY (run_key, case_id, seq))"}},
    {"each run's results.json whole (fetch, history --db and report --db read it back), and the SHA-256 of "
     "every image file the run wrote",
     {"CREATE TABLE documents (run_key TEXT PRIMARY KEY, body TEXT NOT NULL)",
      "CREATE TABLE images (run_key TEXT NOT NULL, case_id TEXT NOT NULL, role TEXT NOT NULL, path TEXT NOT "
      "NULL, sha256 TEXT NOT NULL, PRIMARY KEY (run_key, case_id, role))"}},
    {"thresholds per device and metric, and the accepted steps, which history --db and alerts read",
     {"CREATE TABLE thresholds (device TEXT NOT NULL, metric TEXT NOT NULL, alpha DOUBLE PRECISION, "
      "min_effect "
      "DOUBLE PRECISION, percent DOUBLE PRECISION, PRIMARY KEY (device, metric))",
      "CREATE TABLE accepted_steps (case_pattern TEXT NOT NULL, metric_pattern TEXT NOT NULL, commit_sha "
      "TEXT "
      "NOT NULL, reason TEXT NOT NULL, PRIMARY KEY (case_pattern, metric_pattern, commit_sha))"}},
};

// sqlite:PATH[?timeout=S] (the file, its folder created; how long a writer waits for another's lock, 60 s by
// default), or postgresql://... / postgres://... (libpq's URI, as is).
struct Target {
  bool sqlite = true;
  std::string connect;
};
Target parse_url(const std::string& url) {
  if (url.rfind("sqlite:", 0) == 0) {
    std::string path = url.substr(7), timeout = "60";
    if (const size_t q = path.rfind("?timeout="); q != std::string::npos) {
      timeout = path.substr(q + 9);
      path.resize(q);
      if (timeout.empty() || timeout.size() > 6 ||
          timeout.find_first_not_of("0123456789") != std::string::npos)
        throw StoreError("--db " + url + ": timeout=" + timeout + " is not a whole number of seconds");
    }
    if (path.empty()) throw StoreError("--db " + url + ": no file after sqlite:");
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    // timeout: a second writer (a fleet's shards stored at once) waits for the first's transaction.
    return {true, "db=\"" + path + "\" timeout=" + timeout};
  }
  if (url.rfind("postgresql://", 0) == 0 || url.rfind("postgres://", 0) == 0) return {false, url};
  throw StoreError("--db " + redacted_store_url(url) +
                   ": not sqlite:PATH or postgresql://USER@HOST:PORT/DATABASE");
}

// The numbers a case reports once (accuracy, counters, staleness, what was rendered), as metric names of
// their JSON paths ("accuracy.misclassified_percent"); arrays (per light, per frame) are left to
// results.json.
void numeric_leaves(const json& j, const std::string& prefix,
                    std::vector<std::pair<std::string, double>>& out) {
  if (j.is_number()) {
    out.emplace_back(prefix, j.get<double>());
  } else if (j.is_object()) {
    for (const auto& [key, value] : j.items()) numeric_leaves(value, prefix + "." + key, out);
  }
}

}  // namespace

std::string redacted_store_url(const std::string& url) {
  static const std::regex user_password(R"((://[^:/@?]*:)[^@/]*@)"), parameter(R"((password=)[^&\s]*)");
  return std::regex_replace(std::regex_replace(url, user_password, "$1***@"), parameter, "$1***");
}

std::string run_key_of(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

struct ResultsStore::Impl {
  bool sqlite = true;
  soci::session sql;
};

ResultsStore::ResultsStore(const std::string& url) : impl_(new Impl), url_(redacted_store_url(url)) {
  try {
    const Target t = parse_url(url);
    impl_->sqlite = t.sqlite;
    impl_->sql.open(t.sqlite ? *soci::factory_sqlite3() : *soci::factory_postgresql(), t.connect);
  } catch (const StoreError&) {
    delete impl_;
    throw;
  } catch (const std::exception& e) {
    delete impl_;
    std::string what = e.what();
    what = what.substr(0, what.find('\n'));
    throw StoreError("--db " + redacted_store_url(url) + ": cannot open: " + what);
  }
}

ResultsStore::~ResultsStore() { delete impl_; }

namespace {

// Writers take turns: SQLite's BEGIN IMMEDIATE takes the write lock at once (a deferred transaction that
// reads first could not upgrade while another writes), PostgreSQL's transaction-scoped advisory lock keeps
// two stores from migrating or adding one run at the same time.
void begin_exclusive(soci::session& sql, bool sqlite) {
  if (sqlite) {
    sql << "BEGIN IMMEDIATE";
  } else {
    sql << "BEGIN";
    sql << "SELECT pg_advisory_xact_lock(7340001)";
  }
}

int current_version(soci::session& sql) {
  sql << "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, description TEXT NOT "
         "NULL)";
  int version = 0;
  soci::indicator ind = soci::i_ok;
  sql << "SELECT MAX(version) FROM schema_migrations", soci::into(version, ind);
  return ind == soci::i_null ? 0 : version;
}

void migrate(soci::session& sql) {
  for (int v = current_version(sql); v < int(kMigrations.size()); ++v) {
    for (const char* statement : kMigrations[size_t(v)].statements) sql << statement;
    const int version = v + 1;
    const std::string description = kMigrations[size_t(v)].description;
    sql << "INSERT INTO schema_migrations (version, description) VALUES (:v, :d)", soci::use(version),
        soci::use(description);
  }
}

struct Rows {
  std::vector<std::string> case_id, metric;
  std::vector<int> repetition;
  std::vector<double> value;
  void add(const std::string& id, const std::string& m, int rep, double v) {
    case_id.push_back(id), metric.push_back(m), repetition.push_back(rep), value.push_back(v);
  }
};

// Every case's per-repetition times and its once-reported figures.
Rows measures_of(const RunData& run) {
  Rows rows;
  auto series = [&](const std::map<std::string, std::vector<double>>& by_case, const char* metric) {
    for (const auto& [id, values] : by_case)
      for (size_t i = 0; i < values.size(); ++i) rows.add(id, metric, int(i), values[i]);
  };
  series(run.samples, "frame_ms");
  series(run.cpu_samples, "frame_cpu_ms");
  series(run.gpu_samples, "frame_gpu_ms");
  for (const auto& [id, c] : run.cases) {
    std::vector<std::pair<std::string, double>> leaves;
    // "timing": every statistic of the frame's and each pass's times (timing.shadow.gpu_ms.p90, ...).
    for (const char* section : {"accuracy", "counters", "staleness", "timing"})
      if (c->contains(section)) numeric_leaves((*c)[section], section, leaves);
    // The device's clock before and after each repetition, sample by sample (the repetition column counts
    // samples here).
    if (c->contains("device_state") && (*c)["device_state"].contains("samples") &&
        (*c)["device_state"]["samples"].is_array()) {
      int sample = 0;
      for (const json& d : (*c)["device_state"]["samples"]) {
        if (d.contains("clock_mhz") && d["clock_mhz"].is_number())
          rows.add(id, "device_state.clock_mhz", sample, d["clock_mhz"].get<double>());
        ++sample;
      }
    }
    if (c->contains("shadow_plan") && (*c)["shadow_plan"].contains("rendered"))
      numeric_leaves((*c)["shadow_plan"]["rendered"], "rendered", leaves);
    for (const auto& [metric, value] : leaves) rows.add(id, metric, -1, value);
  }
  return rows;
}

// The run's results.json whole, and the hash of every image it names that is there (--images none writes
// none; a folder copied without its images keeps its document).
void insert_document(soci::session& sql, const RunData& run, const std::string& key, StoredRun& out) {
  const std::string body = run.doc.dump();
  sql << "INSERT INTO documents (run_key, body) VALUES (:k, :b)", soci::use(key), soci::use(body);
  std::vector<std::string> ids, roles, paths, hashes;
  for (const auto& [id, c] : run.cases) {
    if (!c->contains("images") || !(*c)["images"].is_object()) continue;
    for (const auto& [role, relative] : (*c)["images"].items()) {
      if (!relative.is_string()) continue;
      const std::string hash =
          sha256_hex_of_file((std::filesystem::path(run.dir) / relative.get<std::string>()).string());
      if (hash.empty()) continue;
      ids.push_back(id), roles.push_back(role), paths.push_back(relative.get<std::string>());
      hashes.push_back(hash);
    }
  }
  const std::vector<std::string> keys(ids.size(), key);
  if (!ids.empty())
    sql << "INSERT INTO images (run_key, case_id, role, path, sha256) VALUES (:k, :i, :r, :p, :h)",
        soci::use(keys), soci::use(ids), soci::use(roles), soci::use(paths), soci::use(hashes);
  out.images = int(ids.size());
}

void insert_run(soci::session& sql, const RunData& run, const std::string& key, StoredRun& out) {
  const json& o = run.doc["omnishadow"];
  const std::string format = o.value("format", ""), commit = o.value("commit", ""),
                    date = o.value("commit_date", ""), command = o.value("command_line", "");
  const int shard_index = o.contains("shard") ? o["shard"].value("index", 0) : 0;
  const int shard_count = o.contains("shard") ? o["shard"].value("count", 1) : 1;
  const int complete = o.value("complete", false) ? 1 : 0;
  sql << "INSERT INTO runs (run_key, file, format, commit_sha, commit_date, command_line, shard_index, "
         "shard_count, complete) VALUES (:k, :f, :fm, :c, :d, :cl, :si, :sc, :co)",
      soci::use(key), soci::use(run.file), soci::use(format), soci::use(commit), soci::use(date),
      soci::use(command), soci::use(shard_index), soci::use(shard_count), soci::use(complete);
  const std::map<std::string, std::string> keys = device_keys(run);
  if (o.contains("devices") && o["devices"].is_object())
    for (const auto& [backend, d] : o["devices"].items()) {
      const std::string device_key = keys.count(backend) ? keys.at(backend) : backend;
      const std::string api = d.value("api", ""), renderer = d.value("renderer", ""),
                        version = d.value("version", "");
      sql << "INSERT INTO devices (run_key, backend, device_key, api, renderer, version) VALUES (:k, :b, "
             ":dk, "
             ":a, :r, :v)",
          soci::use(key), soci::use(backend), soci::use(device_key), soci::use(api), soci::use(renderer),
          soci::use(version);
    }
  std::vector<std::string> ids, backends, statuses, reasons, axes;
  std::vector<std::string> f_ids, f_checks, f_statuses, f_messages;
  std::vector<int> f_seq;
  for (const auto& [id, c] : run.cases) {
    ids.push_back(id);
    backends.push_back(id.substr(0, id.find('/')));
    statuses.push_back(c->value("status", ""));
    reasons.push_back(c->value("reason", ""));
    axes.push_back(c->contains("axes") ? (*c)["axes"].dump() : "{}");
    if (!c->contains("findings") || !(*c)["findings"].is_array()) continue;
    int seq = 0;
    for (const json& f : (*c)["findings"]) {
      f_ids.push_back(id), f_seq.push_back(seq++), f_checks.push_back(f.value("check", ""));
      f_statuses.push_back(f.value("status", "")), f_messages.push_back(f.value("message", ""));
    }
  }
  const std::vector<std::string> run_keys(ids.size(), key), f_keys(f_ids.size(), key);
  if (!ids.empty())
    sql << "INSERT INTO cases (run_key, case_id, backend, status, reason, axes) VALUES (:k, :i, :b, :s, :r, "
           ":a)",
        soci::use(run_keys), soci::use(ids), soci::use(backends), soci::use(statuses), soci::use(reasons),
        soci::use(axes);
  if (!f_ids.empty())
    sql << "INSERT INTO findings (run_key, case_id, seq, check_name, status, message) VALUES (:k, :i, :q, "
           ":c, "
           ":s, :m)",
        soci::use(f_keys), soci::use(f_ids), soci::use(f_seq), soci::use(f_checks), soci::use(f_statuses),
        soci::use(f_messages);
  Rows m = measures_of(run);
  const std::vector<std::string> m_keys(m.case_id.size(), key);
  if (!m.case_id.empty())
    sql << "INSERT INTO measures (run_key, case_id, metric, repetition, value) VALUES (:k, :i, :m, :r, :v)",
        soci::use(m_keys), soci::use(m.case_id), soci::use(m.metric), soci::use(m.repetition),
        soci::use(m.value);
  out.cases = int(ids.size());
  out.measures = int(m.case_id.size());
}

// Runs `body` in a transaction of its own (migrated first). On any failure it is rolled back and the store
// says one line: `what`, then the cause's first line.
template <typename Body>
void in_transaction(soci::session& sql, bool sqlite, const std::string& what, Body body) {
  try {
    begin_exclusive(sql, sqlite);
    migrate(sql);
    body();
    sql << "COMMIT";
  } catch (const std::exception& e) {
    try {
      sql << "ROLLBACK";
    } catch (const std::exception&) {  // the connection may be gone; the server rolls back itself then
    }
    std::string message = e.what();
    throw StoreError(what + ": " + message.substr(0, message.find('\n')));
  }
}

}  // namespace

StoredRun ResultsStore::store(const RunData& run) {
  StoredRun out;
  out.file = run.file;
  out.run_key = run_key_of(run.doc.dump());
  soci::session& sql = impl_->sql;
  in_transaction(sql, impl_->sqlite, run.file + ": not stored in " + url_ + " (nothing of it written)", [&] {
    int present = 0;
    sql << "SELECT COUNT(*) FROM runs WHERE run_key = :k", soci::use(out.run_key), soci::into(present);
    if (present == 0) {
      insert_run(sql, run, out.run_key, out);
      insert_document(sql, run, out.run_key, out);
      out.added = true;
      return;
    }
    int documents = 0;  // a run stored under schema 1 gets its document and image hashes now
    sql << "SELECT COUNT(*) FROM documents WHERE run_key = :k", soci::use(out.run_key), soci::into(documents);
    if (documents == 0) {
      insert_document(sql, run, out.run_key, out);
      out.completed = true;
    }
  });
  return out;
}

int ResultsStore::schema_version() {
  int v = 0;
  in_transaction(impl_->sql, impl_->sqlite, "cannot migrate " + url_,
                 [&] { v = current_version(impl_->sql); });
  return v;
}

long long ResultsStore::count(const std::string& table) {
  static const std::set<std::string> tables = {"runs",    "cases",     "measures", "findings",
                                               "devices", "documents", "images"};
  if (!tables.count(table)) throw StoreError("no table " + table);
  long long n = 0;
  impl_->sql << "SELECT COUNT(*) FROM " + table, soci::into(n);
  return n;
}

std::vector<FetchedRun> ResultsStore::fetch(const FetchFilter& filter, int& without_document) {
  schema_version();  // migrated first: a store made by an older binary reads as empty, not as an error
  soci::session& sql = impl_->sql;
  std::vector<FetchedRun> runs;
  try {
    // Every run when no device key or commit is asked for; both are bound either way (one statement). A
    // commit matches when one is a prefix of the other (runs record 12 digits; git gives 40), of 7 digits at
    // least (substr and length mean the same in SQLite and PostgreSQL).
    soci::rowset<soci::row> rows =
        (sql.prepare
             << "SELECT r.run_key, r.file, r.commit_date, d.body FROM runs r JOIN documents d ON "
                "d.run_key = r.run_key WHERE (:dk = '' OR EXISTS (SELECT 1 FROM devices v WHERE "
                "v.run_key = r.run_key AND v.device_key = :dk2)) AND (:c = '' OR (length(r.commit_sha) >= 7 "
                "AND length(:c2) >= 7 AND (substr(:c3, 1, length(r.commit_sha)) = r.commit_sha OR "
                "substr(r.commit_sha, 1, length(:c4)) = :c5))) ORDER BY r.commit_date, r.run_key",
         soci::use(filter.device_key), soci::use(filter.device_key), soci::use(filter.commit),
         soci::use(filter.commit), soci::use(filter.commit), soci::use(filter.commit),
         soci::use(filter.commit));
    for (const soci::row& row : rows)
      runs.push_back({row.get<std::string>(0),
                      row.get<std::string>(1),
                      row.get<std::string>(2),
                      row.get<std::string>(3),
                      {}});
    for (FetchedRun& run : runs) {
      soci::rowset<soci::row> images =
          (sql.prepare << "SELECT path, sha256 FROM images WHERE run_key = :k", soci::use(run.run_key));
      for (const soci::row& row : images) run.image_sha256[row.get<std::string>(0)] = row.get<std::string>(1);
    }
    long long all = 0, with_document = 0;
    sql << "SELECT COUNT(*) FROM runs", soci::into(all);
    sql << "SELECT COUNT(*) FROM documents", soci::into(with_document);
    without_document = int(all - with_document);
  } catch (const std::exception& e) {
    std::string what = e.what();
    throw StoreError("cannot read " + url_ + ": " + what.substr(0, what.find('\n')));
  }
  return runs;
}

namespace {

std::optional<double> optional_double(const soci::row& row, size_t i) {
  if (row.get_indicator(i) == soci::i_null) return std::nullopt;
  return row.get<double>(i);
}

}  // namespace

void ResultsStore::accept(const AcceptedStep& step) {
  soci::session& sql = impl_->sql;
  in_transaction(sql, impl_->sqlite, "cannot accept the step in " + url_, [&] {
    sql << "INSERT INTO accepted_steps (case_pattern, metric_pattern, commit_sha, reason) VALUES (:c, :m, "
           ":s, "
           ":r) ON CONFLICT (case_pattern, metric_pattern, commit_sha) DO UPDATE SET reason = "
           "excluded.reason",
        soci::use(step.case_pattern), soci::use(step.metric_pattern), soci::use(step.commit),
        soci::use(step.reason);
  });
}

void ResultsStore::set_threshold(const Threshold& t) {
  soci::session& sql = impl_->sql;
  double alpha = t.alpha.value_or(0.0), min_effect = t.min_effect.value_or(0.0),
         percent = t.percent.value_or(0.0);
  soci::indicator a = t.alpha ? soci::i_ok : soci::i_null, m = t.min_effect ? soci::i_ok : soci::i_null,
                  p = t.percent ? soci::i_ok : soci::i_null;
  in_transaction(sql, impl_->sqlite, "cannot set the threshold in " + url_, [&] {
    sql << "INSERT INTO thresholds (device, metric, alpha, min_effect, percent) VALUES (:d, :m, :a, :e, :p) "
           "ON "
           "CONFLICT (device, metric) DO UPDATE SET alpha = excluded.alpha, min_effect = "
           "excluded.min_effect, "
           "percent = excluded.percent",
        soci::use(t.device), soci::use(t.metric), soci::use(alpha, a), soci::use(min_effect, m),
        soci::use(percent, p);
  });
}

std::vector<AcceptedStep> ResultsStore::accepted_steps() {
  std::vector<AcceptedStep> out;
  soci::session& sql = impl_->sql;
  in_transaction(sql, impl_->sqlite, "cannot read the accepted steps in " + url_, [&] {
    soci::rowset<soci::row> rows =
        (sql.prepare << "SELECT case_pattern, metric_pattern, commit_sha, reason FROM "
                        "accepted_steps ORDER BY commit_sha, case_pattern, metric_pattern");
    for (const soci::row& r : rows)
      out.push_back(
          {r.get<std::string>(0), r.get<std::string>(1), r.get<std::string>(2), r.get<std::string>(3)});
  });
  return out;
}

std::vector<Threshold> ResultsStore::thresholds() {
  std::vector<Threshold> out;
  soci::session& sql = impl_->sql;
  in_transaction(sql, impl_->sqlite, "cannot read the thresholds in " + url_, [&] {
    soci::rowset<soci::row> rows =
        (sql.prepare
         << "SELECT device, metric, alpha, min_effect, percent FROM thresholds ORDER BY device, metric");
    for (const soci::row& r : rows)
      out.push_back({r.get<std::string>(0), r.get<std::string>(1), optional_double(r, 2),
                     optional_double(r, 3), optional_double(r, 4)});
  });
  return out;
}

}  // namespace omnishadow::bench
