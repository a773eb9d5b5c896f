#pragma once
// A crashing driver costs one case (deqp-runner and piglit run their tests this way). `omnishadow run`
// supervises: it runs the matrix in a worker process (this binary again, with --worker-* flags), which names
// on a pipe each case and step before it starts them (bench/run/case_progress.h). When the worker dies by a
// signal (a driver's SIGSEGV or abort) or says nothing for --case-timeout-s (a hang; then it is killed), the
// case it was in is recorded `crashed` with the signal or the timeout and the step, and a fresh worker goes
// on from the next case in matrix order. The first worker writes OUT/results.json as a run without isolation
// does (each case saved as it finishes); after a crash each part is kept under OUT/.parts/ and at the end
// they are merged into OUT/results.json: every finished case, the crashed ones in their matrix places. Exit 1
// when a case crashed.
//
// A case whose worker died by a signal runs again, first in a fresh worker, up to crash_retries times, as
// deqp-runner runs a failure again to tell a flaky driver from a broken one: a case that then finishes keeps
// that attempt's result with `crashed_before` (each earlier attempt's signal and step), is listed as flaky
// and costs the run nothing; one that dies every time is `crashed`. A hang is not run again: each attempt
// would cost --case-timeout-s.
#include <string>
#include <vector>

namespace omnishadow::bench {

struct IsolationSettings {
  std::vector<std::string> args;  // this process's arguments after the program name ("run", then the options)
  std::string out_dir;            // the run's folder (given or the default one), passed to every worker
  double case_timeout_s = 300.0;  // no progress line for this long: the worker is killed, the case crashed
  int crash_retries = 1;          // attempts after the first at a case whose worker died by a signal
  bool check = false;             // --check: a kept case that failed makes the run exit 1
};

// Runs the matrix in worker processes as above and returns the run's exit code.
int supervise_run(const IsolationSettings& settings);

// The arguments a worker adds to the user's (skipped when recording the command line in results.json).
bool is_worker_argument(const std::string& arg);

}  // namespace omnishadow::bench
