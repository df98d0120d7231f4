// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vrsph/core/parse.hpp>

namespace vrsph {

namespace {
std::string_view trim(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}
}  // namespace

std::optional<Real> parse_real(std::string_view text) {
  const std::string s(trim(text));  // a copy: strtod needs a NUL-terminated buffer
  if (s.empty() || s.find('\0') != std::string::npos) return std::nullopt;
  char* end = nullptr;
  const Real v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

std::optional<std::int64_t> parse_integer(std::string_view text) {
  const std::string s(trim(text));
  if (s.empty() || s.find('\0') != std::string::npos) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size() || errno == ERANGE) return std::nullopt;
  return static_cast<std::int64_t>(v);
}

std::string printable(std::string_view text, std::size_t max_length) {
  std::string out;
  for (const char c : text) {
    if (out.size() >= max_length) {
      out += "...";
      break;
    }
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", u);
      out += buf;
    }
  }
  return out;
}

std::optional<bool> parse_boolean(std::string_view text) {
  if (text == "true" || text == "1" || text == "yes" || text == "on") return true;
  if (text == "false" || text == "0" || text == "no" || text == "off") return false;
  return std::nullopt;
}

std::string to_lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string renumber_particles(const std::string& message, const std::function<long long(long long)>& number_of) {
  // A scan by hand: <regex> doubles the compile time of whoever includes it.
  std::string out;
  std::size_t at = 0;
  // Copies the digits at `at`, mapped (if they are a number at all).
  const auto number = [&]() {
    std::size_t end = at;
    while (end < message.size() && std::isdigit(static_cast<unsigned char>(message[end]))) ++end;
    if (end == at || end - at > 12) return false;  // not a particle number (nor one stoll could overflow on)
    out += std::to_string(number_of(std::stoll(message.substr(at, end - at))));
    at = end;
    return true;
  };
  for (;;) {
    const std::size_t word = message.find("particle", at);
    if (word == std::string::npos) break;
    std::size_t digits = word + 8;
    if (digits < message.size() && message[digits] == 's') ++digits;
    if (digits >= message.size() || message[digits] != ' ') {
      out.append(message, at, digits - at);
      at = digits;
      continue;
    }
    out.append(message, at, digits + 1 - at);
    at = digits + 1;
    if (number() && message.compare(at, 5, " and ") == 0) {
      out += " and ";
      at += 5;
      number();
    }
  }
  out.append(message, at, std::string::npos);
  return out;
}

}  // namespace vrsph
