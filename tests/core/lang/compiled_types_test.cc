// The library's types as the build compiled them (core/lang/compiled_types.h) are the types its
// text parses to: the CLI reads the compiled ones, this test process parses the text.

#include <gtest/gtest.h>

#include <map>
#include <stdexcept>
#include <string>

#include "core/lang/builtin_library.h"
#include "core/lang/compiled_types.h"
#include "core/lang/type_serial.h"

namespace momenta {
namespace {

/// Every compiled type's bytes, by the type's name.
std::map<std::string, std::string> CompiledByName() {
  const CompiledLibraryTypes compiled = CompiledBuiltinTypes();
  std::map<std::string, std::string> by_name;
  for (size_t k = 0; k < compiled.entries; ++k) {
    const std::string bytes(compiled.bytes + compiled.offsets[k], compiled.offsets[k + 1] - compiled.offsets[k]);
    if (bytes.empty()) continue;
    by_name[DeserializeComponentType(bytes).name] = bytes;
  }
  return by_name;
}

TEST(CompiledTypesTest, EveryLibraryTypeIsCompiledAsItsTextParses) {
  const std::map<std::string, std::string> compiled = CompiledByName();
  size_t types = 0;
  for (const std::string& name : BuiltinLibrary().ComponentNames()) {
    const auto it = compiled.find(name);
    ASSERT_NE(it, compiled.end()) << name << " is not compiled";
    // Byte for byte: every field, every expression node and every location (file:line:col).
    EXPECT_EQ(it->second, SerializeComponentType(*BuiltinLibrary().FindComponent(name))) << name;
    ++types;
  }
  EXPECT_EQ(types, compiled.size());
  EXPECT_GT(types, 300u);  // the library's component types, MultiBody and the MSL's included
}

TEST(CompiledTypesTest, ATypeReadBackKeepsItsLocationsAndSharedExpressions) {
  const ComponentType* mass = BuiltinLibrary().FindComponent("Mass");
  ASSERT_NE(mass, nullptr);
  const ComponentType copy = DeserializeComponentType(SerializeComponentType(*mass));
  EXPECT_EQ(copy.name, mass->name);
  ASSERT_EQ(copy.equations.size(), mass->equations.size());
  for (size_t k = 0; k < copy.equations.size(); ++k) {
    EXPECT_EQ(copy.equations[k].text, mass->equations[k].text);
    EXPECT_EQ(copy.equations[k].loc.ToString(), mass->equations[k].loc.ToString());
    EXPECT_EQ(AstToString(*copy.equations[k].ast.rhs), AstToString(*mass->equations[k].ast.rhs));
  }
  EXPECT_EQ(copy.loc.ToString(), mass->loc.ToString());
  EXPECT_NE(copy.loc.ToString().find("components/"), std::string::npos);

  // Two fields that point to one expression still do after the round trip.
  ComponentType shared;
  shared.name = "Shared";
  const AstPtr one = MakeAst(Ast::Kind::kNumber, 0, "", {});
  shared.parameters.resize(2);
  shared.parameters[0].value = one;
  shared.parameters[1].value = one;
  const ComponentType back = DeserializeComponentType(SerializeComponentType(shared));
  EXPECT_EQ(back.parameters[0].value, back.parameters[1].value);
}

TEST(CompiledTypesTest, BytesCutShortAreRefused) {
  const std::string bytes = SerializeComponentType(*BuiltinLibrary().FindComponent("SpringDamper"));
  for (const size_t keep : {size_t{0}, size_t{3}, bytes.size() / 2, bytes.size() - 1}) {
    try {
      DeserializeComponentType(bytes.substr(0, keep));
      ADD_FAILURE() << "read " << keep << " of " << bytes.size() << " bytes";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "compiled type: the bytes end early");
    }
  }
  EXPECT_THROW(DeserializeComponentType(bytes + "x"), std::runtime_error);
}

TEST(CompiledTypesTest, TypesCompiledFromOtherLibraryTextAreNotUsed) {
  CompiledLibraryTypes other = CompiledBuiltinTypes();
  other.library_hash ^= 1;
  EXPECT_FALSE(UseCompiledLibraryTypes(other));
  other = CompiledBuiltinTypes();
  other.entries -= 1;
  EXPECT_FALSE(UseCompiledLibraryTypes(other));
}

}  // namespace
}  // namespace momenta
