// SPDX-License-Identifier: BSD-3-Clause
#include <array>
#include <charconv>
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/io/json.hpp>

namespace vrsph {

namespace {
// The length of the well-formed UTF-8 sequence at s[k] (RFC 3629, table 3-7 of Unicode: no
// overlong forms, no surrogates, nothing past U+10FFFF), or 0 if it is not one.
std::size_t utf8_length(std::string_view s, std::size_t k) {
  const auto byte = [&](std::size_t i) { return i < s.size() ? static_cast<unsigned char>(s[i]) : 0u; };
  const unsigned c = byte(k);
  const auto cont = [&](std::size_t i, unsigned lo = 0x80, unsigned hi = 0xBF) {
    const unsigned b = byte(i);
    return i < s.size() && b >= lo && b <= hi;
  };
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) return cont(k + 1) ? 2 : 0;
  if (c >= 0xE0 && c <= 0xEF) {
    const unsigned lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
    return cont(k + 1, lo, hi) && cont(k + 2) ? 3 : 0;
  }
  if (c >= 0xF0 && c <= 0xF4) {
    const unsigned lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
    return cont(k + 1, lo, hi) && cont(k + 2) && cont(k + 3) ? 4 : 0;
  }
  return 0;
}

// A JSON string literal. A byte that is not part of well-formed UTF-8 (a file name in another
// encoding) becomes U+FFFD, so that the output stays valid JSON whatever the text held.
std::string json_string(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 2);
  out += '"';
  for (std::size_t k = 0; k < s.size();) {
    const char c = s[k];
    const std::size_t n = utf8_length(s, k);
    if (n == 0) {
      out += "\\ufffd";
      ++k;
      continue;
    }
    if (n > 1) {
      out.append(s, k, n);
      k += n;
      continue;
    }
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          constexpr char hex[] = "0123456789abcdef";
          out += "\\u00";
          out += hex[(c >> 4) & 0xF];
          out += hex[c & 0xF];
        } else {
          out += c;
        }
    }
    ++k;
  }
  out += '"';
  return out;
}

void newline(std::string& out, int indent, int depth) {
  if (indent < 0) return;
  out += '\n';
  out.append(static_cast<std::size_t>(indent) * static_cast<std::size_t>(depth), ' ');
}
}  // namespace

Json::Json(bool b) : kind_(Kind::Scalar), text_(b ? "true" : "false") {}

Json::Json(double x) {
  if (!std::isfinite(x)) return;  // null
  kind_ = Kind::Scalar;
  std::array<char, 32> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), x);  // shortest round trip
  check<ConfigError>(ec == std::errc(), "internal: a double did not fit its JSON text");
  text_.assign(buf.data(), end);
  // "3" would read back as an integer: a double keeps its decimal point ("3.0").
  if (text_.find_first_of(".e") == std::string::npos) text_ += ".0";
}

Json::Json(std::string_view s) : kind_(Kind::Scalar), text_(json_string(s)) {}

Json Json::object() {
  Json j;
  j.kind_ = Kind::Object;
  return j;
}

Json Json::object(std::initializer_list<std::pair<std::string, Json>> members) {
  Json j = object();
  for (const auto& [key, value] : members) j[key] = value;
  return j;
}

Json Json::array() {
  Json j;
  j.kind_ = Kind::Array;
  return j;
}

Json Json::array(std::initializer_list<Json> items) {
  Json j = array();
  j.values_.assign(items.begin(), items.end());
  return j;
}

Json& Json::operator[](std::string_view key) {
  if (kind_ == Kind::Null) kind_ = Kind::Object;
  check<ConfigError>(kind_ == Kind::Object, "internal: JSON member '", key, "' asked of a value that is not an object");
  for (std::size_t k = 0; k < keys_.size(); ++k)
    if (keys_[k] == key) return values_[k];
  keys_.emplace_back(key);
  return values_.emplace_back();
}

const Json* Json::find(std::string_view key) const {
  if (kind_ != Kind::Object) return nullptr;
  for (std::size_t k = 0; k < keys_.size(); ++k)
    if (keys_[k] == key) return &values_[k];
  return nullptr;
}

Json& Json::at(std::size_t i) {
  check<ConfigError>(kind_ == Kind::Array && i < values_.size(), "internal: JSON element ", i,
                     " asked of a value that is not an array that long");
  return values_[i];
}

void Json::push_back(Json item) {
  if (kind_ == Kind::Null) kind_ = Kind::Array;
  check<ConfigError>(kind_ == Kind::Array, "internal: JSON push_back on a value that is not an array");
  values_.push_back(std::move(item));
}

void Json::merge(const Json& other) {
  check<ConfigError>(other.kind_ == Kind::Object || other.kind_ == Kind::Null,
                     "the extra JSON merged into a table's must be an object");
  for (std::size_t k = 0; k < other.keys_.size(); ++k) (*this)[other.keys_[k]] = other.values_[k];
}

std::string Json::dump(int indent) const {
  std::string out;
  write(out, indent, 0);
  return out;
}

void Json::write(std::string& out, int indent, int depth) const {
  switch (kind_) {
    case Kind::Null: out += "null"; return;
    case Kind::Scalar: out += text_; return;
    case Kind::Array:
    case Kind::Object: break;
  }
  const bool object = kind_ == Kind::Object;
  out += object ? '{' : '[';
  for (std::size_t k = 0; k < values_.size(); ++k) {
    if (k) out += ',';
    newline(out, indent, depth + 1);
    if (object) {
      out += json_string(keys_[k]);
      out += indent < 0 ? ":" : ": ";
    }
    values_[k].write(out, indent, depth + 1);
  }
  if (!values_.empty()) newline(out, indent, depth);
  out += object ? '}' : ']';
}

}  // namespace vrsph
