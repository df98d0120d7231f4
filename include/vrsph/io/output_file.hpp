// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Every file vrsph writes goes through write_file: the content goes to a temporary file
// beside the target, is flushed and closed, and only then renamed over the target. So a
// full disk, a kill or a crash mid-write leaves the previous file intact (and no half-written
// file that looks valid), a read-only target or a directory given as a file is an IoError
// naming the path and the system's reason. Targets that are not regular files (/dev/null,
// /dev/full, a FIFO) are written in place: there is nothing to rename over.
#include <functional>
#include <iosfwd>
#include <string>

namespace vrsph {

/// Writes `path` through `write`; `what` names the content in messages ("VTU file").
void write_file(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write);

/// For content another program writes (a plot script): `produce` is given a temporary path
/// beside `path`, with the same extension, and must create it; it is renamed into place only
/// when `produce` returned normally and left a non-empty file.
void write_file_via(const std::string& path, const std::string& what,
                    const std::function<void(const std::string& temporary)>& produce);

/// Removes the temporary files of writes in progress. Async-signal-safe: a SIGINT/SIGTERM
/// handler calls it before the process ends, so an interrupted run leaves no temporaries.
void remove_pending_temporaries() noexcept;

/// Flushes `out` (e.g. std::cout) and throws IoError naming `what` if any write to it failed.
void check_stream(std::ostream& out, const std::string& what);

/// Throws ConfigError when `output` names the same file as `input` (writing would destroy the
/// input before, or while, it is read); `option` names the output's option in the message.
void check_output_is_not_input(const std::string& output, const std::string& input, const std::string& option);

}  // namespace vrsph
