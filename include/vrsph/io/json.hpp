// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// An ordered JSON value for what vrsph writes: result tables, their metadata and the CLI's
// reports. Objects keep their keys in insertion order; numbers are written in the shortest
// form that reads back to the same double; NaN and infinities become null (JSON has neither).
//
// Write-only on purpose: the core needs Eigen and nanoflann alone, and writing is 200 lines.
// Reading JSON (GeoJSON geometry files, the FEniCSx peer's reports) is input from outside and
// goes through nlohmann-json, the optional part JSON.
#include <concepts>
#include <cstddef>
#include <initializer_list>
#include <ranges>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace vrsph {

class Json {
 public:
  Json() = default;  ///< null
  Json(std::nullptr_t) {}
  Json(bool b);
  Json(double x);  ///< not finite: null
  template <std::integral T>
    requires(!std::same_as<T, bool>)
  Json(T v) : kind_(Kind::Scalar), text_(std::to_string(v)) {}
  Json(std::string_view s);
  Json(const std::string& s) : Json(std::string_view(s)) {}
  Json(const char* s) : Json(std::string_view(s)) {}
  /// An array of the range's elements (std::vector<double>, std::vector<std::string>, ...).
  template <std::ranges::input_range R>
    requires(!std::convertible_to<const R&, std::string_view> &&
             std::is_constructible_v<Json, std::ranges::range_reference_t<const R&>>)
  Json(const R& items) : kind_(Kind::Array) {
    for (auto&& item : items) values_.emplace_back(item);
  }

  static Json object();
  static Json object(std::initializer_list<std::pair<std::string, Json>> members);
  static Json array();
  static Json array(std::initializer_list<Json> items);

  /// The member `key` of an object, inserted as null if absent (a null value becomes an empty
  /// object first); throws ConfigError on an array or a scalar.
  Json& operator[](std::string_view key);
  /// j[0] would convert 0 to a null key pointer: arrays are indexed with at().
  template <std::integral T>
  Json& operator[](T) = delete;
  /// The member `key`, or nullptr (also when this is not an object).
  const Json* find(std::string_view key) const;
  bool contains(std::string_view key) const { return find(key) != nullptr; }
  /// Element `i` of an array; throws ConfigError out of range or on a non-array.
  Json& at(std::size_t i);
  /// Appends to an array (a null value becomes an empty array first).
  void push_back(Json item);
  /// Copies every member of `other` (an object) into this object; same keys are overwritten.
  void merge(const Json& other);

  bool is_null() const { return kind_ == Kind::Null; }
  bool is_object() const { return kind_ == Kind::Object; }
  bool is_array() const { return kind_ == Kind::Array; }
  /// Elements of an array or members of an object; 0 for null and scalars.
  std::size_t size() const { return values_.size(); }

  /// indent < 0: one line ("{"a":1,"b":[2,3]}"); otherwise that many spaces per level.
  std::string dump(int indent = -1) const;

 private:
  enum class Kind : unsigned char { Null, Scalar, Array, Object };
  void write(std::string& out, int indent, int depth) const;

  Kind kind_ = Kind::Null;
  std::string text_;               // a scalar's JSON text (numbers, true/false, quoted strings)
  std::vector<std::string> keys_;  // an object's keys, in order, paired with values_
  std::vector<Json> values_;       // an array's elements or an object's values
};

}  // namespace vrsph
