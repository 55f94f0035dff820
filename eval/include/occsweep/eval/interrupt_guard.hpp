// Steps an interrupt's cleaning never cuts in two (docs/robustness.md, "Outputs, temporaries and --force").
#pragma once

#include <functional>

namespace occsweep {

/// Runs `step` holding the lock an interrupt's cleaning takes and keeps until the exit (output_file.hpp,
/// removeTemporariesOnInterrupt): when SIGINT, SIGTERM or SIGHUP comes, `step` has run whole or not at all (a sweep's
/// partial log renamed into place, one line appended to it). `step` must not make, commit or remove a registered
/// temporary, which takes the same lock.
void runWithoutInterruptCleaning(const std::function<void()>& step);

}  // namespace occsweep
