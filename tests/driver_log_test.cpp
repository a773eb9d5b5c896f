#include "backends/common/driver_log.h"

#include <gtest/gtest.h>

namespace omnishadow {
namespace {

// NVIDIA's link log for the passthrough GS (gpu/measured/h100-fb5456a): the message is on the third line.
TEST(DriverLog, KeepsTheMessageAfterAHeaderAndASeparatorLine) {
  const std::string log =
      "Link info\n---------\nmax_vertices layout qualifier must be declared in at least one of the GLSL "
      "geometry "
      "shaders\n";
  EXPECT_EQ(one_line_log(log),
            "Link info | max_vertices layout qualifier must be declared in at least one of the GLSL geometry "
            "shaders");
}

TEST(DriverLog, KeepsEveryCompilerMessageInOrderAndStopsAtTheTerminator) {
  const std::string log =
      std::string(
          "0(50) : error C0000: syntax error\r\n\n  0(56) : error C1503: undefined variable "
          "\"corners\"  \n") +
      '\0' + "garbage after the terminator";
  EXPECT_EQ(one_line_log(log),
            "0(50) : error C0000: syntax error | 0(56) : error C1503: undefined variable \"corners\"");
}

TEST(DriverLog, BoundsALongLogAndSaysHowMuchWasLeftOut) {
  std::string log;
  for (int i = 0; i < 500; ++i) log += "0(" + std::to_string(i) + ") : error: something\n";
  const std::string line = one_line_log(log, 100);
  EXPECT_EQ(line.substr(0, 100), one_line_log(log).substr(0, 100));
  const size_t whole = one_line_log(log, 1000000).size();
  EXPECT_EQ(line.substr(100), " ... (" + std::to_string(whole - 100) + " more characters)");
}

TEST(DriverLog, JoinsEveryValidationMessageAndNamesAnEmptyLog) {
  EXPECT_EQ(one_line_log(std::vector<std::string>{"first\nsecond", "third"}), "first | second | third");
  EXPECT_EQ(one_line_log(std::string_view("\n---\n")), "(no log)");
  EXPECT_EQ(one_line_log(std::vector<std::string>{}), "(no log)");
}

}  // namespace
}  // namespace omnishadow
