#pragma once

namespace gazedirector {

// Installs SIGINT/SIGTERM handlers that only raise a flag; long loops poll it
// with ThrowIfInterrupted() so that destructors remove partial outputs.
void InstallInterruptHandlers();
bool InterruptRequested();
void ThrowIfInterrupted();

}  // namespace gazedirector
