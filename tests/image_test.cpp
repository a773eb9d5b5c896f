// Image comparison and file formats.

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <filesystem>

#include "bench/io/file_io.h"
#include "bench/io/image_io.h"
#include "bench/truth/image_compare.h"

namespace omnishadow::bench {
namespace {

TEST(ImageCompare, CountsValuesBeyondTheTolerance) {
  std::vector<float> a = {0, 1, 2, FLT_MAX, 4}, b = {0, 1.5f, 2, FLT_MAX, 4.01f};
  Difference exact = compare_values(a, b, 0.0);
  EXPECT_EQ(exact.total, 5u);
  EXPECT_EQ(exact.differing, 2u);
  EXPECT_FLOAT_EQ(static_cast<float>(exact.max_abs), 0.5f);
  EXPECT_DOUBLE_EQ(exact.percent_differing(), 40.0);
  EXPECT_EQ(compare_values(a, b, 0.1).differing, 1u);
  std::vector<float> nan = {0, 1, 2, NAN, 4};
  EXPECT_TRUE(std::isinf(compare_values(a, nan, 0.0).max_abs));
  EXPECT_THROW(compare_values(a, std::vector<float>(3), 0.0), std::invalid_argument);
}

TEST(ImageCompare, Bytes) {
  std::vector<uint8_t> a = {0, 10, 255}, b = {0, 12, 250};
  Difference d = compare_values(a, b, 2.0);
  EXPECT_EQ(d.differing, 1u);
  EXPECT_DOUBLE_EQ(d.max_abs, 5.0);
}

TEST(ImageIo, PfmRoundTripsExactly) {
  std::string path = (std::filesystem::temp_directory_path() / "omnishadow_test.pfm").string();
  std::vector<float> values = {0.0f, -1.5f, 3.25e-7f, FLT_MAX, 1e30f, 42.0f};
  write_pfm(path, 2, 1, 3, values);
  FloatImage img = read_pfm(path);
  EXPECT_EQ(img.width, 2);
  EXPECT_EQ(img.height, 1);
  EXPECT_EQ(img.channels, 3);
  EXPECT_EQ(img.values, values);
  write_file_atomic(path, "PF\n2 1\n-1.0\nxx");
  EXPECT_THROW(read_pfm(path), std::runtime_error);
  std::filesystem::remove(path);
}

TEST(FileIo, AtomicWriteReplacesWholeFilesAndReportsUnwritablePaths) {
  std::string path = (std::filesystem::temp_directory_path() / "omnishadow_atomic.txt").string();
  write_file_atomic(path, "first");
  write_file_atomic(path, "second");
  EXPECT_EQ(read_file(path), "second");
  std::filesystem::remove(path);
  EXPECT_THROW(write_file_atomic("/nonexistent-dir/x.json", "x"), std::runtime_error);
}

}  // namespace
}  // namespace omnishadow::bench
