#pragma once
// What a run in a worker process tells the process that supervises it (bench/cli/case_isolation.h), one line
// a message on a pipe, before the thing it names starts: so when the worker dies or stops making progress,
// the supervisor knows the case and the step it had reached. And the test-only faults that show it
// (--inject-crash,
// --inject-hang): a SIGSEGV, or a wait that never ends, where a driver's crash or hang would strike.
//
// Lines: "cases N" (the worker's case count, after the matrix is validated), "case ID<TAB>AXES-JSON" (its
// checks begin), "step NAME" (a step of the checks begins), "timed ID" (a timed repetition begins).
#include <string>

namespace omnishadow::bench {

struct RunOptions;

// Sends one line to the supervisor; nothing when this process has none (fd < 0).
void send_progress(int fd, const std::string& line);

// In a worker: a fatal signal (SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT) first prints one line naming it and
// the native frames to stderr (innermost first, each with its library: a driver's own name libnvidia-* and
// the like), then kills the process by the same signal, so the supervisor records the case as before.
void report_fatal_signals();

// The test-only faults: when `id` matches --inject-crash (--inject-hang) and `timed` is where --inject-in
// puts them, raises SIGSEGV (waits forever). Nothing otherwise.
void inject_fault(const RunOptions& o, const std::string& id, bool timed);

}  // namespace omnishadow::bench
