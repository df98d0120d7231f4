// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Every file vrsph reads is opened here: a directory, a missing or an unreadable file is
// an IoError naming the path and `what` it was to be ("point cloud file"), the twin of
// write_file for output.
#include <fstream>
#include <string>

namespace vrsph {

/// An open stream on path (binary mode: no translation, as every format here wants).
std::ifstream open_input(const std::string& path, const std::string& what);

/// The whole content of path.
std::string read_file(const std::string& path, const std::string& what);

}  // namespace vrsph
