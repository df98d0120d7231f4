// SPDX-License-Identifier: BSD-3-Clause
#include <vrsph/core/error.hpp>
#include <vrsph/core/references.hpp>
#include <vrsph/methods/registry.hpp>
#include "test_util.hpp"

using namespace vrsph;

TEST(Registry, ListsBuiltinMethodsWithReferencesAndOperators) {
  const auto list = builtin_methods().list();
  ASSERT_FALSE(list.empty());
  for (const auto& m : list) {
    EXPECT_FALSE(m.name.empty());
    // Every method cites at least one publication by key, the first with an identifier, and
    // no file name of the project's working copies of the papers reaches users.
    const auto cited = references_cited_in(m.source);
    ASSERT_FALSE(cited.empty()) << m.name << " cites no publication: " << m.source;
    EXPECT_FALSE(cited.front().identifier.empty() && cited.front().venue.empty()) << m.name;
    EXPECT_EQ(m.source.find(".txt"), std::string::npos) << m.name << ": " << m.source;
    EXPECT_FALSE(m.operators.empty());
    EXPECT_NO_THROW(builtin_methods().create(m.name));
  }
  EXPECT_TRUE(builtin_methods().info("sph").supports(OperatorKind::DivAGrad));
}

TEST(Registry, UnknownNamesAndOptionsAreConfigErrors) {
  EXPECT_THROW_MSG(builtin_methods().create("sphh"), ConfigError, "unknown method 'sphh' (known: sph");
  EXPECT_THROW_MSG(builtin_methods().create("sph", MethodOptions::parse({"volumes=dx"})), ConfigError,
                   "method sph has no option(s): volumes");
  EXPECT_THROW_MSG(builtin_methods().create("sph", MethodOptions::parse({"volume=mass"})), ConfigError,
                   "volume='mass' is not one of: dx, shepard");
  EXPECT_THROW_MSG(MethodOptions::parse({"volume"}), ConfigError, "not of the form key=value");
  EXPECT_THROW_MSG(MethodOptions::parse({"a=1", "a=2"}), ConfigError, "given twice");
  MethodRegistry r;
  r.add({"x", "[QW]", "", "", {}, {}}, [](const MethodOptions&) { return std::unique_ptr<Method>(); });
  EXPECT_THROW_MSG(r.add({"x", "[QW]", "", "", {}, {}}, nullptr), ConfigError, "registered twice");
}

TEST(References, TheFourPapersWithIdentifiersAndCitationsFoundByKey) {
  const auto cited = references_cited_in("[QW] §4; [AAR](27)-(30); [QW] again; [NOPE]; [IM] (2)");
  ASSERT_EQ(cited.size(), 3u);  // each once, in order, unknown keys skipped
  EXPECT_EQ(cited[0].key, "QW");
  EXPECT_EQ(cited[1].key, "AAR");
  EXPECT_EQ(cited[2].key, "IM");
  EXPECT_EQ(cited[0].identifier, "arXiv:2503.15188");
  EXPECT_EQ(cited[0].citation(),
            "Z. Qiao, Y. Wei, \"Convergence analysis of SPH method on irregular particle distributions for the "
            "Poisson equation\", preprint (2025), arXiv:2503.15188");
  for (const char* key : {"QW", "AAR", "SPE", "IM"})
    EXPECT_EQ(references_cited_in(std::string("[") + key + "]").size(), 1u) << key;
  EXPECT_TRUE(references_cited_in("no brackets [unclosed").empty());
}
