#include "gazedirector/util/interrupt.h"

#include <csignal>
#include <cstdlib>

#include <gtest/gtest.h>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

// Exit codes of the child process that the death tests below fork, so that
// the flag a signal raises stays out of the other tests' process.
constexpr int kThrewInterrupted = 7, kDidNotThrow = 8, kThrewOther = 9;

// Polls after `signal` arrives: exits with how ThrowIfInterrupted answered.
void PollAfter(int signal) {
  InstallInterruptHandlers();
  if (InterruptRequested()) std::exit(kThrewOther);  // nothing requested yet
  std::raise(signal);
  if (!InterruptRequested()) std::exit(kDidNotThrow);
  try {
    ThrowIfInterrupted();
  } catch (const Error& error) {
    std::exit(error.code() == ExitCode::kInterrupted ? kThrewInterrupted : kThrewOther);
  }
  std::exit(kDidNotThrow);
}

TEST(InterruptDeathTest, ControlCIsCaughtAndReportedAsAnInterruption) {
  EXPECT_EXIT(PollAfter(SIGINT), ::testing::ExitedWithCode(kThrewInterrupted), "");
}

TEST(InterruptDeathTest, TerminationIsCaughtAndReportedAsAnInterruption) {
  EXPECT_EXIT(PollAfter(SIGTERM), ::testing::ExitedWithCode(kThrewInterrupted), "");
}

// (Without installing the handlers here, which would change how this
// process takes Ctrl-C.)
TEST(InterruptTest, NothingIsThrownWithoutASignal) {
  EXPECT_FALSE(InterruptRequested());
  EXPECT_NO_THROW(ThrowIfInterrupted());
}

}  // namespace
}  // namespace gazedirector
