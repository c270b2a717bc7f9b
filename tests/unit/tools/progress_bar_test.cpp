// The progress line of soltex-load and soltex-bench (client/load/progress_bar.h), written into
// a file as it is into a test log: one line per update, nothing redrawn in place.
#include "progress_bar.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace soltex {
namespace {

std::string contents(std::FILE* file) {
  std::rewind(file);
  std::string text;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file))
    text.push_back(static_cast<char>(c));
  return text;
}

TEST(ProgressBar, IntoAFileEveryUpdateIsALineOfItsOwn) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  ProgressBar bar(4, file);
  bar.show(0, "first");
  bar.show(2, "second");
  bar.finish();
  bar.finish();  // once only
  EXPECT_EQ(contents(file),
            "[....................] 0/4 first\n"
            "[##########..........] 2/4 second\n"
            "[####################] 4/4 done\n");
  std::fclose(file);
}

TEST(ProgressBar, WithoutATotalShowsTheTextAlone) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  ProgressBar bar(0, file);
  bar.show("[    1.0 s] 10 bricks");
  bar.finish();
  EXPECT_EQ(contents(file), "[    1.0 s] 10 bricks\n");
  std::fclose(file);
}

TEST(ProgressBar, DoneBeyondTheTotalFillsTheBarAndSaysSo) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  ProgressBar bar(2, file);
  bar.show(5, "x");
  EXPECT_EQ(contents(file), "[####################] 5/2 x\n");
  std::fclose(file);
}

}  // namespace
}  // namespace soltex
