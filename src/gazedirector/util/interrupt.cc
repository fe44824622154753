#include "gazedirector/util/interrupt.h"

#include <atomic>
#include <csignal>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace {

std::atomic<bool> g_interrupted{false};

void OnSignal(int) { g_interrupted.store(true); }

}  // namespace

void InstallInterruptHandlers() {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
}

bool InterruptRequested() { return g_interrupted.load(); }

void ThrowIfInterrupted() {
  if (InterruptRequested()) throw Error(ExitCode::kInterrupted, "interrupted; partial outputs removed");
}

}  // namespace gazedirector
