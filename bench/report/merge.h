#pragma once
// `omnishadow merge OUT RUN...`: joins the results of shards (`run --shard i/N`) into one results.json in
// OUT, with image paths rewritten relative to OUT, so that compare works on the merged run.

#include <string>
#include <vector>

namespace omnishadow::bench {

// What a merge joined: whole, or not and why (shards missing, inputs that were themselves incomplete).
struct MergeResult {
  bool complete = true;
  std::vector<int> missing_shards;
  std::vector<std::string> incomplete_inputs;  // results files whose run was stopped or was partial
  std::string describe() const;                // "shard 1 of 2 missing; a/results.json incomplete (stopped)"
};

// Throws CompareError on unreadable inputs, a case in two shards, a shard given twice or shards of different
// counts, or one backend on two different devices. Shards missing from 0..N-1 make the merged run incomplete
// ("complete": false, "missing_shards"), and compare then fails on the cases they held.
MergeResult merge_runs(const std::string& out_dir, const std::vector<std::string>& runs);

}  // namespace omnishadow::bench
