#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lidarseg/apps/CommandLine.h"

namespace lidarseg::apps {
namespace {

// Runs the shared parser on a small command line with one numeric flag and one argument.
std::optional<int> parse(std::vector<std::string> args, int* n = nullptr) {
  TCLAP::CmdLine cmd("test tool", ' ', "1.0");
  TCLAP::ValueArg<int> number("n", "number", "a number", false, 1, "N", cmd);
  TCLAP::UnlabeledValueArg<std::string> input("input", "a file", true, "", "FILE", cmd);
  args.insert(args.begin(), "tool");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  const auto status = parseCommandLine(cmd, static_cast<int>(argv.size()), argv.data(), "tool");
  if (n != nullptr) *n = number.getValue();
  return status;
}

TEST(CommandLine, ValidArgumentsRunAndUsageErrorsExitWithTwo) {
  int n = 0;
  EXPECT_EQ(parse({"-n", "7", "file"}, &n), std::nullopt);
  EXPECT_EQ(n, 7);
  EXPECT_EQ(parse({"-n", "seven", "file"}), std::optional<int>(kUsageError));
  EXPECT_EQ(parse({"file", "--no-such-flag"}), std::optional<int>(kUsageError));
  EXPECT_EQ(parse({}), std::optional<int>(kUsageError));
}

TEST(CommandLine, HelpAndVersionExitWithZeroEvenAfterAFullCommand) {
  EXPECT_EQ(parse({"--help"}), std::optional<int>(0));
  EXPECT_EQ(parse({"-n", "3", "file", "--help"}), std::optional<int>(0));
  EXPECT_EQ(parse({"--version"}), std::optional<int>(0));
}

// F10 (docs/reliability.md): TCLAP splits one argument at its first blank, so "-m -1" given
// as one argument is -m given "-1", which it reads as 2^64 - 1: a usage error like "-m" "-1".
TEST(CommandLine, AnUnsignedValueInsideOneArgumentIsCheckedToo) {
  const auto parseCount = [](std::vector<std::string> args, std::size_t* m) {
    TCLAP::CmdLine cmd("test tool", ' ', "1.0");
    TCLAP::ValueArg<std::size_t> count("m", "max-scans", "a count", false, 0, "N", cmd);
    TCLAP::UnlabeledValueArg<std::string> input("input", "a file", true, "", "FILE", cmd);
    args.insert(args.begin(), "tool");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    const auto status = parseCommandLine(cmd, static_cast<int>(argv.size()), argv.data(), "tool");
    *m = count.getValue();
    return status;
  };
  std::size_t m = 0;
  EXPECT_EQ(parseCount({"file", "-m 12"}, &m), std::nullopt);
  EXPECT_EQ(m, 12u);
  EXPECT_EQ(parseCount({"file", "-m -1"}, &m), std::optional<int>(kUsageError));
  EXPECT_EQ(parseCount({"file", "--max-scans -1"}, &m), std::optional<int>(kUsageError));
  EXPECT_EQ(parseCount({"file", "--max-scans", "-1"}, &m), std::optional<int>(kUsageError));
}

TEST(CommandLine, AnMrptExceptionIsReducedToItsMessage) {
  const std::runtime_error mrpt_style(
      "==== MRPT exception ====\nbacktrace:\n[ 0] mrpt::io::CFileGZOutputStream::Write\n"
      "Message: Error writing to 'out.rawlog': No space left on device\n");
  EXPECT_EQ(describeError(mrpt_style), "Error writing to 'out.rawlog': No space left on device");
  EXPECT_EQ(describeError(std::runtime_error("'x.log' holds no usable laser scan")),
            "'x.log' holds no usable laser scan");
}

}  // namespace
}  // namespace lidarseg::apps
