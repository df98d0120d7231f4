// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Strict text-to-number conversion shared by every reader and option parser: the
// whole text must be the number (no trailing characters, no embedded NUL byte, no
// empty string), so "0.5\0junk" or "3abc" are errors rather than 0.5 or 3.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vrsph/core/types.hpp>

namespace vrsph {

/// The value of `text` (surrounding blanks allowed) as a double, or nullopt if any
/// character is not part of the number. Accepts "nan"/"inf" (callers decide).
std::optional<Real> parse_real(std::string_view text);
/// The value of `text` as a base-10 integer, or nullopt (also on overflow of int64).
/// "1e3" is not an integer.
std::optional<std::int64_t> parse_integer(std::string_view text);

/// The boolean a word names: true for "true", "1", "yes", "on"; false for "false", "0", "no",
/// "off" (exactly these, in lower case); nullopt for anything else. The one vocabulary of
/// method options (MethodOptions::get_bool) and boolean CLI options.
std::optional<bool> parse_boolean(std::string_view text);

/// `text` with ASCII letters in lower case (file extensions, keywords, array names).
std::string to_lower(std::string text);

/// Printable form of a text for error messages: control bytes (NUL, tab, ...) and
/// non-ASCII bytes become \\xNN, and long texts are cut at `max_length` characters.
std::string printable(std::string_view text, std::size_t max_length = 80);

/// `message` with the particle numbers it names ("particle 12", "particles 3 and 4") mapped
/// by `number_of`: a message from code that ran on one rank's part of a cloud, reworded
/// with the whole cloud's numbers.
std::string renumber_particles(const std::string& message, const std::function<long long(long long)>& number_of);

}  // namespace vrsph
