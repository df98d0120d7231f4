// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Stopping a long library call on request (Ctrl-C in Python, where the interpreter cannot run
// its signal handler while the library holds the thread). The embedding installs a check; the
// library calls it from the thread that entered it between stages and every few milliseconds
// inside long loops, and ends the call with vrsph::Interrupted when it returns true. Worker
// threads never call the check (an interpreter's signal handling is tied to its main thread):
// they see the request through interrupt_pending() and skip their remaining work.

namespace vrsph {

/// The check: true = stop. nullptr (the default) = never. Process-wide; set it once.
using InterruptCheck = bool (*)();
void set_interrupt_check(InterruptCheck check);

/// Calls the check (on the calling thread: outside parallel regions, or OpenMP thread 0) and
/// throws Interrupted when it asks to stop, or when a stop was requested earlier in the call.
void check_interrupt();

/// For loops run by many threads: thread 0 polls the check every `every` calls (pass its own
/// counter); every thread gets true once a stop is requested and should skip its work. After
/// the loop, check_interrupt() throws on the calling thread.
bool interrupt_pending(long long iteration, long long every = 256);

}  // namespace vrsph
