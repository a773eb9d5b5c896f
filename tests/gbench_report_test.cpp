// Google Benchmark's console context as omnishadow prints it (bench/run/gbench_report.h): a warning that does
// not apply is explained once, never passed on.
#include "bench/run/gbench_report.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace omnishadow::bench {
namespace {

TEST(GbenchReport, TheDebugLibraryWarningIsExplained) {
  const std::string context =
      "Run on (2 X 2000 MHz CPU s)\n***WARNING*** Library was built as DEBUG. Timings may be affected.\nLoad "
      "Average: 1.00, 0.50, 0.25\n";
  const std::string out = explain_debug_library(context);
  EXPECT_EQ(out.find(kDebugLibraryWarning), std::string::npos) << out;
  EXPECT_NE(out.find(kDebugLibraryNote), std::string::npos) << out;
  EXPECT_NE(out.find("Run on (2 X 2000 MHz CPU s)\n"), std::string::npos) << "other lines kept";
  EXPECT_NE(out.find("Load Average: 1.00"), std::string::npos);
  EXPECT_EQ(explain_debug_library("Run on (2 X 2000 MHz CPU s)\n"), "Run on (2 X 2000 MHz CPU s)\n");

  // The reporter itself, whatever this machine's libbenchmark prints (Debian's is built without NDEBUG).
  RoundReporter reporter;
  std::ostringstream printed, errors;
  reporter.SetOutputStream(&printed);
  reporter.SetErrorStream(&errors);
  ASSERT_TRUE(reporter.ReportContext(benchmark::BenchmarkReporter::Context()));
  EXPECT_EQ(errors.str().find(kDebugLibraryWarning), std::string::npos) << errors.str();
  EXPECT_EQ(printed.str().find(kDebugLibraryWarning), std::string::npos) << printed.str();
  EXPECT_NE(errors.str().find("Run on"), std::string::npos) << "the context itself still printed";
}

}  // namespace
}  // namespace omnishadow::bench
