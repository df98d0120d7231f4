// SPDX-License-Identifier: BSD-3-Clause
// The JSON writer (vrsph/io/json.hpp): exact text for the forms we promise, doubles that read
// back bit for bit, strings that stay valid JSON whatever bytes they hold, and (in a build with
// nlohmann-json) a parse of the output by an independent reader.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <vrsph/config.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/json.hpp>
#include "test_util.hpp"
#if VRSPH_HAVE_JSON
#include <nlohmann/json.hpp>
#endif

using namespace vrsph;

TEST(Json, ScalarsAndContainersHaveTheirExactText) {
  EXPECT_EQ(Json().dump(), "null");
  EXPECT_EQ(Json(true).dump(), "true");
  EXPECT_EQ(Json(-42).dump(), "-42");
  EXPECT_EQ(Json(std::numeric_limits<unsigned long long>::max()).dump(), "18446744073709551615");
  EXPECT_EQ(Json(0.5).dump(), "0.5");
  EXPECT_EQ(Json(3.0).dump(), "3.0");  // a double stays a double when read back
  EXPECT_EQ(Json(1e-5).dump(), "1e-05");
  EXPECT_EQ(Json(-0.0).dump(), "-0.0");
  EXPECT_EQ(Json(std::nan("")).dump(), "null");
  EXPECT_EQ(Json(std::numeric_limits<double>::infinity()).dump(), "null");
  EXPECT_EQ(Json(std::vector<double>{1.5, std::nan("")}).dump(), "[1.5,null]");
  EXPECT_EQ(Json(std::vector<std::string>{"a", "b"}).dump(), R"(["a","b"])");
  EXPECT_EQ(Json::object().dump(2), "{}");
  EXPECT_EQ(Json::array().dump(2), "[]");

  Json j;  // null becomes an object on the first member; keys keep their order
  j["z"] = 1;
  j["a"] = Json::array({1, "two", nullptr});
  j["m"]["inner"] = false;
  j["z"] = 2;  // overwritten in place
  EXPECT_EQ(j.dump(), R"({"z":2,"a":[1,"two",null],"m":{"inner":false}})");
  EXPECT_EQ(j.dump(2), "{\n  \"z\": 2,\n  \"a\": [\n    1,\n    \"two\",\n    null\n  ],\n  \"m\": {\n"
                       "    \"inner\": false\n  }\n}");
  EXPECT_TRUE(j.contains("m"));
  EXPECT_FALSE(j.contains("inner"));
  EXPECT_EQ(j.size(), 3u);

  Json base = Json::object({{"k", 1}, {"rows", "old"}});
  base.merge(Json::object({{"rows", 2}, {"new", "x"}}));
  EXPECT_EQ(base.dump(), R"({"k":1,"rows":2,"new":"x"})");
}

TEST(Json, MisuseIsAnError) {
  Json a = Json::array({1});
  EXPECT_THROW_MSG(a["key"], ConfigError, "not an object");
  EXPECT_THROW_MSG(a.at(1), ConfigError, "not an array that long");
  Json s("text");
  EXPECT_THROW_MSG(s.push_back(1), ConfigError, "not an array");
  EXPECT_THROW_MSG(Json::object().merge(Json(3)), ConfigError, "must be an object");
}

TEST(Json, StringsAreEscapedAndStayValidUtf8) {
  EXPECT_EQ(Json("q\"b\\s/").dump(), R"("q\"b\\s/")");
  EXPECT_EQ(Json(std::string("\n\t\r\b\f\x01\x1f", 7)).dump(), R"("\n\t\r\b\f\u0001\u001f")");
  EXPECT_EQ(Json(std::string("a\0b", 3)).dump(), R"("a\u0000b")");
  EXPECT_EQ(Json("λ ≤ 2 — 𝜋").dump(), "\"λ ≤ 2 — 𝜋\"");  // well-formed UTF-8 passes through
  // Bytes that are not UTF-8 (a Latin-1 file name, a cut sequence, an overlong '/', a
  // surrogate, a code point past U+10FFFF) become U+FFFD, one per byte.
  EXPECT_EQ(Json("caf\xe9.csv").dump(), R"("caf\ufffd.csv")");
  EXPECT_EQ(Json("\xe2\x82").dump(), R"("\ufffd\ufffd")");
  EXPECT_EQ(Json("\xc0\xaf").dump(), R"("\ufffd\ufffd")");
  EXPECT_EQ(Json("\xed\xa0\x80").dump(), R"("\ufffd\ufffd\ufffd")");
  EXPECT_EQ(Json("\xf4\x90\x80\x80").dump(), R"("\ufffd\ufffd\ufffd\ufffd")");
  Json key;
  key["caf\xe9"] = 1;
  EXPECT_EQ(key.dump(), R"({"caf\ufffd":1})");
}

TEST(Json, DoublesReadBackBitForBit) {
  std::mt19937_64 rng(7);
  std::vector<double> values = {std::numeric_limits<double>::min(), std::numeric_limits<double>::denorm_min(),
                                std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                                0.1, 1.0 / 3.0, 2.5e-308, 123456789012345678.0};
  for (int k = 0; k < 20000; ++k) {
    std::uint64_t bits = rng();
    double x;
    std::memcpy(&x, &bits, sizeof x);
    if (std::isfinite(x)) values.push_back(x);
  }
  for (double x : values) {
    const std::string text = Json(x).dump();
    const double back = std::strtod(text.c_str(), nullptr);
    ASSERT_EQ(std::memcmp(&back, &x, sizeof x), 0) << text;
    ASSERT_LE(text.size(), 25u) << text;  // shortest form, not 17 digits padded
  }
}

#if VRSPH_HAVE_JSON
TEST(Json, AnIndependentReaderParsesWhatWeWrite) {
  Json j;
  j["text"] = "tab\there \"quoted\" back\\slash \x01 caf\xe9 λ";
  j["numbers"] = std::vector<double>{0.1, -2.5e-300, 1e300, std::nan("")};
  j["nested"]["deeper"] = Json::array({Json::object({{"k", 1}}), Json::array(), true});
  for (int indent : {-1, 0, 2}) {
    const auto parsed = nlohmann::json::parse(j.dump(indent));
    EXPECT_EQ(parsed["text"].get<std::string>(), "tab\there \"quoted\" back\\slash \x01 caf\xef\xbf\xbd λ");
    EXPECT_EQ(parsed["numbers"][0].get<double>(), 0.1);
    EXPECT_EQ(parsed["numbers"][1].get<double>(), -2.5e-300);
    EXPECT_TRUE(parsed["numbers"][3].is_null());
    EXPECT_EQ(parsed["nested"]["deeper"][0]["k"].get<int>(), 1);
    EXPECT_TRUE(parsed["nested"]["deeper"][2].get<bool>());
  }
}
#endif
