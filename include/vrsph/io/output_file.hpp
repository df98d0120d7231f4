#pragma once
// Every file vrsph writes goes through write_file: the content is written, flushed
// and closed, and only then is success declared. A full disk, a read-only target or
// a directory given as a file is an IoError naming the path and the system's reason,
// never a silently truncated table, cloud or VTU file.
#include <functional>
#include <iosfwd>
#include <string>

namespace vrsph {

/// Writes `path` through `write`; `what` names the content in messages ("VTU file").
void write_file(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write);

/// Flushes `out` (e.g. std::cout) and throws IoError naming `what` if any write to it failed.
void check_stream(std::ostream& out, const std::string& what);

}  // namespace vrsph
