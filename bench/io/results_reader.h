#pragma once
// Reading results.json back (compare, merge, device-key): the whole document is checked against the shape the
// writer produces before anyone indexes into it, so a truncated, foreign or hand-edited file is one line
// naming the file and the JSON pointer, never an exception from deep inside nlohmann or a read of a missing
// key.

#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace omnishadow::bench {

class CompareError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Google Benchmark writes non-JSON tokens (NaN, inf, -inf) for aggregates such as the coefficient of
// variation of a counter that is 0 in every repetition; they are read as null. Only bare tokens outside
// strings are touched.
nlohmann::json parse_gbench_json(const std::string& text);

// A results file, or a run folder holding results.json.
struct RunData {
  std::string dir;   // folder that image paths are relative to
  std::string file;  // the results.json read
  nlohmann::json doc;
  std::map<std::string, const nlohmann::json*> cases;  // by case id, pointing into doc
  std::map<std::string, std::vector<double>>
      samples;  // per case: mean frame wall time of each repetition, ms
  std::map<std::string, std::vector<double>> cpu_samples;  // per case: mean process CPU time per frame, ms
  // Per case: mean GPU time per frame (shadow + lighting passes, timer/timestamp queries), ms; only
  // repetitions whose GPU timer passed its sanity check (gpu_timer_reliable), as only they carry the pass
  // times.
  std::map<std::string, std::vector<double>> gpu_samples;
};

// Throws CompareError naming the file (and the JSON pointer) on anything that is not an omnishadow results
// file.
RunData load_run(const std::string& path);
// Same for text already in memory; `file` names errors, `dir` is where image paths resolve.
RunData parse_run(const std::string& text, const std::string& file, const std::string& dir);

}  // namespace omnishadow::bench
