// InputFile and OutputFile: the input policy every loader shares (regular files only, a size limit) and
// result files that are replaced whole or not at all.
#include "physics/core/InputFile.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <iterator>
#include <string>

#include "physics/core/OutputFile.h"
#include "tests/TempPath.h"

namespace strata::test {
namespace {

std::string Contents(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void ExpectRefused(const std::filesystem::path& path, const std::string& why) {
  const Result<std::string> read = ReadInputFile(path, 1 << 20);
  ASSERT_FALSE(read.ok()) << path;
  EXPECT_EQ(read.error().code, ErrorCode::kParseError);
  EXPECT_NE(read.error().message.find(path.string()), std::string::npos) << read.error().message;
  EXPECT_NE(read.error().message.find(why), std::string::npos) << read.error().message;
  const Result<std::uint64_t> checked = CheckInputFile(path, 1 << 20);
  ASSERT_FALSE(checked.ok());
  EXPECT_NE(checked.error().message.find(why), std::string::npos) << checked.error().message;
}

TEST(InputFile, ReadsARegularFileWhole) {
  const auto path = TempPath("regular.txt");
  const std::string text(100000, 'x');
  std::ofstream(path, std::ios::binary) << text;
  const Result<std::string> read = ReadInputFile(path, 1 << 20);
  ASSERT_TRUE(read.ok()) << read.error().message;
  EXPECT_EQ(*read, text);
  EXPECT_EQ(*CheckInputFile(path, 1 << 20), text.size());
  std::filesystem::remove(path);
}

TEST(InputFile, RefusesWhatIsNotARegularFileBeforeReadingIt) {
  ExpectRefused(TempPath("missing.txt"), "file not found");
  ExpectRefused(std::filesystem::temp_directory_path(), "is a directory");
  // Endless devices and a pipe with no writer would hang a reader: refused without a read.
  ExpectRefused("/dev/zero", "is a device");
  const auto fifo = TempPath("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ExpectRefused(fifo, "is a pipe");
  std::filesystem::remove(fifo);
}

TEST(InputFile, RefusesAFileOverItsLimitByItsSize) {
  const auto path = TempPath("large.txt");
  std::ofstream(path, std::ios::binary) << std::string(1001, 'x');
  ASSERT_TRUE(ReadInputFile(path, 1001).ok());
  const Result<std::string> read = ReadInputFile(path, 1000);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().message.find("is 1001 bytes, more than the 1000 bytes"), std::string::npos)
      << read.error().message;
  EXPECT_FALSE(CheckInputFile(path, 1000).ok());
  std::filesystem::remove(path);
}

TEST(OutputFile, CommitReplacesTheTargetAndLeavesNoTemporary) {
  const auto path = TempPath("out.txt");
  std::ofstream(path) << "old";
  ASSERT_TRUE(WriteOutputFile(path, "new contents").ok());
  EXPECT_EQ(Contents(path), "new contents");
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  std::filesystem::remove(path);
}

TEST(OutputFile, AWriterDroppedBeforeCommitLeavesTheOldFileWhole) {
  const auto path = TempPath("kept.txt");
  std::ofstream(path) << "old";
  {
    OutputFile file(path);
    ASSERT_TRUE(file.status().ok());
    file.stream() << std::string(100000, 'n');  // a run that fails (or is killed) before it ends
  }
  EXPECT_EQ(Contents(path), "old");
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  std::filesystem::remove(path);
}

TEST(OutputFile, AProcessKilledWhileWritingLeavesTheOldFileWhole) {
  // A real SIGKILL, after part of the new file reached the disk: no destructor, no cleanup runs.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const auto path = TempPath("killed.txt");
  std::ofstream(path) << "old";
  EXPECT_EXIT(
      {
        OutputFile file(path);
        file.stream() << std::string(1 << 20, 'n');
        file.stream().flush();
        std::raise(SIGKILL);
      },
      ::testing::KilledBySignal(SIGKILL), "");
  EXPECT_EQ(Contents(path), "old");
  std::filesystem::remove(path);
  std::filesystem::remove(path.string() + ".tmp");  // what a killed writer leaves beside the target
}

TEST(OutputFile, FailedWritesAndDirectoriesAreErrors) {
  const Status full = WriteOutputFile("/dev/full", std::string(1 << 16, 'x'));
  ASSERT_FALSE(full.ok());
  EXPECT_NE(full.message().find("/dev/full"), std::string::npos) << full.message();
  const Status directory = WriteOutputFile(std::filesystem::temp_directory_path(), "x");
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.message().find("is a directory"), std::string::npos) << directory.message();
}

}  // namespace
}  // namespace strata::test
