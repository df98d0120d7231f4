#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include "test_util.hpp"

using namespace vrsph;

TEST(Registry, ListsBuiltinMethodsWithPaperAndOperators) {
  const auto list = builtin_methods().list();
  ASSERT_FALSE(list.empty());
  for (const auto& m : list) {
    EXPECT_FALSE(m.name.empty());
    EXPECT_NE(m.paper.find(".txt"), std::string::npos) << m.name << " must cite its seed file";
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
  r.add({"x", "p.txt", "", "", {}, {}}, [](const MethodOptions&) { return std::unique_ptr<Method>(); });
  EXPECT_THROW_MSG(r.add({"x", "p.txt", "", "", {}, {}}, nullptr), ConfigError, "registered twice");
}
