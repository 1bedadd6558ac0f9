// Progress: a bar redrawn in place on a terminal, nothing but one summary line anywhere else.
#include "tools/bench/Progress.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

namespace strata::bench {
namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

std::string Contents(std::FILE* file) {
  std::fflush(file);
  std::rewind(file);
  std::string text;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file)) text.push_back(static_cast<char>(c));
  return text;
}

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size()))
    ++count;
  return count;
}

TEST(Progress, OffATerminalItPrintsOnlyTheSummaryLine) {
  std::unique_ptr<std::FILE, FileCloser> file(std::tmpfile());
  ASSERT_NE(file, nullptr);
  {
    Progress progress("strata thing", "steps", file.get(), /*terminal=*/false);
    for (std::size_t done = 0; done <= 50; ++done) progress.Update(done, 50);
    progress.Finish("50 steps");
    progress.Finish("again");  // only the first counts
  }
  const std::string text = Contents(file.get());
  EXPECT_EQ(text.rfind("strata thing: 50 steps (", 0), 0u) << text;
  EXPECT_EQ(Count(text, "\n"), 1u) << text;
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(Count(text, "\r"), 0u) << text;
}

TEST(Progress, OnATerminalItRedrawsInPlaceOncePerInterval) {
  std::unique_ptr<std::FILE, FileCloser> file(std::tmpfile());
  ASSERT_NE(file, nullptr);
  Progress progress("strata thing", "tiles", file.get(), /*terminal=*/true, std::chrono::hours(1));
  progress.Update(0, 4);
  progress.Update(1, 4);  // within the interval of the first: not drawn
  progress.Update(2, 4);
  std::string text = Contents(file.get());
  EXPECT_EQ(Count(text, "strata thing ["), 1u) << text;
  EXPECT_NE(text.find("0/4 tiles"), std::string::npos) << text;
  EXPECT_EQ(text.find("2/4 tiles"), std::string::npos) << text;
  progress.Update(4, 4);  // the end is always drawn
  text = Contents(file.get());
  EXPECT_NE(text.find("[##############################] 4/4 tiles"), std::string::npos) << text;
  EXPECT_EQ(Count(text, "\n"), 0u) << "the bar stays on one line";
  progress.Finish("4 tiles");
  text = Contents(file.get());
  // The bar is erased before the summary, which ends the line.
  EXPECT_NE(text.find("\r\033[Kstrata thing: 4 tiles ("), std::string::npos) << text;
  EXPECT_EQ(Count(text, "\n"), 1u);
  progress.Update(4, 4);  // after Finish nothing more is drawn
  EXPECT_EQ(Contents(file.get()), text);
}

TEST(Progress, HideErasesTheBarAndTheNextUpdateDrawsItAgain) {
  std::unique_ptr<std::FILE, FileCloser> file(std::tmpfile());
  ASSERT_NE(file, nullptr);
  Progress progress("strata bench", "runs", file.get(), /*terminal=*/true);
  progress.Update(0, 2);
  progress.Hide();
  std::fputs("a row of figures\n", file.get());
  progress.Update(1, 2);  // drawn at once: nothing was on screen
  const std::string text = Contents(file.get());
  const std::size_t first = text.find("0/2 runs"), row = text.find("\r\033[Ka row of figures\n");
  ASSERT_NE(first, std::string::npos) << text;
  ASSERT_NE(row, std::string::npos) << text;
  EXPECT_LT(first, row);
  EXPECT_GT(text.find("1/2 runs"), row) << text;
  EXPECT_NE(text.find("1/2 runs"), std::string::npos) << text;
}

}  // namespace
}  // namespace strata::bench
